// SPDX-License-Identifier: MIT
//
// The stability guard (GuardSettings; core/src/force/contact_life.cpp endContact, law_of_motion
// non-finite check): a run that becomes non-finite stops with NumericalError naming the ball or
// contact and the step; an impact resolved in fewer than min_steps steps is reported (warning or
// error) naming the contact and its number of steps; a contact that gave back more energy than
// it took is reported; and the default automatic step gives no findings at all.
#include <algorithm>
#include <catch2/catch.hpp>

#include "test_support.hpp"

using namespace talus;
using namespace talus::test;

namespace {

constexpr double kR = 0.05, kRho = 2600.0, kKn = 1e7;

/// Ball above a floor moving down at v0 (no gravity); returns the ball id.
BallId dropScene(Model& m, double gap, double v0) {
    m.createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
    return m.createBall(ballAt(Vec2(0.0, kR + gap), kR, kRho, Vec2(0.0, -v0)));
}

/// Runs until the contact has ended; returns the number of steps with positive overlap.
int64_t runToSeparation(Model& m, BallId b) {
    int64_t loaded = 0;
    bool touched = false;
    for (int i = 0; i < 100000; ++i) {
        m.cycle(1);
        const bool over = m.ballPos(b).y() < kR;
        loaded += over;
        touched = touched || over;
        if (touched && m.contactCount() == 0) break;
    }
    return loaded;
}

}  // namespace

TEST_CASE("a run that becomes non-finite stops with NumericalError naming the ball and step",
          "[core][guard]") {
    // A stiff contact (ball created overlapping a wall by 1 mm, kn = 1e7) with an absurd fixed
    // step, 1e160 s: the first step computes the force, the second multiplies it by dt^2 / m
    // ~ 1e324 and the position overflows. Either the law of motion (ball) or the force loop
    // (contact, next to the ball) may be the one to notice; both name ball 1 and the step.
    auto m = makeModel(Vec2::Zero(), linearProps(kKn));
    const BallId b = dropScene(*m, -1e-3, 0.0);
    m->timestep() = fixedStep(1e160);
    m->cycle(1);
    CHECK(std::isfinite(m->ballPos(b).y()));
    try {
        m->cycle(5);
        FAIL("no NumericalError");
    } catch (const NumericalError& e) {
        const std::string what = e.what();
        INFO(what);
        CHECK(what.find("non-finite") != std::string::npos);
        CHECK(what.find("ball 1") != std::string::npos);
        // The model stays at the step that failed, and the message names it.
        CHECK(what.find("step " + std::to_string(m->step())) != std::string::npos);
        CHECK(m->step() <= 2);
    }
}

TEST_CASE("a contact law returning a non-finite force is named", "[core][guard]") {
    // kn near the largest double times an overlap > 1 m overflows to inf inside the model; the
    // engine must name the contact (ball, wall, segment, model) and the step. (The model's own
    // kn is bounded by its range check; a ball's inheritable kn reaches the law unchecked.)
    auto m = makeModel(Vec2::Zero(), linearProps(1e6));
    m->createWall(wallOf({Vec2(-100.0, 0.0), Vec2(100.0, 0.0)}));
    BallDef ball = ballAt(Vec2(0.0, 8.0), 10.0, kRho);
    ball.kn = 1e308;
    m->createBall(ball);
    try {
        m->cycle(1);
        FAIL("no NumericalError");
    } catch (const NumericalError& e) {
        const std::string what = e.what();
        INFO(what);
        CHECK(what.find("non-finite") != std::string::npos);
        CHECK(what.find("contact ball 1 - wall 1 segment 1") != std::string::npos);
        CHECK(what.find("'linear'") != std::string::npos);
        CHECK(what.find("step " + std::to_string(m->step())) != std::string::npos);
    }
}

