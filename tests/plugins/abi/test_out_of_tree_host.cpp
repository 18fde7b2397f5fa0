// SPDX-License-Identifier: MIT
//
// Host side of the out-of-tree test (out_of_tree.cmake): loads the `null` template model that
// was built as a separate project against an installed Talus, and checks that the engine can use
// it. The library's path comes in TALUS_OOT_PLUGIN; run without it, the program fails.
#include <stdlib.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "talus/contact_model.hpp"
#include "talus/errors.hpp"
#include "talus/model.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/save_object.hpp"

using namespace talus;

namespace {

std::string pluginPath() {
    const char* p = std::getenv("TALUS_OOT_PLUGIN");
    if (!p || !*p) FAIL("TALUS_OOT_PLUGIN is not set (this program is run by out_of_tree.cmake)");
    char* r = ::realpath(p, nullptr);
    REQUIRE(r != nullptr);
    std::string s(r);
    std::free(r);
    return s;
}

struct Loaded {
    PluginRegistry reg;
    std::string path = pluginPath();
    const ModelFactory* f = nullptr;
    Loaded() {
        REQUIRE(reg.load(path) == std::vector<std::string>{"null"});
        f = &reg.find("null");
    }
};

PropBlock propBlock() {
    PropBlock pb{};
    pb.size = sizeof(PropBlock);
    pb.version = TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR;
    pb.end2_type = kEndBall;
    for (int i = 0; i < 2; ++i) pb.kn[i] = pb.ks[i] = pb.fric[i] = std::nan("");
    pb.radius[0] = pb.radius[1] = 0.1;
    pb.mass[0] = pb.mass[1] = 1.0;
    pb.mass_eff = 0.5;
    return pb;
}

struct Slot {
    std::vector<std::max_align_t> words;
    explicit Slot(std::size_t bytes)
        : words((bytes + sizeof(std::max_align_t) - 1) / sizeof(std::max_align_t)) {}
};

}  // namespace

TEST_CASE("the out-of-tree null model loads with its identity", "[abi][oot]") {
    Loaded l;
    CHECK(l.f->name == "null");
    CHECK(l.f->library == l.path);  // the out-of-tree build, not the in-tree one
    CHECK(l.f->plugin_version == "1.0.0");
    REQUIRE(l.f->info != nullptr);
    CHECK(l.f->info->abi_major == TALUS_ABI_MAJOR);
    CHECK(l.f->info->abi_minor == TALUS_ABI_MINOR);
    CHECK(l.f->info->model_count == 1);
    CHECK(std::string(l.f->info->build_key) == TALUS_BUILD_KEY);
    CHECK(&l.reg.find("NULL") == l.f);
}

TEST_CASE("the out-of-tree null model describes its properties", "[abi][oot]") {
    Loaded l;
    auto proto = l.reg.createPrototype(*l.f);
    CHECK(std::string(proto->Name()) == "null");
    CHECK(std::string(proto->PropNames()) == "user,calls");
    REQUIRE(proto->PropCount() == 2);

    const PropInfo* user = proto->PropInfoAt(0);
    REQUIRE(user != nullptr);
    CHECK(std::string(user->name) == "user");
    CHECK(std::string(user->units) == "-");
    CHECK(user->flags == 0u);
    CHECK(user->default_value == 0.0);
    CHECK(std::strlen(user->description) > 0);

    const PropInfo* calls = proto->PropInfoAt(1);
    REQUIRE(calls != nullptr);
    CHECK(std::string(calls->name) == "calls");
    CHECK(calls->flags == (kPropReadOnly | kPropState));
    CHECK(proto->PropInfoAt(2) == nullptr);
    CHECK(proto->PropInfoAt(-1) == nullptr);

    CHECK(proto->AcceptProp(0, 2.5) == 0);
    CHECK(proto->ReturnProp(0) == 2.5);
    CHECK(proto->AcceptProp(1, 3.0) != 0);
    CHECK(std::string(proto->LastError()).find("read-only") != std::string::npos);
    CHECK(proto->AcceptProp(0, std::nan("")) != 0);
    CHECK(proto->PreCycle(propBlock()) == nullptr);
    CHECK(proto->Version() >= 1);
    CHECK(proto->KnEstimate() == 0.0);
    CHECK(proto->KsEstimate() == 0.0);
    CHECK(std::isinf(proto->ContactDuration(1.0, 5.0)));
    CHECK(proto->ActivityDistance() == 0.0);
    CHECK(proto->OKToDelete());
    CHECK((proto->Traits() & 1u) != 0);
}

