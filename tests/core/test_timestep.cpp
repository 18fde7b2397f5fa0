// SPDX-License-Identifier: MIT
//
// The automatic time step (core/src/step/timestep.cpp): which rule governs in simple scenes, the
// stability rule's formula, and what the resolution and approach rules promise:
//  - free flight far from anything: kinematic (stay inside the broadphase fat box) or growth;
//  - an isolated impact: resolution, dt = duration / 30 with duration = pi sqrt(m*/knest);
//  - resolution = 0: stability, dt = safety sqrt(m / sum(knest + ksest)) (PFC's time step;
//    knest is raised by 1/(sqrt(1 + beta^2) - beta)^2 for a dashpot);
//  - fixed: the fixed step;
//  - an impact is resolved in >= 30 steps, and the step in which a contact starts is already the
//    resolved one, so the overlap at first touch is at most one resolution step's travel.
#include <catch2/catch.hpp>
#include <map>

#include "test_support.hpp"

using namespace talus;
using namespace talus::test;

namespace {

constexpr double kR = 0.05, kRho = 2600.0, kKn = 1e7;

double dashpotFactor(double beta) {
    const double f = std::sqrt(1.0 + beta * beta) - beta;
    return 1.0 / (f * f);
}

}  // namespace

TEST_CASE("free flight far from walls: kinematic or growth rule", "[core][timestep]") {
    auto m = makeModel(Vec2(0.0, -9.81), linearProps(kKn));
    m->createWall(wallOf({Vec2(-100.0, -100.0), Vec2(100.0, -100.0)}));
    const BallId b = m->createBall(ballAt(Vec2(0.0, 0.0), kR, kRho, Vec2(2.0, 3.0)));
    std::map<StepRule, int> seen;
    m->cycle(1);  // the first step has no previous step to grow from
    for (int i = 0; i < 500; ++i) {
        m->cycle(1);
        ++seen[m->lastStepRule()];
    }
    report("free flight rules over 500 steps: kinematic %d, growth %d, other %d\n",
           seen[StepRule::Kinematic], seen[StepRule::Growth],
           500 - seen[StepRule::Kinematic] - seen[StepRule::Growth]);
    CHECK((seen[StepRule::Kinematic] + seen[StepRule::Growth]) == 500);
    CHECK(seen[StepRule::Kinematic] > 0);
    const std::string why = m->lastStepReason();
    CHECK((why.find("kinematic") != std::string::npos || why.find("growth") != std::string::npos));
    CHECK(m->ballPos(b).y() > -50.0);  // it never came near the wall
}

TEST_CASE("an isolated impact is governed by the resolution rule", "[core][timestep]") {
    for (double beta : {0.0, 0.3}) {
        auto m = makeModel(Vec2::Zero(), linearProps(kKn, 0.0, 0.0, beta));
        m->createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
        const BallId b = m->createBall(ballAt(Vec2(0.0, kR + 0.01), kR, kRho, Vec2(0.0, -1.0)));
        const double mass = m->ballMass(b);
        // Duration the rule assumes: pi sqrt(m/knest), knest raised for the dashpot; / 30.
        const double dt_res = M_PI * std::sqrt(mass / (kKn * dashpotFactor(beta))) / 30.0;
        std::map<StepRule, int> in_contact;
        int64_t contact_steps = 0;
        bool was_in = false;
        for (int i = 0; i < 5000; ++i) {
            m->cycle(1);
            const bool in = m->contactCount() > 0;
            if (in && was_in) {  // the step that found the contact was chosen before it existed
                ++in_contact[m->lastStepRule()];
                CHECK(m->lastTimestep() == Approx(dt_res).epsilon(1e-12));
                ++contact_steps;
            }
            if (was_in && !in) break;
            was_in = in;
        }
        INFO("beta " << beta);
        CHECK(contact_steps >= 29);
        CHECK(in_contact[StepRule::Resolution] == contact_steps);
    }
}

