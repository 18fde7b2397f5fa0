// SPDX-License-Identifier: MIT
//
// Undamped bounces (linear model, beta = 0): the exact restitution is 1 (the closed form of a
// linear spring-dashpot). Central differences conserve a modified energy of the linear oscillator,
// so the error comes only from the two non-smooth instants (touch and separation) falling between
// steps; it depends on the phase of first touch within a step, so every figure here is a mean/worst
// over random phases, with the same phases at every step size.
#include <catch2/catch.hpp>

#include "test_support.hpp"

using namespace talus;
using namespace talus::test;

namespace {

constexpr double kRadius = 0.1, kDensity = 2600.0, kKn = 1e8, kV0 = 1.0;

ImpactSetup elasticSetup(bool ball_target) {
    ImpactSetup s;
    s.model = "linear";
    s.props = linearProps(kKn);
    s.ball_target = ball_target;
    s.radius = s.target_radius = kRadius;
    s.density = s.target_density = kDensity;
    s.normal_speed = ball_target ? 0.5 * kV0 : kV0;
    s.target_speed = ball_target ? 0.5 * kV0 : 0.0;
    return s;
}

double effectiveMass(bool ball_target) {
    const double m = diskMass(kDensity, kRadius);
    return ball_target ? 0.5 * m : m;
}

struct Sample {
    double phase;  ///< phase of first touch within a step, [0, 1)
    double frac;   ///< fractional part of the number of steps per contact, [0, 1)
};

/// Restitution error statistics with fixed steps dt = T / (n + frac), T = pi sqrt(m*/k).
Stats restitutionError(bool ball_target, int n, const std::vector<Sample>& samples) {
    const double T = linearDuration(effectiveMass(ball_target), kKn);
    Stats st;
    for (const Sample& smp : samples) {
        const double dt = T / (n + smp.frac);
        ImpactSetup s = elasticSetup(ball_target);
        s.timestep = fixedStep(dt);
        s.guard.resolution = GuardAction::Off;  // the coarsest steps are under-resolved on purpose
        s.guard.energy = GuardAction::Off;
        s.gap = kV0 * dt * (3.0 + smp.phase);  // first touch at this phase within a step
        const ImpactResult r = runImpact(s);
        REQUIRE(r.separated);
        st.add(r.restitution - 1.0);
    }
    return st;
}

std::vector<Sample> randomSamples(uint64_t seed, int count, bool integer_steps) {
    Rng rng(seed);
    std::vector<Sample> p(static_cast<std::size_t>(count));
    for (Sample& v : p) {
        v.phase = rng.uniform();
        v.frac = integer_steps ? 0.0 : rng.uniform();
    }
    return p;
}

}  // namespace

TEST_CASE("undamped bounce: restitution 1, error shrinks at least like dt^2", "[core][bounce]") {
    // Fixed steps at fractions of sqrt(m*/k): dt = pi sqrt(m*/k) / (n + frac) for n = 8..128
    // steps per contact (dt = 0.39 .. 0.024 sqrt(m*/k)). The error depends on the phase of touch
    // and on the phase of separation, i.e. on frac; both are drawn at random (the same draws at
    // every n), so the mean over samples is C h^p with one constant C and the order p is clean.
    // a 1-D sketch of the scheme gives dt^3; the engine gives 2 in general and 3
    // when the contact lasts a whole number of steps (frac = 0, reported below), because the
    // touch and separation errors then cancel to leading order. The automatic step is exactly
    // that case: dt = duration / 30.
    const std::vector<int> steps_per_contact = {8, 16, 32, 64, 128};
    for (bool ball_target : {false, true}) {
        DYNAMIC_SECTION((ball_target ? "ball-ball" : "ball-wall")) {
            for (bool integer_steps : {false, true}) {
                const auto samples = randomSamples(20240611, 60, integer_steps);
                std::vector<double> h, mean;
                for (int n : steps_per_contact) {
                    const Stats st = restitutionError(ball_target, n, samples);
                    h.push_back(M_PI / (n + (integer_steps ? 0.0 : 0.5)));  // in sqrt(m*/k)
                    mean.push_back(st.mean());
                    report("bounce %s %s dt = %.4f sqrt(m*/k): |e-1| mean %.3e worst %.3e\n",
                           ball_target ? "ball-ball" : "ball-wall",
                           integer_steps ? "integer" : "random-frac", h.back(), st.mean(),
                           st.worst);
                    // No energy created or lost beyond the discretisation error.
                    CHECK(st.worst < 0.05);
                }
                const double need = integer_steps ? 2.7 : 1.8;
                for (std::size_t i = 0; i + 1 < h.size(); ++i) {
                    const double p = std::log(mean[i] / mean[i + 1]) / std::log(h[i] / h[i + 1]);
                    report("  observed order %.4f -> %.4f: %.2f\n", h[i], h[i + 1], p);
                    // At least ~2 (3 for whole steps per contact), with 10% allowance for
                    // the scatter of 60 samples.
                    CHECK(p >= need);
                }
                const double p_fit = fittedOrder(h, mean);
                report("  fitted order %.2f\n", p_fit);
                CHECK(p_fit >= need);
            }
        }
    }
}

