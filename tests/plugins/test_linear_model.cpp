// SPDX-License-Identifier: MIT
//
// The `linear` model's documented contract (docs/models/linear.md): property names, units and
// defaults, range errors, PFC inheritance, the time-step contract (knest raised for dashpots,
// ContactDuration), energies and SaveRestore. Its restitution, oblique and Chung & Ooi checks
// live with the engine tests (tests/core/test_restitution.cpp, test_oblique.cpp,
// test_chung_ooi.cpp), since the engine's dashpot scheme is tested through it.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "contact_law_support.hpp"

using namespace talus;
using namespace talus::lawtest;
using Catch::Matchers::Contains;

TEST_CASE("linear: property table as documented", "[linear][props]") {
    const ModelFactory& f = PluginRegistry::global().find("linear");
    const ContactModel& m = *f.reference;
    struct Row {
        const char* name;
        const char* units;
        double def;
        bool read_only;
    };
    const Row rows[] = {{"kn", "N/m", 0.0, false},      {"ks", "N/m", 0.0, false},
                        {"fric", "-", 0.0, false},      {"dp_nratio", "-", 0.0, false},
                        {"dp_sratio", "-", 0.0, false}, {"dp_mode", "-", 0.0, false},
                        {"lin_fn", "N", 0.0, true},     {"lin_fs", "N", 0.0, true},
                        {"dp_fn", "N", 0.0, true},      {"dp_fs", "N", 0.0, true},
                        {"lin_slip", "-", 0.0, true}};
    REQUIRE(m.PropCount() == static_cast<int32_t>(std::size(rows)));
    for (int32_t i = 0; i < m.PropCount(); ++i) {
        const PropInfo* p = m.PropInfoAt(i);
        INFO(rows[i].name);
        CHECK(std::string(p->name) == rows[i].name);
        CHECK(std::string(p->units) == rows[i].units);
        CHECK(p->default_value == rows[i].def);
        CHECK(((p->flags & kPropReadOnly) != 0) == rows[i].read_only);
    }
    CHECK(std::string(m.PropNames()) ==
          "kn,ks,fric,dp_nratio,dp_sratio,dp_mode,lin_fn,lin_fs,dp_fn,dp_fs,lin_slip");
}

TEST_CASE("linear: property errors", "[linear][props]") {
    CHECK_THAT(modelError("linear", {{"k_n", 1e8}}),
               Contains("unknown property 'k_n' for model 'linear'") && Contains("kn, ks, fric"));
    CHECK_THAT(modelError("linear", {{"kn", -1.0}}), Contains("'kn' must be >= 0 (got -1)"));
    CHECK_THAT(modelError("linear", {{"dp_nratio", 1.1}}),
               Contains("'dp_nratio' must be in [0, 1]"));
    CHECK_THAT(modelError("linear", {{"dp_mode", 1.5}}),
               Contains("'dp_mode' must be one of 0 = full, 1 = no_tension"));
    CHECK_THAT(modelError("linear", {{"lin_fn", 1.0}}), Contains("read-only"));
}

TEST_CASE("linear: kn and ks in series, fric the minimum, else the model's own",
          "[linear][props]") {
    LawDriver drv("linear", {{"kn", 5e7}, {"ks", 2e7}, {"fric", 0.7}}, true, 0.1, 0.1, 1.0);
    const ContactModel& proto = drv.prototype();
    std::vector<std::max_align_t> storage(proto.ObjectSize() / sizeof(std::max_align_t) + 1);
    PropBlock pb = drv.propBlock();
    pb.kn[0] = 1e8, pb.kn[1] = 3e8;  // series: 7.5e7
    pb.fric[1] = 0.4;                // one end: 0.4
    ContactModel* c = proto.Clone(pb, storage.data());
    REQUIRE(c);
    CHECK(c->ReturnProp(0) == Approx(7.5e7).epsilon(1e-15));
    CHECK(c->ReturnProp(1) == 2e7);  // no end defines ks: the model's own
    CHECK(c->ReturnProp(2) == 0.4);
    c->Destroy();
}

