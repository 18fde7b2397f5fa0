// SPDX-License-Identifier: MIT
//
// SaveRestore through the ABI, with the shipped `linear` model: a contact saved in mid-impact and
// restored into a fresh clone must continue bit for bit like the contact that was not saved
// (docs/plugin-abi.md, "SaveRestore"); a save whose value types do not match what the model
// reads must stop with an error, not restore garbage.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "talus/contact_model.hpp"
#include "talus/errors.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/save_object.hpp"

using namespace talus;
using Catch::Matchers::Contains;

namespace {

/// Storage for one per-contact object, as the host's pools provide it.
struct Slot {
    std::vector<std::max_align_t> words;
    explicit Slot(std::size_t bytes)
        : words((bytes + sizeof(std::max_align_t) - 1) / sizeof(std::max_align_t)) {}
    void* data() { return words.data(); }
};

/// Owns a per-contact object made by Clone and destroys it in place.
struct Contact {
    Slot slot;
    ContactModel* model = nullptr;
    FdBlock fd{};  // carries the forces from step to step, as the host's pair does
    Contact(const ContactModel& proto, const PropBlock& pb) : slot(proto.ObjectSize()) {
        model = proto.Clone(pb, slot.data());
        REQUIRE(model != nullptr);
        fd.size = sizeof(FdBlock);
        fd.version = TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR;
    }
    ~Contact() {
        if (model) model->Destroy();
    }
    Contact(const Contact&) = delete;
    Contact& operator=(const Contact&) = delete;
};

PropBlock propBlock() {
    PropBlock pb{};
    pb.size = sizeof(PropBlock);
    pb.version = TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR;
    pb.end2_type = kEndWall;
    for (int i = 0; i < 2; ++i) pb.kn[i] = pb.ks[i] = pb.fric[i] = std::nan("");
    pb.radius[0] = 0.1;
    pb.mass[0] = 2.0;
    pb.mass_eff = 2.0;
    return pb;
}

/// The kinematics of step i of a prescribed impact: overlap up and down, shear that slides.
void drive(FdBlock& fd, int i, bool energy) {
    const double dt = 1e-5;
    auto overlap = [&](int k) { return 1e-4 * std::sin(0.05 * k) - 2e-6; };
    auto shear = [&](int k) { return 3e-5 * k * dt / 1e-3 + 1e-6 * std::cos(0.3 * k); };
    fd.flags = (i == 0 ? kFdFirstCall : 0u) | (energy ? kFdEnergyOn : 0u);
    fd.status = 0;
    fd.error = nullptr;
    fd.tdel = dt;
    fd.time = i * dt;
    fd.u_n = overlap(i);
    fd.du_n = overlap(i) - overlap(i - 1);
    fd.du_s = shear(i) - shear(i - 1);
    fd.u_dot_n = fd.du_n / dt;
    fd.u_dot_s = fd.du_s / dt;
    fd.t_dot_rel = 0.0;
    fd.dtheta = 0.0;
    fd.mass_eff = 2.0;
    fd.knest = fd.ksest = fd.krest = 0.0;
    for (double& e : fd.energy) e = 0.0;
}

void step(Contact& c, int i) {
    drive(c.fd, i, true);
    c.model->FDlaw(c.fd);
    REQUIRE(c.fd.status == 0);
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Every output of the two blocks and every property of the two objects, bit for bit.
void requireIdentical(const Contact& a, const Contact& b) {
    CHECK(sameBits(a.fd.n_force, b.fd.n_force));
    CHECK(sameBits(a.fd.s_force, b.fd.s_force));
    CHECK(sameBits(a.fd.moment, b.fd.moment));
    CHECK(sameBits(a.fd.knest, b.fd.knest));
    CHECK(sameBits(a.fd.ksest, b.fd.ksest));
    CHECK(a.fd.flags == b.fd.flags);
    for (int k = 0; k < kEnergyCount; ++k) CHECK(sameBits(a.fd.energy[k], b.fd.energy[k]));
    for (int32_t p = 0; p < a.model->PropCount(); ++p) {
        INFO(a.model->PropInfoAt(p)->name);
        CHECK(sameBits(a.model->ReturnProp(p), b.model->ReturnProp(p)));
    }
}

std::vector<uint8_t> save(ContactModel& m) {
    BinarySaveObject so(m.Version());
    m.SaveRestore(so);
    return so.bytes();
}

struct Linear {
    PluginRegistry reg;
    const ModelFactory* factory = nullptr;
    PluginRegistry::PrototypePtr proto;
    PropBlock pb = propBlock();
    Linear() {
        reg.load(LINEAR_PLUGIN);
        factory = &reg.find("linear");
        proto = reg.createPrototype(*factory);
        const std::pair<const char*, double> props[] = {
            {"kn", 1e7}, {"ks", 6e6}, {"fric", 0.3}, {"dp_nratio", 0.3}, {"dp_sratio", 0.2}};
        for (const auto& [name, value] : props) {
            int32_t idx = -1;
            for (int32_t i = 0; i < proto->PropCount(); ++i)
                if (std::string(proto->PropInfoAt(i)->name) == name) idx = i;
            REQUIRE(idx >= 0);
            REQUIRE(proto->AcceptProp(idx, value) == 0);
        }
        REQUIRE(proto->PreCycle(pb) == nullptr);
    }
};

}  // namespace

TEST_CASE("linear: a contact restored mid-impact continues bit for bit", "[abi][save]") {
    Linear lin;
    const int save_at = GENERATE(1, 17, 40, 70);  // before, during and after sliding/separation
    const int total = 140;

    Contact straight(*lin.proto, lin.pb);
    for (int i = 0; i < save_at; ++i) step(straight, i);
    const std::vector<uint8_t> bytes = save(*straight.model);
    CHECK_FALSE(bytes.empty());

    // A fresh clone, restored from the bytes; the host restores its own copy of the forces.
    Contact restored(*lin.proto, lin.pb);
    BinarySaveObject in(bytes, straight.model->Version());
    REQUIRE_FALSE(in.IsSaving());
    CHECK(in.DataVersion() == straight.model->Version());
    restored.model->SaveRestore(in);
    CHECK(in.atEnd());
    restored.fd = straight.fd;
    requireIdentical(straight, restored);

    for (int i = save_at; i < total; ++i) {
        step(straight, i);
        step(restored, i);
        INFO("step " << i);
        requireIdentical(straight, restored);
    }
    CHECK(save(*straight.model) == save(*restored.model));
}

TEST_CASE("linear: a save is the same whether taken once or after a restore", "[abi][save]") {
    Linear lin;
    Contact a(*lin.proto, lin.pb);
    for (int i = 0; i < 25; ++i) step(a, i);
    const std::vector<uint8_t> first = save(*a.model);
    Contact b(*lin.proto, lin.pb);
    BinarySaveObject in(first, a.model->Version());
    b.model->SaveRestore(in);
    CHECK(save(*b.model) == first);
}

TEST_CASE("linear: restoring a save with the wrong value types stops with a clear error",
          "[abi][save]") {
    Linear lin;
    Contact good(*lin.proto, lin.pb);
    for (int i = 0; i < 10; ++i) step(good, i);
    const std::vector<uint8_t> bytes = save(*good.model);

    auto restoreFrom = [&](const std::vector<uint8_t>& data) -> std::string {
        Contact fresh(*lin.proto, lin.pb);
        try {
            restoreContactModel(*fresh.model, data, good.model->Version());
        } catch (const InputError& e) {
            return e.what();
        }
        FAIL("restore accepted a save it cannot have written");
        return {};
    };

    SECTION("an int where the model reads a double") {
        BinarySaveObject bad(good.model->Version());
        int32_t i = 7;
        bad.Int(i);
        CHECK_THAT(restoreFrom(bad.bytes()),
                   Contains("expected a double but the save holds an int"));
    }
    SECTION("a double where the model reads its final bool") {
        // Same values, but the last one (the linear model's `touching` flag) written as a double.
        BinarySaveObject bad(good.model->Version());
        BinarySaveObject replay(bytes, good.model->Version());
        const int32_t doubles = static_cast<int32_t>((bytes.size() - 2) / 9);  // tag + 8 bytes
        for (int32_t k = 0; k < doubles; ++k) {
            double v = 0.0;
            replay.Double(v);
            bad.Double(v);
        }
        bool flag = false;
        replay.Bool(flag);
        REQUIRE(replay.atEnd());
        double as_double = flag ? 1.0 : 0.0;
        bad.Double(as_double);
        CHECK_THAT(restoreFrom(bad.bytes()),
                   Contains("expected a bool but the save holds a double"));
    }
    SECTION("a save that ends early") {
        std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + 9 * 3);
        CHECK_THAT(restoreFrom(cut), Contains("ended early"));
    }
}
