// SPDX-License-Identifier: MIT
//
// Linear dashpot restitution e(beta) at the step the engine picks by default, for an isolated
// impact, against the closed form of a linear spring-dashpot:
//   dp_mode 0 (dashpot may pull):   e = exp(-pi beta / sqrt(1 - beta^2))
//   dp_mode 1 (no tension):         e = exp(-beta (pi - 2 asin beta) / sqrt(1 - beta^2))
// (modes 2 and 3 differ from 0 and 1 only while a contact slides, so a normal impact must give
// the same numbers). Requirement: within 0.5% (relative) for every phase of first touch. The
// phase is randomised through the initial gap of runImpact, drawn over 1..60 steps' travel at
// the resolution step, with our own fixed-seed PRNG; 40 phases per case.
//
// Why 0.5% is a fair bound at the default step: the engine resolves the contact in 30 steps of
// the dashpot-raised stiffness and integrates the dashpot implicitly with exact impulses at both
// ends (core/include/talus/sdk/dashpot.hpp), a second-order scheme; a stand-alone prototype
// measured 0.06-0.25% mean (0.10-0.49% worst) for a cruder version of it at 31 steps, and the
// elastic part alone is good to < 1e-4 here (test_bounce.cpp).
#include <catch2/catch.hpp>

#include "dashpot_rest_scenes.hpp"
#include "test_support.hpp"

using namespace talus;
using namespace talus::test;

namespace {

constexpr double kRadius = 0.1, kDensity = 2600.0, kKn = 1e8, kV0 = 2.0;

struct Case {
    bool ball_target;
    int mode;
    double beta;
};

Stats measure(const Case& c, uint64_t seed, int phases, int64_t* min_steps = nullptr) {
    const double m_eff = diskMass(kDensity, kRadius) * (c.ball_target ? 0.5 : 1.0);
    const double e_exact =
        (c.mode == 1 || c.mode == 3) ? restitutionNoTension(c.beta) : restitutionFull(c.beta);
    // Travel per step at the resolution step (the dashpot only shortens it).
    const double travel = kV0 * linearDuration(m_eff, kKn) / 30.0;
    Rng rng(seed);
    Stats st;
    for (int i = 0; i < phases; ++i) {
        ImpactSetup s;
        s.props = linearProps(kKn, 0.0, 0.0, c.beta, 0.0, c.mode);
        s.ball_target = c.ball_target;
        s.radius = s.target_radius = kRadius;
        s.density = s.target_density = kDensity;
        s.normal_speed = c.ball_target ? 0.5 * kV0 : kV0;
        s.target_speed = c.ball_target ? 0.5 * kV0 : 0.0;
        s.gap = travel * rng.uniform(1.0, 60.0);
        const ImpactResult r = runImpact(s);
        REQUIRE(r.separated);
        st.add((r.restitution - e_exact) / e_exact);
        if (min_steps) *min_steps = std::min(*min_steps, r.steps_in_contact);
    }
    return st;
}

}  // namespace

TEST_CASE("dashpot restitution at the default step matches the closed forms",
          "[core][restitution]") {
    const std::vector<double> betas = {0.05, 0.1, 0.2, 0.3, 0.5, 0.7};
    for (bool ball_target : {false, true}) {
        for (int mode : {0, 1}) {
            DYNAMIC_SECTION((ball_target ? "ball-ball" : "ball-wall") << ", dp_mode " << mode) {
                Stats all;
                for (double beta : betas) {
                    int64_t min_steps = 1 << 30;
                    const Stats st =
                        measure({ball_target, mode, beta},
                                1000 + static_cast<uint64_t>(beta * 100) + mode, 40, &min_steps);
                    report(
                        "restitution %s mode %d beta %.2f: e_exact %.5f, rel. error mean "
                        "%.3e worst %.3e (min %lld steps in contact)\n",
                        ball_target ? "ball-ball" : "ball-wall", mode, beta,
                        mode ? restitutionNoTension(beta) : restitutionFull(beta), st.mean(),
                        st.worst, static_cast<long long>(min_steps));
                    INFO("beta " << beta << " mean " << st.mean() << " worst " << st.worst);
                    CHECK(st.worst < 5e-3);
                    all.add(st.worst);
                }
                report("  worst over all beta: %.3e\n", all.worst);
            }
        }
    }
}

