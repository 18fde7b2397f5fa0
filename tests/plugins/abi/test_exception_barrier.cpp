// SPDX-License-Identifier: MIT
//
// The exception barrier (docs/plugin-abi.md, "Exceptions"). A model's FDlaw that throws must
// become a PluginError naming the model and the contact, never a crash: a model built with
// ModelBase converts the exception into FdBlock::status/error itself; for a bare ContactModel
// the host has to catch what escapes.
#include <catch2/catch.hpp>
#include <string>

#include "talus/errors.hpp"
#include "talus/impact_rig.hpp"
#include "talus/model.hpp"
#include "talus/plugin_registry.hpp"

using namespace talus;
using Catch::Matchers::Contains;

namespace {

/// A ball 1 mm above a horizontal wall, falling onto it; the model is `model`.
struct Scene {
    Model m;
    BallId ball;
    Scene(PluginRegistry& reg, const std::string& model, const std::vector<PropValue>& props = {})
        : m(ModelDef{}, reg) {
        m.setWarningHandler([](const std::string&) {});
        m.setDefaultContactModel(model, props);
        WallDef w;
        w.points = {Vec2(-1.0, 0.0), Vec2(1.0, 0.0)};
        m.createWall(w);
        BallDef b;
        b.pos = Vec2(0.0, 0.101);
        b.radius = 0.1;
        b.density = 2600.0;
        b.vel = Vec2(0.0, -1.0);
        ball = m.createBall(b);
        m.timestep().automatic = false;
        m.timestep().fixed = 1e-4;
    }
};

}  // namespace

TEST_CASE("a ModelBase model that throws gives a PluginError naming model and contact",
          "[abi][exceptions]") {
    PluginRegistry reg;
    reg.load(THROWER_SDK);

    SECTION("std::exception: its text is kept") {
        Scene s(reg, "thrower_sdk");
        std::string msg;
        try {
            s.m.cycle(100);
            FAIL("the model did not throw");
        } catch (const PluginError& e) {
            msg = e.what();
        }
        CHECK_THAT(msg, Contains("contact model 'thrower_sdk' failed at step"));
        CHECK_THAT(msg, Contains("ball 1 - wall 1 segment 1"));
        CHECK_THAT(msg, Contains("thrower_sdk: deliberate failure at overlap"));
        // The run stopped at the failing step: the ball has reached the wall, not passed it.
        CHECK(s.m.ballPos(s.ball).y() < 0.1);
        CHECK(s.m.ballPos(s.ball).y() > 0.09);
        // and the model stays consistent: cycling again reports the same failure
        CHECK_THROWS_AS(s.m.cycle(1), PluginError);
    }
    SECTION("anything else: a generic text") {
        Scene s(reg, "thrower_sdk", {{"kind", 1.0}});
        CHECK_THROWS_WITH(s.m.cycle(100), Contains("thrower_sdk") &&
                                              Contains("ball 1 - wall 1 segment 1") &&
                                              Contains("unknown exception in FDlaw"));
    }
}

TEST_CASE("the rigs report a throwing model as a PluginError", "[abi][exceptions]") {
    PluginRegistry reg;
    reg.load(THROWER_SDK);
    SECTION("runImpact") {
        ImpactSetup setup;
        setup.model = "thrower_sdk";
        setup.guard.resolution = GuardAction::Off;
        CHECK_THROWS_AS(runImpact(setup, reg), PluginError);
        CHECK_THROWS_WITH(runImpact(setup, reg), Contains("contact model 'thrower_sdk'"));
    }
    SECTION("driveContact") {
        DriveSetup drive;
        drive.model = "thrower_sdk";
        drive.overlap = {-1e-4, 0.0, 1e-4, 2e-4};
        CHECK_THROWS_WITH(
            driveContact(drive, reg),
            Contains("model 'thrower_sdk' failed at sample 2") && Contains("deliberate failure"));
    }
}

TEST_CASE("a bare ContactModel that throws does not bring the host down", "[abi][exceptions]") {
    PluginRegistry reg;
    reg.load(THROWER_RAW);
    Scene s(reg, "thrower_raw");
    bool threw = false;
    try {
        s.m.cycle(100);
    } catch (const std::exception& e) {
        threw = true;
        CHECK_THAT(std::string(e.what()), Contains("thrower_raw"));
    }
    CHECK(threw);
    // The model can still be queried and destroyed (ASan checks the clean-up).
    CHECK(s.m.ballCount() == 1);
    CHECK(s.m.contactCount() == 1);
}

// The ABI promises more for a bare model (contact_model.hpp, "Exceptions"): the host catches what
// escapes FDlaw and reports it like a status error, naming the model and the contact.
TEST_CASE("a bare ContactModel that throws gives a PluginError naming model and contact",
          "[abi][exceptions]") {
    PluginRegistry reg;
    reg.load(THROWER_RAW);
    Scene s(reg, "thrower_raw");
    std::string msg;
    try {
        s.m.cycle(100);
    } catch (const PluginError& e) {
        msg = e.what();
    } catch (const std::exception&) {
        FAIL("the exception escaped the engine as a plain std::exception, not a PluginError");
    }
    CHECK_THAT(msg, Contains("contact model 'thrower_raw'"));
    CHECK_THAT(msg, Contains("ball 1 - wall 1 segment 1"));
    CHECK_THAT(msg, Contains("deliberate failure at overlap"));
}