TEST_CASE("an impact resolved in fewer than 10 steps gives one guard warning", "[core][guard]") {
    // Fixed step dt = T/5 (T = pi sqrt(m/k)): the contact lasts ~5 steps.
    auto m = makeModel(Vec2::Zero(), linearProps(kKn));
    WarningLog log;
    log.attach(*m);
    const BallId b = dropScene(*m, 0.003, 1.0);
    const double T = linearDuration(diskMass(kRho, kR), kKn);
    m->timestep() = fixedStep(T / 5.0);
    m->guard().energy = GuardAction::Off;  // this test is about resolution only
    const int64_t loaded = runToSeparation(*m, b);
    REQUIRE(loaded < 10);
    REQUIRE(log.texts.size() == 1);
    const std::string& w = log.texts.front();
    INFO(w);
    CHECK(w.find("guard: 1 contact(s) had fewer than 10 steps per contact duration") !=
          std::string::npos);
    CHECK(w.find("contact ball 1 - wall 1 segment 1 (model 'linear')") != std::string::npos);
    CHECK(w.find("lasted " + std::to_string(loaded) + " steps") != std::string::npos);
    // A min_steps of 3 accepts it.
    auto m2 = makeModel(Vec2::Zero(), linearProps(kKn));
    WarningLog log2;
    log2.attach(*m2);
    const BallId b2 = dropScene(*m2, 0.003, 1.0);
    m2->timestep() = fixedStep(T / 5.0);
    m2->guard().energy = GuardAction::Off;
    m2->guard().min_steps = 3;
    runToSeparation(*m2, b2);
    CHECK(log2.texts.empty());
}

TEST_CASE("guard resolution = Error throws NumericalError naming the contact", "[core][guard]") {
    auto m = makeModel(Vec2::Zero(), linearProps(kKn));
    WarningLog log;
    log.attach(*m);
    const BallId b = dropScene(*m, 0.003, 1.0);
    m->timestep() = fixedStep(linearDuration(diskMass(kRho, kR), kKn) / 5.0);
    m->guard().resolution = GuardAction::Error;
    m->guard().energy = GuardAction::Off;
    try {
        runToSeparation(*m, b);
        FAIL("no NumericalError");
    } catch (const NumericalError& e) {
        const std::string what = e.what();
        INFO(what);
        CHECK(what.find("impact under-resolved") != std::string::npos);
        CHECK(what.find("contact ball 1 - wall 1 segment 1") != std::string::npos);
        CHECK(what.find("at least 10 steps") != std::string::npos);
    }
}

// History: up to 9e13f47 the guard's contact work measured the first step's normal increment
// from the touch point and the last one only to overlap 0; for a linear spring that telescopes
// to W = 0 whatever the step, and this test failed (0 of 40 phases reported although 17 gained
// more than 1.2%, up to 8.3%). Since 41bdc07 the work is the last force times the mean of the
// half-step rates over the velocity window, what the law of motion actually did.
TEST_CASE("an under-resolved impact that creates energy is caught by the energy guard",
          "[core][guard]") {
    // At 5.5 steps per contact (dt = 0.57 sqrt(m/k), stable but under-resolved) the restitution
    // error ranges over several percent with the phase of touch (test_bounce.cpp: +-1.7% at 8.5
    // steps, growing like dt^2), i.e. energy errors of up to ~7%. The guard's tolerance is 1% of
    // the energy taken, so some phases must be reported (Warn) and throw (Error), every reported
    // one must really have e > 1, and every one with e^2 > 1.012 must be reported.
    const double T = linearDuration(diskMass(kRho, kR), kKn), dt = T / 5.5;
    int caught = 0, gained = 0;
    double worst_gain = 0.0;
    for (int i = 0; i < 40; ++i) {
        const double phase = (i + 0.5) / 40.0;
        auto m = makeModel(Vec2::Zero(), linearProps(kKn));
        WarningLog log;
        log.attach(*m);
        const BallId b = dropScene(*m, dt * (3.0 + phase), 1.0);
        m->timestep() = fixedStep(dt);
        m->guard().resolution = GuardAction::Off;
        runToSeparation(*m, b);
        m->cycle(1);
        const double e = m->ballVel(b).y() / 1.0;
        const bool warned = log.any("gave back more energy than they took");
        worst_gain = std::max(worst_gain, e * e - 1.0);
        if (e * e > 1.0 + 1.2e-2) ++gained;
        if (warned) {
            ++caught;
            INFO("phase " << phase << " e " << e << ": " << log.texts.front());
            CHECK(e > 1.0);
            CHECK(log.any("contact ball 1 - wall 1 segment 1"));
        }
        if (e * e > 1.0 + 1.2e-2) CHECK(warned);  // above tolerance (with 0.2% slack): caught
    }
    report(
        "energy guard at 5.5 steps per contact: %d of 40 phases reported, %d gained > 1.2%% "
        "(largest energy gain %.2f%%)\n",
        caught, gained, 100.0 * worst_gain);
    CHECK(caught > 0);

    // Error mode throws.
    bool threw = false;
    for (int i = 0; i < 40 && !threw; ++i) {
        auto m = makeModel(Vec2::Zero(), linearProps(kKn));
        const BallId b = dropScene(*m, dt * (3.0 + (i + 0.5) / 40.0), 1.0);
        m->timestep() = fixedStep(dt);
        m->guard().resolution = GuardAction::Off;
        m->guard().energy = GuardAction::Error;
        try {
            runToSeparation(*m, b);
        } catch (const NumericalError& e) {
            threw = true;
            CHECK(std::string(e.what()).find("energy created") != std::string::npos);
        }
    }
    CHECK(threw);
}