TEST_CASE("resolution = 0: the stability rule, safety * sqrt(m / sum(kn + ks))",
          "[core][timestep]") {
    // A ball at rest on a flat wall (one contact) and in a V corner (two contacts), with a
    // dashpot so that knest != kn. ks = kn / 2 keeps rotation from governing: the rotational
    // limit sqrt(I / (ksest d^2)) = sqrt(m / (2 ksest)) (I = m R^2 / 2, d ~ R) is larger than
    // sqrt(m / (knest + ksest)) when knest > ksest. The balls are settled first (local damping)
    // so that the contacts are stable and persistent.
    const double beta = 0.2;
    struct Scene {
        const char* name;
        std::vector<Vec2> wall;
        double y0;
        int contacts;
    };
    for (const Scene& sc : {Scene{"flat", {Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}, kR - 2.5e-5, 1},
                            Scene{"V corner",
                                  {Vec2(-1.0, 1.0), Vec2(0.0, 0.0), Vec2(1.0, 1.0)},
                                  kR * std::sqrt(2.0) - 2e-5,
                                  2}}) {
        auto m = makeModel(Vec2(0.0, -9.81), linearProps(kKn, 0.5 * kKn, 0.5, beta, beta));
        m->createWall(wallOf(sc.wall));
        const BallId b = m->createBall(ballAt(Vec2(0.0, sc.y0), kR, kRho));
        m->timestep().resolution = 0.0;
        m->damping().local = 0.7;
        m->cycle(3000);
        REQUIRE(m->contactCount() == static_cast<std::size_t>(sc.contacts));
        m->cycle(1);
        const double k = sc.contacts * (kKn + 0.5 * kKn) * dashpotFactor(beta);
        const double expect = 0.8 * std::sqrt(m->ballMass(b) / k);
        INFO(sc.name << ": " << m->lastStepReason());
        CHECK(m->lastStepRule() == StepRule::Stability);
        CHECK(m->lastTimestep() == Approx(expect).epsilon(1e-12));
        CHECK(m->lastStepReason().find("stability") != std::string::npos);
        CHECK(m->lastStepReason().find("ball 1") != std::string::npos);
        // The safety factor scales it.
        m->timestep().safety = 0.4;
        m->cycle(1);
        CHECK(m->lastTimestep() == Approx(0.5 * expect).epsilon(1e-12));
    }
}

TEST_CASE("a fixed step is the fixed step", "[core][timestep]") {
    auto m = makeModel(Vec2(0.0, -9.81), linearProps(kKn));
    m->createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
    m->createBall(ballAt(Vec2(0.0, kR + 0.01), kR, kRho));
    m->timestep() = fixedStep(3.3e-5);
    for (int i = 0; i < 2000; ++i) {
        m->cycle(1);
        REQUIRE(m->lastStepRule() == StepRule::Fixed);
        REQUIRE(m->lastTimestep() == 3.3e-5);
    }
    CHECK(m->time() == Approx(2000 * 3.3e-5).epsilon(1e-12));
    m->timestep().fixed = 0.0;
    CHECK_THROWS_AS(m->cycle(1), InputError);
}

TEST_CASE("an isolated impact at the default step is resolved in 30 steps", "[core][timestep]") {
    // dt = duration / 30 exactly (resolution rule), so the contact spans 30 steps; the number of
    // steps with positive overlap is 30, or 29 when touch falls within the last ~1.4% of a
    // step (the discrete contact is shorter than pi sqrt(m/k) by (omega dt)^2 / 24 = 4.6e-4).
    // So: duration / dt >= 30 (1 - 1e-3), and at least 29 loaded steps.
    Rng rng(31);
    int n30 = 0, n = 0;
    double worst_ratio = 1e9;
    for (double beta : {0.0, 0.2, 0.5}) {
        for (int i = 0; i < 40; ++i) {
            ImpactSetup s;
            s.props = linearProps(kKn, 0.0, 0.0, beta);
            s.radius = kR;
            s.density = kRho;
            s.normal_speed = 1.5;
            s.gap = 1.5 * linearDuration(diskMass(kRho, kR), kKn) / 30.0 * rng.uniform(1.0, 60.0);
            const ImpactResult r = runImpact(s);
            REQUIRE(r.separated);
            const double ratio = r.duration / r.timestep;
            worst_ratio = std::min(worst_ratio, ratio);
            INFO("beta " << beta << " duration/dt " << ratio << " steps " << r.steps_in_contact);
            CHECK(ratio >= 30.0 * (1.0 - 1e-3));
            CHECK(r.steps_in_contact >= 29);
            n30 += r.steps_in_contact >= 30;
            ++n;
        }
    }
    report("impacts at the default step: %d of %d with >= 30 loaded steps, min duration/dt %.4f\n",
           n30, n, worst_ratio);
}