TEST_CASE("undamped bounce at the default automatic step", "[core][bounce]") {
    // The default step resolves a contact in exactly 30 steps (dt = duration / 30), the
    // whole-steps case of the sweep above, where n = 32 gives |e - 1| <= 6e-5 (worst of 60
    // phases) and the error goes like dt^3: (32/30)^3 = 1.2. Bound: 2e-4, i.e. that with a
    // factor ~3 for the approach rule shortening the steps before touch.
    for (bool ball_target : {false, true}) {
        Rng rng(77 + ball_target);
        Stats st;
        for (int i = 0; i < 30; ++i) {
            ImpactSetup s = elasticSetup(ball_target);
            const double dt_res = linearDuration(effectiveMass(ball_target), kKn) / 30.0;
            s.gap = kV0 * dt_res * rng.uniform(1.0, 40.0);
            const ImpactResult r = runImpact(s);
            REQUIRE(r.separated);
            st.add(r.restitution - 1.0);
        }
        report("bounce %s default step: |e-1| mean %.3e worst %.3e\n",
               ball_target ? "ball-ball" : "ball-wall", st.mean(), st.worst);
        CHECK(st.worst < 2e-4);
    }
}

TEST_CASE("undamped ball bouncing on a wall under gravity: apex drift per bounce",
          "[core][bounce]") {
    // A ball dropped from h0 onto a wall, beta = 0, default automatic step. Flight under gravity
    // is integrated exactly, so the apex height after each bounce, computed from any free-flight
    // state as y + v_y(t)^2 / (2g) with v_y at the whole step, measures the energy the contacts
    // created or lost. Under gravity a contact no longer lasts a whole number of steps, so each
    // bounce has the generic second-order error: at 30 steps per contact the random-phase sweep
    // above gives |e - 1| ~ 4e-4 mean, 1.2e-3 worst, i.e. an energy error 2|e - 1| per bounce.
    // Bounds: worst single bounce 3e-3 (measured ~7e-4); net drift per bounce over 40 bounces
    // 2e-4: the errors change sign with the phase, so the net drift is much smaller than the
    // single-bounce error (~mean / sqrt(40) if unbiased; a systematic bias would show here).
    const double g = 9.81, r = 0.05, h0 = 0.5;  // apex of the centre above the contact height
    ModelDef def;
    def.gravity = Vec2(0.0, -g);
    Model m(def);
    m.setDefaultContactModel("linear", linearProps(1e7));
    m.createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
    const BallId ball = m.createBall(ballAt(Vec2(0.0, r + h0), r, 2600.0));
    std::vector<double> apex;
    bool in_flight_up = false;
    const int bounces = 40;
    while (static_cast<int>(apex.size()) < bounces + 1 && m.step() < 2000000) {
        m.cycle(1);
        const Vec2 x = m.ballPos(ball);
        const double vy = m.ballVel(ball).y() - 0.5 * g * m.lastTimestep();  // at time()
        const bool free = m.contactCount() == 0 && x.y() > r * 1.01;
        if (apex.empty()) {
            apex.push_back(x.y() + vy * vy / (2.0 * g) - r);  // initial: exact h0
            continue;
        }
        if (free && vy > 0.0 && !in_flight_up) {
            apex.push_back(x.y() + vy * vy / (2.0 * g) - r);
            in_flight_up = true;
        }
        if (!free) in_flight_up = false;
    }
    REQUIRE(static_cast<int>(apex.size()) == bounces + 1);
    CHECK(apex[0] == Approx(h0).epsilon(1e-12));
    Stats per_bounce;
    for (int i = 1; i <= bounces; ++i) per_bounce.add((apex[i] - apex[i - 1]) / h0);
    const double drift = (apex[bounces] - apex[0]) / h0 / bounces;
    report("apex drift: mean per bounce %.3e, worst single bounce %.3e, net per bounce %.3e\n",
           per_bounce.mean(), per_bounce.worst, drift);
    CHECK(per_bounce.worst < 3e-3);
    CHECK(std::fabs(drift) < 2e-4);
}