TEST_CASE("linear: time-step contract", "[linear][timestep]") {
    const double kn = 1e8, ks = 4e7, bn = 0.5, bs = 0.3, m = 20.0;
    LawDriver drv("linear", {{"kn", kn}, {"ks", ks}, {"dp_nratio", bn}, {"dp_sratio", bs}}, false,
                  0.1, 0.0, m);
    ContactModel* c = drv.clone();
    auto factor = [](double b) {
        const double f = std::sqrt(1.0 + b * b) - b;
        return 1.0 / (f * f);
    };
    CHECK(c->KnEstimate() == Approx(kn * factor(bn)).epsilon(1e-15));
    CHECK(c->KsEstimate() == Approx(ks * factor(bs)).epsilon(1e-15));
    // The half period of the faster spring: a disk's shear spring sees the inverse mass 3/m*,
    // so here (3 ks = 1.2 kn) it is the shear spring's (docs/models/linear.md).
    CHECK(c->ContactDuration(m, 3.0) == Approx(M_PI * std::sqrt(m / (3.0 * ks))).epsilon(1e-15));
    {
        LawDriver soft("linear", {{"kn", kn}, {"ks", 0.2 * kn}}, false, 0.1, 0.0, m);
        CHECK(soft.clone()->ContactDuration(m, 3.0) ==
              Approx(M_PI * std::sqrt(m / kn)).epsilon(1e-15));
    }
    FdBlock fd = drv.block(1e-4, 0.5, 0.1, 1e-5, nullptr);
    c->FDlaw(fd);
    CHECK(fd.knest == Approx(kn * factor(bn)).epsilon(1e-15));
    CHECK(fd.ksest == Approx(ks * factor(bs)).epsilon(1e-15));
}

TEST_CASE("linear: strain energy F^2/(2k) and the books of a damped impact", "[linear][energy]") {
    DriveSetup d;
    d.model = "linear";
    d.props = {{"kn", 1e8}, {"ks", 5e7}, {"fric", 10.0}};
    d.overlap = {1e-5, 2e-5};
    d.shear = {0.0, 1e-6};
    const DriveResult r = driveContact(d);
    CHECK(r.strain == Approx(0.5 * 1e8 * 4e-10 + 0.5 * 5e7 * 1e-12).epsilon(1e-12));

    ImpactSetup s;
    s.model = "linear";
    s.props = {{"kn", 1e8}, {"dp_nratio", 0.3}};
    s.normal_speed = 2.0;
    const ImpactResult ir = runImpact(s);
    CHECK(ir.energy.dashpot > 0.0);
    // The dashpot work equals the kinetic energy lost, to the scheme's accuracy.
    CHECK(ir.energy.dashpot ==
          Approx(ir.energy_in * (1.0 - ir.restitution * ir.restitution)).epsilon(2e-3));
}

TEST_CASE("linear: SaveRestore mid-contact continues bit for bit", "[linear][save]") {
    for (int mode : {0, 1, 3}) {
        LawDriver drv("linear",
                      {{"kn", 1e8},
                       {"ks", 5e7},
                       {"fric", 0.3},
                       {"dp_nratio", 0.2},
                       {"dp_sratio", 0.1},
                       {"dp_mode", static_cast<double>(mode)}},
                      false, 0.1, 0.0, 30.0);
        std::vector<double> u, us;
        for (int i = 1; i <= 120; ++i) {
            u.push_back(1e-4 * std::sin(M_PI * i / 100.0));
            us.push_back(2e-5 * std::sin(M_PI * i / 60.0));
        }
        int compared = 0;
        CHECK(saveRestoreContinuesExactly(drv, u, us, 1e-6, 40, &compared));
        CHECK(compared == 80);
    }
}