TEST_CASE("after a long free flight the first contact step is the resolved one",
          "[core][timestep]") {
    // A ball dropped from heights of 0.5 .. 20 m: free flight takes large kinematic/growth steps,
    // then the approach rule must bring the step down before touch, so the overlap at the first
    // loaded step is at most one resolution step's travel v_impact * dt_res (times 1 + 1e-9).
    Rng rng(5);
    const double g = 9.81;
    for (int i = 0; i < 20; ++i) {
        const double h = rng.uniform(0.5, 20.0);
        auto m = makeModel(Vec2(0.0, -g), linearProps(kKn));
        m->createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
        const BallId b = m->createBall(ballAt(Vec2(0.0, kR + h), kR, kRho));
        const double dt_res = linearDuration(m->ballMass(b), kKn) / 30.0;
        double biggest_flight_step = 0.0, overlap = 0.0;
        while (m->step() < 1000000) {
            const double v = -m->ballVel(b).y();
            m->cycle(1);
            overlap = kR - m->ballPos(b).y();
            if (overlap > 0.0) {
                const double v_max = v + g * m->lastTimestep();
                INFO("h " << h << ": first overlap " << overlap << ", v dt_res " << v_max * dt_res
                          << ", step " << m->lastTimestep());
                CHECK(overlap <= v_max * dt_res * (1.0 + 1e-9));
                CHECK(m->lastTimestep() <= dt_res * (1.0 + 1e-12));
                break;
            }
            biggest_flight_step = std::max(biggest_flight_step, m->lastTimestep());
        }
        CHECK(biggest_flight_step > 10.0 * dt_res);  // the flight did take large steps
    }
}

TEST_CASE("a ball released at rest on or near a floor does not start with a deep overlap",
          "[core][timestep]") {
    // Same promise from the very first step: a ball at rest at gap g0 <= 1 mm above a floor
    // (g0 = 0: placed exactly on it, the most common set-up). The first loaded step may overlap
    // by at most the resolution step's travel, (v_touch + g dt_res) dt_res, v_touch =
    // sqrt(2 g g0). And an undamped ball released at rest must never rise above its release
    // height by more than the O(dt^2) energy error of a few bounces (bound: 1% of the radius).
    // The approach rule bounds the closing distance with the relative acceleration
    // (core/src/step/timestep.cpp, Model::noteApproach), so it covers a body at rest on the very
    // first step too; an earlier version used |v_rel| + accel * m_dt with m_dt = 0 there and let
    // the kinematic rule alone set that step (measured: 2.5 mm sinking, then a 5.6 m launch).
    const double g = 9.81;
    for (double gap : {0.0, 1e-6, 1e-4, 1e-3}) {
        auto m = makeModel(Vec2(0.0, -g), linearProps(kKn));
        m->setWarningHandler([](const std::string&) {});
        m->createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
        const BallId b = m->createBall(ballAt(Vec2(0.0, kR + gap), kR, kRho));
        const double dt_res = linearDuration(m->ballMass(b), kKn) / 30.0;
        const double travel = (std::sqrt(2.0 * g * gap) + g * dt_res) * dt_res;
        double first = -1.0, highest = -1e9, first_step = 0.0;
        for (int i = 0; i < 3000; ++i) {
            m->cycle(1);
            if (i == 0) first_step = m->lastTimestep();
            const double y = m->ballPos(b).y();
            if (first < 0.0 && kR - y > 0.0) first = kR - y;
            highest = std::max(highest, y - (kR + gap));
        }
        report(
            "released at rest %.0e m above the floor: first step %.3g s (dt_res %.3g s), first "
            "overlap %.3e m (allowed %.3e), highest rise above release %.3e m\n",
            gap, first_step, dt_res, first, travel, highest);
        INFO("gap " << gap << ": first overlap " << first << " allowed " << travel
                    << ", rise above release " << highest);
        CHECK(first <= travel * (1.0 + 1e-9));
        CHECK(highest <= 0.01 * kR);
    }
}