TEST_CASE("dashpot modes 2 and 3 equal modes 0 and 1 in a normal impact", "[core][restitution]") {
    // Without shear motion nothing slides, so the shear-dashpot switch of modes 2/3 is inert and
    // the runs must be identical to the bit (same seed, same phases).
    for (double beta : {0.2, 0.5}) {
        for (int base : {0, 1}) {
            const Stats a = measure({false, base, beta}, 42, 5);
            const Stats b = measure({false, base + 2, beta}, 42, 5);
            CHECK(a.sum == b.sum);
            CHECK(a.worst == b.worst);
        }
    }
}

TEST_CASE("the two tension modes really differ", "[core][restitution]") {
    // the closed form of a linear spring-dashpot: beta = 0.2 gives 0.527 (full) vs 0.572 (no
    // tension). A plugin that ignored dp_mode would pass one of the closed-form checks by accident,
    // never both; this pins the reference values themselves.
    CHECK(restitutionFull(0.2) == Approx(0.527).margin(5e-4));
    CHECK(restitutionNoTension(0.2) == Approx(0.572).margin(5e-4));
    CHECK(betaForRestitution(restitutionFull(0.3)) == Approx(0.3).epsilon(1e-12));
    CHECK(betaForRestitutionNoTension(restitutionNoTension(0.3)) == Approx(0.3).epsilon(1e-9));
}

// ------------------------------------------------------------------ persistent contacts
//
// The dashpot's rate prediction includes what the rest of the model does to the contact
// (sdk/dashpot.hpp, DashpotHistory): in equilibrium the dashpot force must vanish and the
// reaction equal the load; in steady sliding the dashpot force is c times the slip rate. With
// the prediction that left gravity out, a resting linear ball (dp_nratio 0.3, kn 1e9) had a
// floor reaction 1.1% above its weight and booked dashpot work for ever, and the disk below slid
// 0.6% too slowly.

namespace {

using namespace talus::restscene;

// Tolerances. After the transient (damped at beta omega, e-folding in <= 0.02 s here; we settle
// for 3 s, > 100 e-folds) the remaining error is round-off: the dashpot's fixed point in
// equilibrium is F_d = 0 exactly, and the measured residuals are 1e-13 of the weight. 1e-9 is
// far above that and 1e7 times below the defect (1e-2).
constexpr double kRestTol = 1e-9;

}  // namespace

TEST_CASE("a ball resting on a floor: reaction = weight, no dashpot force, no dashpot work",
          "[core][restitution][rest]") {
    for (int mode = 0; mode <= 3; ++mode) {
        for (double beta : {0.3, 0.7}) {
            const RestResult r =
                restingColumn("linear", linearProps(1e6, 1e6, 0.5, beta, 0.3, mode), 1, 3.0, 5000);
            report(
                "resting ball, linear mode %d beta %.1f: reaction %+.2e, dp_fn %.2e W, dashpot "
                "work in 5000 steps %.2e J (strain %.2e J)\n",
                mode, beta, r.reaction_error, r.dashpot_force, r.dashpot_growth, r.strain);
            INFO("mode " << mode << " beta " << beta);
            CHECK(std::fabs(r.reaction_error) < kRestTol);
            CHECK(r.dashpot_force < kRestTol);
            CHECK(r.spring_error < kRestTol);
            // Nothing moves, so nothing may be dissipated: the defect booked 0.11 J per 5000
            // steps here against 0.047 J stored.
            CHECK(r.dashpot_growth <= kRestTol * r.strain);
        }
    }
    // The repro's stiff contact at its default step (c dt / 2m = 0.023 there).
    const RestResult r =
        restingColumn("linear", linearProps(1e9, 1e9, 0.5, 0.3, 0.0, 0), 1, 0.5, 5000);
    CHECK(std::fabs(r.reaction_error) < kRestTol);
    CHECK(r.dashpot_force < kRestTol);
    CHECK(r.dashpot_growth <= kRestTol * r.strain);
}

TEST_CASE("a resting column of balls: every spring carries the weight above it",
          "[core][restitution][rest]") {
    for (int mode = 0; mode <= 3; ++mode) {
        for (int n : {3, 5}) {
            const RestResult r =
                restingColumn("linear", linearProps(1e6, 1e6, 0.5, 0.5, 0.3, mode), n, 3.0, 5000);
            report(
                "column of %d, linear mode %d: bottom reaction %+.2e, worst spring error "
                "%.2e W, worst dp_fn %.2e W, dashpot work %.2e J\n",
                n, mode, r.reaction_error, r.spring_error, r.dashpot_force, r.dashpot_growth);
            INFO("mode " << mode << ", " << n << " balls");
            CHECK(std::fabs(r.reaction_error) < kRestTol);
            CHECK(r.spring_error < kRestTol);
            CHECK(r.dashpot_force < kRestTol);
            CHECK(r.dashpot_growth <= kRestTol * r.strain);
        }
    }
}

