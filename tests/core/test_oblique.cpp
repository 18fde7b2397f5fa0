// SPDX-License-Identifier: MIT
//
// Oblique impacts of a ball on a wall with the linear model (Maw, Barber & Fawcett 1976), for disk
// (kappa = I/(m R^2) = 1/2, MassMode::Disk) and sphere (kappa = 2/5, MassMode::Sphere) inertia.
//
// Sliding regime (V_s >= (1 + 1/kappa) mu (1 + e) v_n), Chung & Ooi test-4 form (speed v at
// angle theta from the normal, no initial spin):
//   tangential restitution  e_t = v_t'/v_t = 1 - mu (1 + e) / tan(theta)
//   spin                    R |omega'| = mu (1 + e) v cos(theta) / kappa
//   contact-point rebound   tan(theta_r) = (tan(theta) - (1 + 1/kappa) mu (1 + e)) / e
// These follow from the impulse identity of the closed form of a linear spring-dashpot: with the
// Coulomb limit on the spring part only (PFC, and the linear plugin) and the dashpot impulse
// exactly zero over a contact, the tangential impulse is mu times the normal impulse m (1 + e) v_n
// whatever the step. So, with e the *measured* normal restitution, they should hold to the extent
// that the contact slides at every step; we allow 1e-6 (measured: round-off to ~1e-10, see the
// report). Against the *prescribed* e they also carry the restitution error (<= 0.5%,
// test_restitution.cpp), scaled by mu (1 + e)/tan(theta) <= 0.26 here: bound 2e-3. One modelling
// detail enters: the engine puts the contact point at R - overlap/2 from the centre (PFC2D's
// documentation), so the torque arm is shorter than R by overlap/2; kn is chosen stiff (max overlap
// / R = 4e-4), so the spin is low by about the mean overlap / 2R ~ 1.3e-4: bound 5e-4 on the spin
// and 2e-4 on tan(theta_r) (slip_out = v_t + omega R carries the same relative spin error times R
// omega' / (e v_n) <= ~1.5).
//
// Stick regime with compliance, mu -> infinity, no damping (Maw, Barber & Fawcett 1976):
//   V_s'/V_s = cos(pi sqrt((1 + 1/kappa) k_s / k_n))
// The tangential spring is a harmonic oscillator of mass m/(1 + 1/kappa) running for the normal
// contact duration pi sqrt(m/k_n). Error sources: the O(dt^2) phase error of central differences
// for the two oscillators (with 30 steps per normal contact and up to ~1.9 rad of tangential
// phase per normal half period, ~(omega_t dt)^2/24 * phase <= 2e-3 rad) and the arm effect above:
// bound 5e-3 absolute on the ratio.
#include <catch2/catch.hpp>

#include "test_support.hpp"

using namespace talus;
using namespace talus::test;

namespace {

constexpr double kR = 0.0025, kRho = 4000.0, kV = 3.9, kMu = 0.092, kE = 0.98;

double kappaOf(MassMode mode) { return mode == MassMode::Disk ? 0.5 : 0.4; }
double massOf(MassMode mode) {
    return mode == MassMode::Disk ? diskMass(kRho, kR) : sphereMass(kRho, kR);
}
/// Stiff enough that the maximum overlap is < 5e-4 R at the test speed (see the file comment).
double stiffness(MassMode mode) {
    const double m = massOf(mode);
    const double d_max = 4e-4 * kR;
    return m * (kV / d_max) * (kV / d_max);
}

ImpactSetup obliqueSetup(MassMode mode, double theta_deg) {
    const double th = theta_deg * M_PI / 180.0;
    ImpactSetup s;
    const double kn = stiffness(mode);
    s.props = linearProps(kn, kn, kMu, betaForRestitution(kE), 0.0, 0);
    s.mass_mode = mode;
    s.radius = kR;
    s.density = kRho;
    s.normal_speed = kV * std::cos(th);
    s.tangential_speed = kV * std::sin(th);
    return s;
}

}  // namespace