TEST_CASE("an idle scene keeps a bounded step, and what starts after it is exact",
          "[core][timestep]") {
    // Nothing moves, nothing accelerates, no gravity: the growth rule used to
    // double the step every cycle (6e26 s after 100 cycles, t = inf at 1034), and the first step
    // after gravity, a force or a velocity appeared carried half of that idle step in its
    // velocity update (1e27 m/s). Now: a lone ball (no pair gives a time scale) takes the
    // documented 1 ms, kept while idle; the step after an idle one restarts the integrator, so
    // free flight from the change on is the closed form to round-off (1e-12 m over 1 m).
    for (const char* what : {"gravity", "fapp", "vel"}) {
        auto m = makeModel(Vec2::Zero(), linearProps(kKn));
        const BallId b = m->createBall(ballAt(Vec2(0.0, 0.0), kR, kRho));
        m->cycle(2000);
        INFO(what << ": " << m->lastStepReason());
        CHECK(m->lastStepRule() == StepRule::Idle);
        CHECK(m->lastTimestep() == 1e-3);
        CHECK(m->time() == Approx(2.0).epsilon(1e-12));
        Vec2 a(0.0, 0.0), v0(0.0, 0.0);
        if (what == std::string("gravity")) {
            m->gravity() = a = Vec2(0.0, -9.81);
        } else if (what == std::string("fapp")) {
            m->setBallAppliedForce(b, Vec2(3.0, -4.0));
            a = Vec2(3.0, -4.0) / m->ballMass(b);
        } else {
            m->setBallVel(b, v0 = Vec2(0.5, -1.0));
        }
        const double t0 = m->time();
        for (int i = 0; i < 200; ++i) {
            m->cycle(1);
            const double t = m->time() - t0;
            const Vec2 expect = v0 * t + 0.5 * a * t * t;
            REQUIRE((m->ballPos(b) - expect).norm() <= 1e-12 * std::max(1.0, expect.norm()));
            REQUIRE(m->lastStepRule() != StepRule::Idle);
        }
    }
}

TEST_CASE("the idle step near a wall is the step its contact would need", "[core][timestep]") {
    // A ball at rest 1 mm above a floor, no gravity: the pair is a broadphase candidate, so the
    // idle step is the limit the approach rule would give it, duration / 30 with duration
    // pi sqrt(m/kn) (resolution rule; safety * sqrt(m/kn) = 0.8 sqrt(m/kn) is larger).
    auto m = makeModel(Vec2::Zero(), linearProps(kKn));
    m->createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
    const BallId b = m->createBall(ballAt(Vec2(0.0, kR + 1e-3), kR, kRho));
    m->cycle(100);
    CHECK(m->lastStepRule() == StepRule::Idle);
    CHECK(m->lastTimestep() == Approx(linearDuration(m->ballMass(b), kKn) / 30.0).epsilon(1e-12));
    CHECK(m->lastStepReason().find("ball 1 - wall 1") != std::string::npos);
}