TEST_CASE("a disk sliding down an incline: acceleration and slip follow the closed forms",
          "[core][restitution][rest]") {
    // tan 25 deg = 0.466 > 3 mu: the disk slides (a rolling disk needs mu >= tan(theta)/3).
    // Rigid-body closed forms with a Coulomb force mu N, N = m g cos(theta):
    //   a = g (sin theta - mu cos theta),  spin acceleration mu N l / I = 2 mu g cos(theta) l / r^2
    // with l = r - overlap/2 the lever arm to the contact point (l/r = 1 - 1.4e-3 here).
    // Leapfrog integrates a constant acceleration exactly, so what remains after the normal
    // transient is the dashpot's bias; the defect's was -6e-3 (the normal spring carried the
    // dashpot's pull, and Coulomb's limit follows the spring). Measured after the fix: 5e-13
    // (round-off of a velocity difference over 1 s); bound 1e-9.
    const double theta = 25.0 * M_PI / 180.0, mu = 0.1;
    const double a_exact = kGravity * (std::sin(theta) - mu * std::cos(theta));
    for (int mode = 0; mode <= 3; ++mode) {
        // Modes 0 and 1 keep the shear dashpot while sliding (PFC): no shear dashpot here, it
        // has its own case below.
        const double beta_s = mode >= 2 ? 0.3 : 0.0;
        const SlideResult s =
            slidingDisk("linear", linearProps(1e6, 1e6, mu, 0.5, beta_s, mode), theta, 2.0, 1.0);
        // I dw/dt = mu N l, l = r - overlap/2 the lever arm to the contact point.
        const double spin_exact =
            2.0 * mu * kGravity * std::cos(theta) * s.lever / (s.radius * s.radius);
        report("incline, linear mode %d: accel rel. error %+.2e, spin accel %+.2e\n", mode,
               (s.accel - a_exact) / a_exact, (s.spin_accel - spin_exact) / spin_exact);
        INFO("mode " << mode);
        CHECK(s.accel == Approx(a_exact).epsilon(1e-9));
        CHECK(s.spin_accel == Approx(spin_exact).epsilon(1e-9));
    }
    SECTION("with a shear dashpot that stays on while sliding (mode 0)") {
        // Friction F = mu N + c_s s, s the slip speed of the contact point. For a disk
        // ds/dt = g sin(theta) - q F, q = 1/m + l^2/I the tangential inverse mass (3/m for
        // l = r), so s relaxes (in 1 / (q c_s) = 3 ms) to the steady slip where F = g sin(theta)
        // / q: s_inf = (g sin(theta) / q - mu N) / c_s, and the disk then accelerates at
        // g sin(theta) (1 - 1/(m q)), (2/3) g sin(theta) like a rolling one. The slip rate is
        // where a biased shear dashpot shows: the prediction that left the rest out had it 10%
        // high. Measured now: 1.4e-11 (slip) and 1.3e-13 (acceleration).
        const double beta_s = 0.3, ks = 1e6;
        const SlideResult s =
            slidingDisk("linear", linearProps(1e6, ks, mu, 0.5, beta_s, 0), theta, 2.0, 1.0);
        const double cs = 2.0 * beta_s * std::sqrt(s.mass * ks);
        const double q = (1.0 + 2.0 * s.lever * s.lever / (s.radius * s.radius)) / s.mass;
        const double s_inf =
            (kGravity * std::sin(theta) / q - mu * s.mass * kGravity * std::cos(theta)) / cs;
        const double a_inf = kGravity * std::sin(theta) * (1.0 - 1.0 / (s.mass * q));
        report("incline with shear dashpot: slip %.9g vs %.9g (%+.2e), accel %+.2e\n", s.slip,
               s_inf, (s.slip - s_inf) / s_inf, (s.accel - a_inf) / a_inf);
        CHECK(s.slip == Approx(s_inf).epsilon(1e-9));
        CHECK(s.accel == Approx(a_inf).epsilon(1e-9));
    }
}