TEST_CASE("the null model's FDlaw returns zeros and touches nothing else", "[abi][oot]") {
    Loaded l;
    auto proto = l.reg.createPrototype(*l.f);
    const PropBlock pb = propBlock();
    Slot a(proto->ObjectSize()), b(proto->ObjectSize());
    ContactModel* c1 = proto->Clone(pb, a.words.data());
    ContactModel* c2 = proto->Clone(pb, b.words.data());
    REQUIRE(c1 != nullptr);
    REQUIRE(c2 != nullptr);

    const bool energy = GENERATE(false, true);
    FdBlock fd;
    std::memset(&fd, 0x5a, sizeof fd);  // every byte set: untouched fields keep the pattern
    fd.size = sizeof(FdBlock);
    fd.version = TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR;
    fd.flags = kFdFirstCall | (energy ? kFdEnergyOn : 0u);
    fd.status = 0;
    fd.error = nullptr;
    fd.u_n = 1e-3;
    fd.u_dot_n = 2.0;
    fd.n_force = 123.0;  // previous forces: the null law replaces them with zero
    fd.s_force = -4.0;
    fd.moment = 0.5;
    FdBlock expect = fd;
    expect.n_force = expect.s_force = expect.moment = 0.0;
    expect.knest = expect.ksest = expect.krest = 0.0;
    if (energy) expect.energy[kEnergyStrain] = 0.0;

    c1->FDlaw(fd);
    CHECK(fd.status == 0);
    CHECK(fd.n_force == 0.0);
    CHECK(fd.s_force == 0.0);
    CHECK(fd.moment == 0.0);
    CHECK(fd.knest == 0.0);
    CHECK(fd.ksest == 0.0);
    CHECK(fd.krest == 0.0);
    CHECK(std::memcmp(&fd, &expect, sizeof fd) == 0);

    // per-contact state: each contact counts its own calls
    c1->FDlaw(fd);
    CHECK(c1->ReturnProp(1) == 2.0);
    CHECK(c2->ReturnProp(1) == 0.0);
    CHECK(proto->ReturnProp(1) == 0.0);

    // SaveRestore: a fresh clone restored from c1 reads back c1's state
    BinarySaveObject out(c1->Version());
    c1->SaveRestore(out);
    BinarySaveObject in(out.bytes(), c1->Version());
    c2->SaveRestore(in);
    CHECK(in.atEnd());
    CHECK(c2->ReturnProp(1) == 2.0);

    c1->Destroy();
    c2->Destroy();
}

TEST_CASE("a model using the out-of-tree null model: a ball falls through a wall", "[abi][oot]") {
    Loaded l;
    std::vector<std::string> warnings;
    auto scene = [&](Model& m, bool with_wall) {
        m.setWarningHandler([&](const std::string& w) { warnings.push_back(w); });
        if (with_wall) {
            WallDef w;
            w.points = {Vec2(-1.0, 0.0), Vec2(1.0, 0.0)};
            m.createWall(w);
        }
        BallDef b;
        b.pos = Vec2(0.0, 0.3);
        b.radius = 0.1;
        b.density = 2600.0;
        b.vel = Vec2(0.0, -2.0);
        m.timestep().max = 1e-3;  // automatic step, with a null model in the scene
        return m.createBall(b);
    };
    ModelDef def;
    def.gravity = Vec2(0.0, -9.81);
    Model m(def, l.reg);
    m.setDefaultContactModel("null", {{"user", 7.0}});
    const BallId ball = scene(m, true);
    Model ref(def, l.reg);  // the same ball in free fall, without a wall
    const BallId ref_ball = scene(ref, false);
    ref.setWarningHandler([](const std::string&) {});  // it has no contact model, on purpose

    int steps_in_contact = 0;
    for (int i = 0; i < 2000 && m.ballPos(ball).y() > -0.3; ++i) {
        m.cycle(1);
        ref.cycle(1);
        REQUIRE(m.lastTimestep() > 0.0);
        REQUIRE(std::isfinite(m.lastTimestep()));
        CHECK(m.ballForce(ball).norm() == 0.0);
        for (const ContactInfo& c : m.contacts()) {
            ++steps_in_contact;
            CHECK(c.model == "null");
            CHECK(c.normal_force == 0.0);
            CHECK(c.shear_force == 0.0);
            CHECK(m.contactProp(c.key, "user") == 7.0);
            CHECK(m.contactProp(c.key, "calls") >= 1.0);
        }
    }
    CHECK(steps_in_contact > 10);       // the contact existed while the ball crossed the wall
    CHECK(m.ballPos(ball).y() < -0.3);  // ... and the ball went through
    CHECK(m.wallForce(m.wallIds().front()).norm() == 0.0);
    // exactly the free fall of the ball without a wall (same steps, no force)
    CHECK(m.time() == Approx(ref.time()).epsilon(1e-12));
    CHECK(m.ballPos(ball).y() == Approx(ref.ballPos(ref_ball).y()).epsilon(1e-12));
    CHECK(m.ballVel(ball).y() == Approx(ref.ballVel(ref_ball).y()).epsilon(1e-12));
    // velocities are at the half step: v(t - dt/2) of the free fall
    CHECK(m.ballVel(ball).y() ==
          Approx(-2.0 - 9.81 * (m.time() - 0.5 * m.lastTimestep())).epsilon(1e-12));
    for (const auto& w : warnings) WARN(w);
    CHECK(warnings.empty());
}
