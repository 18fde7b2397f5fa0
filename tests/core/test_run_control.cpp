// SPDX-License-Identifier: MIT
//
// Stopping a run from outside (run_control.hpp, docs/output.md "Ctrl-C"): a stop requested
// during step k ends cycle/solveTime right after step k (every phase of it done), a stop that is
// already pending when a run call starts takes no step at all, and the model keeps going once
// the request is cleared. Exact step counts: nothing here is approximate.
#include <catch2/catch.hpp>

#include "talus/errors.hpp"
#include "talus/run_control.hpp"
#include "test_support.hpp"

using namespace talus;
using namespace talus::test;

namespace {

std::unique_ptr<Model> fallingBall() {
    ModelDef def;
    def.gravity = Vec2(0.0, -9.81);
    auto m = std::make_unique<Model>(def);
    m->setDefaultContactModel("linear", linearProps(1e6, 1e6));
    m->timestep().automatic = false;
    m->timestep().fixed = 1e-3;
    m->createBall(ballAt(Vec2(0.0, 10.0), 0.1, 2600.0, Vec2(0.0, 0.0)));
    return m;
}

/// Clears the process-wide flag whatever a test does (the next test starts clean).
struct ClearStop {
    ClearStop() { clearStopRequest(); }
    ~ClearStop() { clearStopRequest(); }
};

}  // namespace

TEST_CASE("a stop requested during a step ends the run after that step") {
    ClearStop guard;
    auto m = fallingBall();
    // The hook runs in the bookkeeping phase of step 7: as a signal arriving mid-step.
    m->addCycleHook(1, [](Model& model) {
        if (model.step() == 7) requestStop();
    });
    bool caught = false;
    try {
        m->cycle(100);
    } catch (const Interrupted& e) {
        caught = true;
        CHECK_FALSE(e.beforeStart());
        CHECK(std::string(e.what()).find("interrupted (Ctrl-C) at step 7") != std::string::npos);
    }
    CHECK(caught);
    CHECK(m->step() == 7);
    // The step is whole: time advanced by exactly 7 fixed steps.
    CHECK(m->time() == Approx(7e-3).epsilon(1e-12));
}

TEST_CASE("a pending stop takes no step; cleared, the run goes on") {
    ClearStop guard;
    auto m = fallingBall();
    m->cycle(3);
    requestStop();
    CHECK_THROWS_AS(m->cycle(10), Interrupted);
    CHECK(m->step() == 3);
    try {
        m->solveTime(0.5);
        FAIL("solveTime ran with a stop pending");
    } catch (const Interrupted& e) {
        CHECK(e.beforeStart());
        CHECK(std::string(e.what()).find("before step 4") != std::string::npos);
    }
    CHECK(m->step() == 3);
    clearStopRequest();
    m->cycle(10);
    CHECK(m->step() == 13);
}

TEST_CASE("solveTime stops at a step end too, and the step observer sees every step") {
    ClearStop guard;
    auto m = fallingBall();
    int64_t seen = 0;
    m->setStepObserver([&seen](const Model& model) {
        ++seen;
        if (model.step() == 20) requestStop();
    });
    CHECK_THROWS_AS(m->solveTime(1.0), Interrupted);
    CHECK(m->step() == 20);
    CHECK(seen == 20);
    m->setStepObserver(nullptr);
}