TEST_CASE("the default automatic step gives no guard findings", "[core][guard]") {
    // Resolved impacts (30 steps) with and without damping, ball-wall and ball-ball: no warning.
    Rng rng(8);
    for (double beta : {0.0, 0.3}) {
        for (int i = 0; i < 10; ++i) {
            auto m = makeModel(Vec2(0.0, -9.81), linearProps(kKn, kKn, 0.4, beta, beta));
            WarningLog log;
            log.attach(*m);
            m->createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
            m->createBall(ballAt(Vec2(0.0, kR + rng.uniform(0.05, 0.5)), kR, kRho, Vec2(0.7, 0.0)));
            m->createBall(ballAt(Vec2(0.02, 3.0 * kR + rng.uniform(0.6, 1.0)), kR, kRho));
            m->solveTime(1.5);
            INFO("beta " << beta << (log.texts.empty() ? "" : ": " + log.texts.front()));
            CHECK(log.texts.empty());
        }
    }
}

// In a pour at the default automatic step, grazing and chattering contacts are short by nature;
// the resolution check compares the step with each contact's own duration, not its life in steps
// (an earlier version counted the life and reported "lasted 3 steps" at the resolved step).
// Requirement: no resolution finding when every step met the resolution rule.
TEST_CASE("a pour at the default step gives no under-resolution findings", "[core][guard]") {
    ModelDef def;
    def.gravity = Vec2(0.0, -9.81);
    Model m(def);
    WarningLog log;
    log.attach(m);
    m.setDefaultContactModel("linear", linearProps(1e5, 5e4, 0.5, 0.2, 0.1, 0));
    m.createWall(wallOf({Vec2(0.0, 1.0), Vec2(0.0, 0.0), Vec2(0.4, 0.0), Vec2(0.4, 1.0)}));
    Rng rng(2024);
    for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 10; ++i)
            m.createBall(ballAt(Vec2(0.05 + 0.034 * i + rng.uniform(-0.003, 0.003),
                                     0.05 + 0.034 * j + rng.uniform(-0.003, 0.003)),
                                rng.uniform(0.008, 0.012), 2600.0,
                                Vec2(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5))));
    m.solveTime(0.4);
    INFO((log.texts.empty() ? std::string("no warning") : log.texts.front()));
    report("pour of 100 balls at the default step: %zu guard warning(s)\n", log.texts.size());
    CHECK(!log.any("lasted fewer than"));
}

TEST_CASE("a ball driven through a soft wall in one step stops the run naming the contact",
          "[core][guard]") {
    // 60 m/s against a wall of kn = 1e3 N/m with a fixed 1 ms step: the ball moves 0.6 radii
    // per step, so its centre crosses the wall line one step after touch while the contact still
    // pushes. Without the check the normal would flip and the wall would pull the ball through.
    auto m = makeModel(Vec2::Zero(), linearProps(1e3));
    m->createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
    m->createBall(ballAt(Vec2(0.0, kR + 0.01), kR, kRho, Vec2(0.0, -60.0)));
    m->timestep().automatic = false;
    m->timestep().fixed = 1e-3;
    m->setWarningHandler([](const std::string&) {});
    std::string what;
    try {
        m->cycle(10);
    } catch (const NumericalError& e) {
        what = e.what();
    }
    using Catch::Matchers::Contains;
    CHECK_THAT(what, Contains("passed through") && Contains("contact ball 1 - wall 1 segment 1") &&
                         Contains("(model 'linear')"));
    // At 0.2 m/s the deepest overlap is v sqrt(m/k) = 0.057 m < R: it bounces, no false alarm.
    auto slow = makeModel(Vec2::Zero(), linearProps(1e3));
    slow->createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
    slow->createBall(ballAt(Vec2(0.0, kR + 0.01), kR, kRho, Vec2(0.0, -0.2)));
    slow->setWarningHandler([](const std::string&) {});
    CHECK_NOTHROW(slow->solveTime(2.0));
}