TEST_CASE("oblique impact, sliding regime: rigid-body formulas", "[core][oblique]") {
    for (MassMode mode : {MassMode::Disk, MassMode::Sphere}) {
        const double kappa = kappaOf(mode);
        // Sliding above theta* = atan((1 + 1/kappa) mu (1 + e)): 28.7 deg (disk), 32.5 deg
        // (sphere); Chung & Ooi 2011, test 4.
        const double theta_star = std::atan((1.0 + 1.0 / kappa) * kMu * (1.0 + kE)) * 180.0 / M_PI;
        CHECK(theta_star == Approx(mode == MassMode::Disk ? 28.7 : 32.5).margin(0.05));
        Rng rng(mode == MassMode::Disk ? 3 : 4);
        Stats et_exact, spin_exact, angle_exact, et_pres, spin_pres, angle_pres;
        for (double theta : {35.0, 40.0, 50.0, 60.0, 70.0, 80.0, 85.0}) {
            ImpactSetup s = obliqueSetup(mode, theta);
            s.gap = s.normal_speed * 1e-7 * rng.uniform(1.0, 30.0);  // random phase of touch
            const ImpactResult r = runImpact(s);
            REQUIRE(r.separated);
            const double th = theta * M_PI / 180.0;
            for (bool measured : {true, false}) {
                const double e = measured ? r.restitution : kE;
                const double et = 1.0 - kMu * (1.0 + e) / std::tan(th);
                const double spin = kMu * (1.0 + e) * kV * std::cos(th) / kappa / kR;
                const double tan_r = (std::tan(th) - (1.0 + 1.0 / kappa) * kMu * (1.0 + e)) / e;
                const double d_et = r.tangential_restitution - et;
                // Sign: the ball moves +x, friction on it points -x, so it spins clockwise.
                const double d_spin = (-r.spin_out - spin) / spin;
                const double d_ang = std::tan(r.contact_point_angle) - tan_r;
                INFO((mode == MassMode::Disk ? "disk" : "sphere")
                     << " theta " << theta << (measured ? " (measured e)" : " (prescribed e)")
                     << " e_t " << r.tangential_restitution << " vs " << et << ", spin "
                     << -r.spin_out << " vs " << spin << ", tan theta_r "
                     << std::tan(r.contact_point_angle) << " vs " << tan_r);
                if (measured) {
                    CHECK(std::fabs(d_et) < 1e-6);
                    CHECK(std::fabs(d_spin) < 5e-4);
                    CHECK(std::fabs(d_ang) < 2e-4);
                    et_exact.add(d_et), spin_exact.add(d_spin), angle_exact.add(d_ang);
                } else {
                    CHECK(std::fabs(d_et) < 2e-3);
                    CHECK(std::fabs(d_spin) < 5e-3);
                    CHECK(std::fabs(d_ang) < 2e-2 * std::max(1.0, std::fabs(tan_r)));
                    et_pres.add(d_et), spin_pres.add(d_spin), angle_pres.add(d_ang);
                }
            }
        }
        report(
            "oblique sliding %s: vs measured e: e_t %.2e, spin (rel) %.2e, tan(theta_r) "
            "%.2e; vs prescribed e: %.2e, %.2e, %.2e (worst over theta)\n",
            mode == MassMode::Disk ? "disk" : "sphere", et_exact.worst, spin_exact.worst,
            angle_exact.worst, et_pres.worst, spin_pres.worst, angle_pres.worst);
    }
}

TEST_CASE("oblique impact below theta*: rigid-stick limit is approached", "[core][oblique]") {
    // Not a closed form for a compliant contact (the slip reverses, Maw et al.), but the rigid
    // stick values bracket it: |V_s'| stays well below the sliding-formula value, and the
    // tangential impulse never exceeds mu times the normal impulse (Coulomb).
    for (MassMode mode : {MassMode::Disk, MassMode::Sphere}) {
        for (double theta : {10.0, 20.0}) {
            ImpactSetup s = obliqueSetup(mode, theta);
            const ImpactResult r = runImpact(s);
            REQUIRE(r.separated);
            const double m = massOf(mode);
            const double jn = m * (r.vn_in - r.vn_out);
            const double jt = m * (r.vt_in - r.vt_out);
            INFO("theta " << theta << " jn " << jn << " jt " << jt);
            CHECK(std::fabs(jt) <= kMu * jn * (1.0 + 1e-9));
        }
    }
}