TEST_CASE("a Hertz or ng ball released at rest on a floor sinks to the static overlap only",
          "[core][timestep]") {
    // A law with no stiffness at zero overlap has an infinite contact duration
    // at zero approach speed, so the approach rule did not limit the first step of a ball
    // released at rest (0.032 s: 4-5 mm into the floor, then 21 m/s upwards). The approach rule
    // now uses the speed the ball will have in the contact (timestep.cpp, approachDuration).
    // Closed form, F = K u^1.5 undamped (energy): the deepest overlap solves
    // m g (gap + u) = (2/5) K u^2.5; for gap = 0, u_max = (5/2 m g / K)^(2/3). Bound: u_max
    // + 2% (the discrete contact's energy error at >= 19 steps per oscillation is ~1e-3, which
    // moves u_max by less than that). The first step is the resolved one: at most
    // duration/30 of the quasi-static oscillation, D = 3.2145 (m^2/(R E*^2 v))^(1/5) at
    // v = g D / pi (hertz.md), measured 0.000467 s.
    const double g = 9.81, R = 0.1, rho = 1000.0, G = 1e8, nu = 0.3;
    struct Law {
        const char* name;
        std::vector<PropValue> props;
        double E;  // F = (4/3) E sqrt(R) u^1.5 against a wall
    };
    for (const Law& law : {Law{"hertz", {{"hz_shear", G}, {"hz_poiss", nu}}, 2.0 * G / (1.0 - nu)},
                           Law{"ng", {{"ng_shear", G}, {"ng_poiss", nu}}, G / (1.0 - nu)}}) {
        for (double gap : {0.0, 1e-6}) {
            ModelDef def;
            def.gravity = Vec2(0.0, -g);
            Model m(def);
            m.setDefaultContactModel(law.name, law.props);
            m.createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
            const BallId b = m.createBall(ballAt(Vec2(0.0, R + gap), R, rho));
            const double mass = m.ballMass(b);
            const double K = 4.0 / 3.0 * law.E * std::sqrt(R);
            // deepest overlap: bisection on m g (gap + u) = (2/5) K u^2.5
            double lo = 0.0, hi = 1e-2;
            for (int k = 0; k < 200; ++k) {
                const double u = 0.5 * (lo + hi);
                (mass * g * (gap + u) > 0.4 * K * std::pow(u, 2.5) ? lo : hi) = u;
            }
            const double u_max = lo;
            double deepest = 0.0, first_step = 0.0;
            for (int i = 0; i < 400; ++i) {  // about 7 oscillations
                m.cycle(1);
                if (i == 0) first_step = m.lastTimestep();
                deepest = std::max(deepest, R - m.ballPos(b).y());
            }
            report(
                "%s released at rest %.0e m above a floor: first step %.3g s, deepest overlap "
                "%.4e m (closed form %.4e m)\n",
                law.name, gap, first_step, deepest, u_max);
            INFO(law.name << " gap " << gap << ": deepest " << deepest << " closed form " << u_max
                          << ", first step " << first_step);
            CHECK(deepest <= 1.02 * u_max);
            CHECK(deepest >= 0.98 * u_max);  // and it does settle onto the floor
            CHECK(first_step < 1e-3);        // the defect: 0.032 s
        }
    }
}

TEST_CASE("a contact bonded as it touches gets the resolution rule", "[core][timestep]") {
    // docs/models/cbond.md, "Time-step contract": bonded contacts got the
    // stability rule only, so a ball bonding to a wall at 2 m/s took 4-5 steps (the step grew
    // 2x per step through the impact). Every step while bonded must be the resolved one.
    auto m = std::make_unique<Model>(ModelDef{});
    m->setDefaultContactModel("cbond", {{"kn", kKn},
                                        {"ks", 0.5 * kKn},
                                        {"fric", 0.5},
                                        {"cb_bond", 1.0},
                                        {"cb_tenf", 1e30},
                                        {"cb_shearf", 1e30},
                                        {"cb_gap", 1e-9}});
    m->createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
    const BallId b = m->createBall(ballAt(Vec2(0.0, kR + 0.002), kR, kRho, Vec2(0.3, -2.0)));
    const double dt_res = linearDuration(m->ballMass(b), kKn) / 30.0;
    int bonded_steps = 0;
    bool was = false;
    for (int i = 0; i < 300; ++i) {
        m->cycle(1);
        const bool in = m->contactCount() > 0;
        if (in && was) {
            ++bonded_steps;
            INFO(m->lastStepReason());
            REQUIRE(m->lastTimestep() <= dt_res * (1.0 + 1e-12));
        }
        was = in;
    }
    CHECK(bonded_steps >= 200);  // unbreakable: it stays bonded and keeps the resolved step
}