namespace {

/// A 1 mm ball touching a wall for a step or two, as balls of a settled pack touch: it
/// approaches at 0.1 mm/s, and in the step it touches a load arrives that pulls it away (its
/// neighbours' push, modelled as an applied force of `pull` times what stops it within a step).
/// kn = 1e6 N/m, fixed step 1e-5 s (about 90 steps per contact duration); 40 phases of touch
/// spread over a step. `bystander`: a second ball far away moving at 2 m/s (0.016 J of kinetic
/// energy), as the rest of a pack holds energy. Returns the warnings of all phases and, with
/// the energy check at "error", how many phases threw.
struct Grazes {
    std::vector<std::string> texts;
    int thrown = 0;
    size_t count(const std::string& needle) const {
        return std::count_if(texts.begin(), texts.end(), [&](const std::string& t) {
            return t.find(needle) != std::string::npos;
        });
    }
};
Grazes grazes(double beta, double pull, bool bystander, GuardAction energy = GuardAction::Warn) {
    constexpr double kRg = 1e-3, kV = 1e-4, kDt = 1e-5;
    Grazes out;
    for (int i = 0; i < 40; ++i) {
        auto m = makeModel(Vec2::Zero(), linearProps(1e6, 1e6, 0.5, beta, beta));
        WarningLog log;
        log.attach(*m);
        m->timestep() = fixedStep(kDt);
        m->guard().energy = energy;
        m->createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
        const BallId b = m->createBall(ballAt(Vec2(0.0, kRg + kV * kDt * (3.0 + (i + 0.5) / 40.0)),
                                              kRg, kRho, Vec2(0.0, -kV)));
        if (bystander) m->createBall(ballAt(Vec2(0.5, 0.5), kRg, kRho, Vec2(2.0, 0.0)));
        for (int k = 0; k < 20 && m->contactCount() == 0; ++k) m->cycle(1);
        REQUIRE(m->contactCount() == 1);
        m->setBallAppliedForce(b, Vec2(0.0, pull * m->ballMass(b) * kV / kDt));
        try {
            m->cycle(20);
            REQUIRE(m->contactCount() == 0);
        } catch (const NumericalError& e) {
            CHECK(std::string(e.what()).find("energy created") != std::string::npos);
            ++out.thrown;
        }
        out.texts.insert(out.texts.end(), log.texts.begin(), log.texts.end());
    }
    return out;
}

}  // namespace

// History: until 2026-11-28 the stiffness check allowed a dashpot's force at the rate just after
// the deepest overlap only. A contact of a settled pack that touches for a step has its deepest
// overlap at that first step, where the force comes from the approach rate (and the onset
// corner): the dense pack at rest (50 000 balls, linear with dp_nratio) reported "7.2e6 N/m of
// overlap while it reported knest 1.5e6". Here every one of the 40 phases was reported at each
// dp_nratio (31 at 0.9).
TEST_CASE("a contact touching for one step in a pack is not taken for a stiffness lie",
          "[core][guard]") {
    for (double beta : {0.0, 0.2, 0.5, 0.9}) {
        const Grazes g = grazes(beta, 1.0, false);
        INFO("dp_nratio " << beta << (g.texts.empty() ? "" : ": " + g.texts.front()));
        CHECK(g.count("stiffer than their model reported") == 0);
    }
}

// History: until 2026-11-28 a contact's energy gain was judged against its own reference only.
// Grazing contacts of a settled pack gain a few 1e-12 J on references of a few 1e-11 J (the
// dense pack at rest: "gave back 1.6e-12 J more than it took", reference 3e-11 J), nothing on
// the scale of the pack. Here up to 11% of its reference, 4.4e-12 J, beside a ball holding
// 0.016 J: reported in 23 of 40 phases until then.
TEST_CASE("an energy gain far below the scene's energy is not reported; alone it is",
          "[core][guard]") {
    // The load pulls at twice what stops the ball: in some phases the contact gives back more
    // than 1% of the approach's kinetic energy, which is all the scene holds.
    const Grazes alone = grazes(0.5, 2.0, false);
    CHECK(alone.count("gave back more energy than they took") > 0);
    const Grazes beside = grazes(0.5, 2.0, true);
    INFO((beside.texts.empty() ? std::string("no warning") : beside.texts.front()));
    CHECK(beside.count("gave back more energy than they took") == 0);
    // With "error": thrown at the end of the step for the gain alone, never beside the ball.
    CHECK(grazes(0.5, 2.0, false, GuardAction::Error).thrown ==
          static_cast<int>(alone.count("gave back more energy than they took")));
    CHECK(grazes(0.5, 2.0, true, GuardAction::Error).thrown == 0);
}