namespace {

/// |V_s'/V_s - cos(pi sqrt((1 + 1/kappa) ks/kn))| over random phases; steps_per_contact = 0
/// means the default automatic step, else a fixed step T/(n + u) with u random (test_bounce.cpp).
Stats stickError(MassMode mode, double ratio, int steps_per_contact, int phases, uint64_t seed) {
    const double kappa = kappaOf(mode);
    const double kn = stiffness(mode);
    const double T = linearDuration(massOf(mode), kn);
    const double expect = std::cos(M_PI * std::sqrt((1.0 + 1.0 / kappa) * ratio));
    Rng rng(seed);
    Stats st;
    for (int i = 0; i < phases; ++i) {
        ImpactSetup s;
        // k_s V_s <= mu k_n v_n at first touch holds for any finite V_s with mu = 1e12.
        s.props = linearProps(kn, ratio * kn, 1e12);
        s.mass_mode = mode;
        s.radius = kR;
        s.density = kRho;
        s.normal_speed = 1.0;
        s.tangential_speed = 0.3;
        double dt = T / 30.0;
        if (steps_per_contact > 0) {
            dt = T / (steps_per_contact + rng.uniform());
            s.timestep = fixedStep(dt);
            s.guard.resolution = GuardAction::Off;
        }
        s.gap = s.normal_speed * dt * rng.uniform(1.0, 30.0);
        const ImpactResult r = runImpact(s);
        REQUIRE(r.separated);
        CHECK(r.restitution == Approx(1.0).margin(2e-3));
        st.add(r.slip_out / r.slip_in - expect);
    }
    return st;
}

const char* nameOf(MassMode mode) { return mode == MassMode::Disk ? "disk" : "sphere"; }

}  // namespace

// The tangential spring is still loaded when the contact ends (V_s'/V_s = cos(phase) means a
// spring force ~ sin(phase)). The linear model pays the shear impulse owed for the part of the last
// step the contact lasted (talus/sdk/corners.hpp); an earlier version dropped the spring at the
// step boundary, which made the tangential rebound first order (8e-2 off at the default step).
TEST_CASE("stick regime, mu -> infinity, no damping: slip reversal at the default step",
          "[core][oblique]") {
    for (MassMode mode : {MassMode::Disk, MassMode::Sphere}) {
        const double kappa = kappaOf(mode);
        Stats all;
        for (double ratio : {0.05, 0.1, 0.2, 1.0 / (1.0 + 1.0 / kappa), 0.5, 0.8, 1.0}) {
            const Stats st = stickError(mode, ratio, 0, 10, 9);
            INFO(nameOf(mode) << " ks/kn " << ratio << ": worst " << st.worst);
            CHECK(st.worst < 5e-3);
            all.add(st.worst);
            report(
                "stick regime %s ks/kn %.3f default step: |V_s'/V_s - cos| worst %.2e mean "
                "%.2e\n",
                nameOf(mode), ratio, st.worst, st.mean());
        }
    }
}

TEST_CASE("stick regime: the slip-reversal error converges at second order", "[core][oblique]") {
    // Fixed steps at 15..60 steps per normal contact, random phases of touch and separation.
    // Beyond that the error meets a floor of about 1e-4 that does not depend on the step: the
    // closed form takes the contact point at R, the engine at R - u/2 (the middle of the overlap),
    // a finite-overlap difference of order u_max / R (measured 1.0e-4 disk, 1.2e-4 sphere at
    // 240 steps); the order is fitted where the step error dominates, and the floor bounded.
    for (MassMode mode : {MassMode::Disk, MassMode::Sphere}) {
        std::vector<double> h, mean;
        for (int n : {15, 30, 60}) {
            const Stats st = stickError(mode, 0.5, n, 30, 21);
            h.push_back(1.0 / (n + 0.5));
            mean.push_back(st.mean());
            report("stick regime %s ks/kn 0.5, %d steps per contact: mean %.3e worst %.3e\n",
                   nameOf(mode), n, st.mean(), st.worst);
        }
        const double p = fittedOrder(h, mean);
        report("  fitted order %.2f\n", p);
        INFO(nameOf(mode) << " fitted order " << p);
        CHECK(p >= 1.8);
        CHECK(stickError(mode, 0.5, 240, 30, 21).mean() < 2e-4);
    }
}

TEST_CASE("stick regime: the slip reversal converges to the closed form", "[core][oblique]") {
    // What holds today (and must keep holding): the error does go to zero with the step, at
    // least at first order, and is within 2% at 240 steps per contact (measured 1.0e-2 worst).
    for (MassMode mode : {MassMode::Disk, MassMode::Sphere}) {
        std::vector<double> h, mean;
        double worst_fine = 0.0;
        for (int n : {30, 60, 120, 240}) {
            const Stats st = stickError(mode, 0.8, n, 20, 22);
            h.push_back(1.0 / (n + 0.5));
            mean.push_back(st.mean());
            worst_fine = st.worst;
        }
        const double p = fittedOrder(h, mean);
        INFO(nameOf(mode) << " fitted order " << p << ", worst at 240 steps " << worst_fine);
        CHECK(p >= 0.9);
        CHECK(worst_fine < 2e-2);
    }
}
