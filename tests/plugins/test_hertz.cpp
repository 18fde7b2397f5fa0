// SPDX-License-Identifier: MIT
//
// Tests of the `hertz` contact model (plugins/hertz, docs/models/hertz.md) against closed forms:
//  - elastic restitution 1 and the Hertz peak force, maximum overlap and duration
//    (Johnson 1985), including Chung & Ooi tests 1 and 2 (Chung & Ooi 2011);
//  - damped restitution against an independent RK4 integration of the same law, and its
//    independence of the impact speed (c ~ u^(1/4), Johnson 1985);
//  - oblique impacts in the sliding regime (Maw, Barber & Fawcett 1976), disk and sphere inertia;
//  - driveContact traces against the force law, the Mindlin stiffness and the unloading rule;
//  - property errors, the time-step contract, energies and SaveRestore.
//
// Tolerances, at the default automatic step (resolution rule, 30 steps per contact duration;
// the stiffness bound pi sqrt(m*/k_t) makes it about 38 near the peak):
//  - restitution: Hertz's error falls like dt^2.5; measured worst over
//    random phases 4e-5 elastic, 1.4e-4 damped; bounds 2e-4 and 1e-3 (mode 1, whose no-tension
//    clip is a corner of the force history, measured 9e-4: bound 2e-3);
//  - peak force and maximum overlap are sampled at steps: near the peak F = F_max (1 - 3/4
//    (omega t)^2), u = u_max (1 - 1/2 (omega t)^2), omega^2 = k_t(u_max)/m* = (15/8) v0^2/u_max^2,
//    t <= dt/2 = t_c/60: at most 3.4e-3 and 2.3e-3 low; bounds 4e-3 and 3e-3;
//  - duration: touch and separation are interpolated between steps (runImpact); bound 1e-3.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "../core/dashpot_rest_scenes.hpp"
#include "contact_law_support.hpp"

using namespace talus;
using namespace talus::lawtest;
using Catch::Matchers::Contains;

namespace {

// Granite-like rock (Nejati 2008: Lac du Bonnet granite G = 27.4 GPa, nu = 0.26).
constexpr double kG = 27.4e9, kNu = 0.26, kR = 0.1, kRho = 2600.0;

std::vector<PropValue> hertzProps(double G, double nu, double fric = 0.0, double beta_n = 0.0,
                                  int mode = 0, double beta_s = 0.0) {
    return {{"hz_shear", G},       {"hz_poiss", nu},      {"fric", fric},
            {"dp_nratio", beta_n}, {"dp_sratio", beta_s}, {"dp_mode", static_cast<double>(mode)}};
}

/// E* and R* as the model must form them (Johnson 1985): equal balls
/// 1/E* = 2 (1-nu^2)/E = (1-nu)/G; a rigid wall contributes nothing: E* = 2G/(1-nu).
double eStar(double G, double nu, bool wall) { return (wall ? 2.0 : 1.0) * G / (1.0 - nu); }

/// A gap for a random phase of first touch, over 1..20 steps of travel at the resolved step.
double randomGap(Rng& rng, double v0, double t_c) {
    return v0 * (t_c / 30.0) * rng.uniform(1.0, 20.0);
}

}  // namespace

TEST_CASE("hertz: an elastic impact returns e = 1 (wall and ball, disk and sphere)", "[hertz]") {
    Rng rng(11);
    Stats err;
    for (bool ball : {false, true})
        for (MassMode mode : {MassMode::Disk, MassMode::Sphere})
            for (double v0 : {0.5, 5.0}) {
                ImpactSetup s;
                s.model = "hertz";
                s.props = hertzProps(kG, kNu);
                s.ball_target = ball;
                s.mass_mode = mode;
                s.radius = kR;
                s.density = kRho;
                s.normal_speed = ball ? 0.5 * v0 : v0;
                s.target_speed = ball ? 0.5 * v0 : 0.0;
                const double m = mode == MassMode::Disk ? diskMass(kRho, kR) : sphereMass(kRho, kR);
                const double m_eff = ball ? 0.5 * m : m, r_eff = ball ? 0.5 * kR : kR;
                const HertzImpact h = hertzImpact(m_eff, r_eff, eStar(kG, kNu, !ball), v0);
                for (int i = 0; i < 8; ++i) {
                    s.gap = randomGap(rng, v0, h.tc);
                    const ImpactResult r = runImpact(s);
                    REQUIRE(r.separated);
                    err.add(r.restitution - 1.0);
                    CHECK(r.duration == Approx(h.tc).epsilon(1e-3));
                    CHECK(r.max_overlap == Approx(h.dmax).epsilon(3e-3));
                    CHECK(r.peak_force == Approx(h.fmax).epsilon(4e-3));
                }
            }
    INFO("worst |e - 1| = " << err.worst << ", mean " << err.mean());
    CHECK(err.worst < 2e-4);
}

TEST_CASE("hertz: Chung & Ooi tests 1 and 2 (sphere masses, rigid wall)", "[hertz][chung-ooi]") {
    struct Case {
        Material mat;
        bool pair;        // test 1: two equal spheres head-on; test 2: sphere on a rigid plane
        double R, speed;  // each sphere's speed (test 1) or the impact speed (test 2)
        double f_table, d_table, t_table;  // Chung & Ooi 2011, as printed
        double f_digit, d_digit, t_digit;  // one unit of the last printed digit
    };
    const Case cases[] = {
        {{"glass", 48e9, 0.20, 2800}, true, 0.01, 10.0, 10.70e3, 274e-6, 40.3e-6, 10, 1e-6, 0.1e-6},
        {{"limestone", 20e9, 0.25, 2500}, true, 0.01, 10.0, 7108, 368e-6, 54.2e-6, 1, 1e-6, 0.1e-6},
        {{"Al alloy", 70e9, 0.30, 2699},
         false,
         0.1,
         0.2,
         11.37e3,
         49.7e-6,
         0.732e-3,
         10,
         0.1e-6,
         1e-6},
        {{"Mg alloy", 40e9, 0.35, 1800}, false, 0.1, 0.2, 7233, 52.1e-6, 0.767e-3, 1, 0.1e-6, 1e-6},
    };
    Rng rng(7);
    for (const Case& c : cases) {
        SECTION(c.mat.name) {
            const double m = sphereMass(c.mat.rho, c.R);
            const double m_eff = c.pair ? 0.5 * m : m, r_eff = c.pair ? 0.5 * c.R : c.R;
            const double v0 = c.pair ? 2.0 * c.speed : c.speed;
            // The model's E* from G and nu must equal E/(2(1-nu^2)) (pair) or E/(1-nu^2) (wall).
            const double e_eff = c.pair ? c.mat.E / (2.0 * (1.0 - c.mat.nu * c.mat.nu))
                                        : c.mat.E / (1.0 - c.mat.nu * c.mat.nu);
            REQUIRE(eStar(c.mat.G(), c.mat.nu, !c.pair) == Approx(e_eff).epsilon(1e-14));
            const HertzImpact h = hertzImpact(m_eff, r_eff, e_eff, v0);
            // Our reading of the table: within half a unit of the last printed digit (7108 N
            // and 7233 N are the Kratos reference values).
            CHECK(std::fabs(h.fmax - c.f_table) <= 0.5 * c.f_digit);
            CHECK(std::fabs(h.dmax - c.d_table) <= 0.5 * c.d_digit);
            CHECK(std::fabs(h.tc - c.t_table) <= 0.5 * c.t_digit);

            ImpactSetup s;
            s.model = "hertz";
            s.props = hertzProps(c.mat.G(), c.mat.nu);
            s.mass_mode = MassMode::Sphere;
            s.ball_target = c.pair;
            s.radius = s.target_radius = c.R;
            s.density = s.target_density = c.mat.rho;
            s.normal_speed = c.speed;
            s.target_speed = c.pair ? c.speed : 0.0;
            for (int i = 0; i < 5; ++i) {
                s.gap = randomGap(rng, v0, h.tc);
                const ImpactResult r = runImpact(s);
                REQUIRE(r.separated);
                CHECK(r.vn_in == Approx(v0).epsilon(1e-12));
                CHECK(r.peak_force == Approx(h.fmax).epsilon(4e-3));
                // Sampled, so below the peak but for the integration error of the discrete
                // frequency, (omega dt)^2/24 = 5e-4 at omega dt = 0.106.
                CHECK(r.peak_force <= h.fmax * (1.0 + 5e-4));
                CHECK(r.max_overlap == Approx(h.dmax).epsilon(3e-3));
                CHECK(r.duration == Approx(h.tc).epsilon(1e-3));
                CHECK(r.restitution == Approx(1.0).margin(2e-4));
            }
        }
    }
}

TEST_CASE("hertz: ContactDuration is the Hertz duration the rig measures", "[hertz][timestep]") {
    // The resolution rule divides ContactDuration(m*, v) by the steps per contact, so it must
    // be the duration of the impact: check it against a converged measurement (200 steps).
    for (bool ball : {false, true}) {
        const double m = diskMass(kRho, kR);
        const double m_eff = ball ? 0.5 * m : m;
        LawDriver drv("hertz", hertzProps(kG, kNu), ball, kR, kR, m_eff);
        ContactModel* c = drv.clone();
        for (double v0 : {0.2, 2.0, 20.0}) {
            ImpactSetup s;
            s.model = "hertz";
            s.props = hertzProps(kG, kNu);
            s.ball_target = ball;
            s.normal_speed = ball ? 0.5 * v0 : v0;
            s.target_speed = ball ? 0.5 * v0 : 0.0;
            s.timestep.resolution = 200;
            const ImpactResult r = runImpact(s);
            CHECK(c->ContactDuration(m_eff, v0) == Approx(r.duration).epsilon(1e-4));
            CHECK(c->ContactDuration(m_eff, v0) ==
                  Approx(hertzImpact(m_eff, ball ? 0.5 * kR : kR, eStar(kG, kNu, !ball), v0).tc)
                      .epsilon(1e-12));
        }
        CHECK(c->ContactDuration(m_eff, 0.0) == HUGE_VAL);  // no approach: the stiffness rules
    }
}

TEST_CASE("hertz: damped restitution matches an RK4 integration and does not depend on speed",
          "[hertz][damping]") {
    // m u'' = -(K u^(3/2) + c0 u^(1/4) u'), K = (4/3) E* sqrt(R*), c0 = 2 beta sqrt(2 m* E*
    // sqrt(R*)) (the dashpot on the tangent stiffness); mode 1 clips the total at zero.
    // The errors are judged on e itself (absolute): e is small for strong damping and a
    // relative bound would ask for more than the energy can resolve. Measured worst at the
    // default step over speeds and phases: 1.5e-4 (mode 0), 6e-4 (mode 1, beta = 0.6, whose
    // clip makes the force history non-smooth); bound 1e-3. At 200 steps per contact: 2e-5.
    const double m = diskMass(kRho, kR), es = eStar(kG, kNu, true);
    const double K = 4.0 / 3.0 * es * std::sqrt(kR);
    Rng rng(3);
    for (int mode : {0, 1})
        for (double beta : {0.1, 0.3, 0.6}) {
            const double c0 = 2.0 * beta * std::sqrt(m * 2.0 * es * std::sqrt(kR));
            auto force = [&](double u, double v) {
                if (u <= 0.0) return 0.0;
                const double f = K * std::pow(u, 1.5) + c0 * std::pow(u, 0.25) * v;
                return mode == 1 ? std::max(0.0, f) : f;
            };
            const double tc1 = hertzImpact(m, kR, es, 1.0).tc;
            const double e_ref =
                referenceRestitution(m, 1.0, tc1, force, [](double u, double) { return u; });
            REQUIRE(e_ref > 0.0);
            REQUIRE(e_ref < 1.0);
            Stats err;
            for (double v0 : {0.3, 3.0, 15.0})
                for (int i = 0; i < 4; ++i) {
                    ImpactSetup s;
                    s.model = "hertz";
                    s.props = hertzProps(kG, kNu, 0.0, beta, mode);
                    s.normal_speed = v0;
                    s.gap = randomGap(rng, v0, hertzImpact(m, kR, es, v0).tc);
                    const ImpactResult r = runImpact(s);
                    REQUIRE(r.separated);
                    err.add(r.restitution - e_ref);
                }
            INFO("mode " << mode << " beta " << beta << ": e_ref " << e_ref << ", worst error "
                         << err.worst);
            CHECK(err.worst < 1e-3);
            ImpactSetup fine;
            fine.model = "hertz";
            fine.props = hertzProps(kG, kNu, 0.0, beta, mode);
            fine.normal_speed = 3.0;
            fine.timestep.resolution = 200;
            CHECK(runImpact(fine).restitution == Approx(e_ref).margin(1e-4));
        }
}

TEST_CASE("hertz: hz_e gives the restitution asked for; the Thornton fit agrees",
          "[hertz][damping]") {
    // The plugin inverts its own scaled impact ODE. Independent cross-check: the fit of
    // Johnson 1985 (Thornton et al. 2013 via the Yade Chung-Ooi scripts), stated for a
    // Hertz law without attractive force, i.e. our dp_mode 1; the fit reproduces our ratio to
    // 7e-4 for e in [0.2, 0.9] (it drifts above e = 0.93, where it was not fitted).
    auto thornton = [](double e) {
        const double h[10] = {-6.918798, -16.41105, 146.8049,  -796.4559, 2928.711,
                              -7206.864, 11494.29,  -11342.18, 6276.757,  -1489.915};
        double alpha = 0.0, p = 1.0;
        for (double hi : h) alpha += hi * (p *= e);
        return std::sqrt(1.0 / (1.0 - (1.0 + e) * (1.0 + e) * std::exp(alpha)) - 1.0);
    };
    Rng rng(8);
    for (int mode : {0, 1})
        for (double e : {0.2, 0.53, 0.8, 0.97}) {
            std::vector<PropValue> props = {{"hz_shear", kG},
                                            {"hz_poiss", kNu},
                                            {"hz_e", e},
                                            {"dp_mode", static_cast<double>(mode)}};
            LawDriver drv("hertz", props, false, kR, 0.0, diskMass(kRho, kR));
            const double beta = drv.prototype().ReturnProp(4);  // dp_nratio, derived
            REQUIRE(std::string(drv.prototype().PropInfoAt(4)->name) == "dp_nratio");
            if (mode == 1 && e <= 0.9) CHECK(beta == Approx(thornton(e)).margin(1e-3));
            for (double v0 : {0.5, 5.0}) {
                ImpactSetup s;
                s.model = "hertz";
                s.props = props;
                s.normal_speed = v0;
                s.gap = randomGap(rng, v0,
                                  hertzImpact(diskMass(kRho, kR), kR, eStar(kG, kNu, true), v0).tc);
                const ImpactResult r = runImpact(s);
                INFO("mode " << mode << " e " << e << " v0 " << v0 << ": beta " << beta);
                CHECK(r.restitution == Approx(e).margin(1e-3));
            }
        }
    CHECK_THAT(modelError("hertz", {{"hz_shear", kG}, {"hz_e", 0.5}, {"dp_nratio", 0.2}}),
               Contains("set either 'hz_e' or 'dp_nratio'"));
    CHECK_THAT(modelError("hertz", {{"hz_shear", kG}, {"hz_e", 0.1}, {"dp_mode", 1}}),
               Contains("needs a damping ratio above 1") && Contains("0.1196"));
}

TEST_CASE("hertz: oblique impacts in the sliding regime (Maw, Barber & Fawcett 1976)",
          "[hertz][oblique]") {
    // Chung & Ooi test 4 set-up: Al oxide, R = 2.5 mm, |v| = 3.9 m/s, mu = 0.092, no spin;
    // angles above the sliding threshold tan(theta) >= (1 + 1/kappa) mu (1 + e). The impulse
    // identity makes e_t = 1 - mu (1+e)/tan(theta) exact for any law whose Coulomb limit acts on
    // the elastic force (the closed form of a linear spring-dashpot): the measured e is used in the
    // formulas, so the tangential checks are independent of the normal error. The spin is exact
    // only up to the lever arm: the engine puts the contact point in the middle of the overlap, arm
    // R - u/2, so R |omega'| is low by up to u_max/(2R) (measured and bounded below).
    const Material alox{"Al oxide", 380e9, 0.23, 4000};
    const double R = 2.5e-3, V = 3.9, mu = 0.092;
    for (MassMode mm : {MassMode::Disk, MassMode::Sphere})
        for (double beta : {0.0, 0.05})
            for (double deg : {40.0, 60.0, 80.0}) {
                const double kappa = mm == MassMode::Disk ? 0.5 : 0.4;
                const double th = deg * M_PI / 180.0;
                ImpactSetup s;
                s.model = "hertz";
                s.props = hertzProps(alox.G(), alox.nu, mu, beta);
                s.mass_mode = mm;
                s.radius = R;
                s.density = alox.rho;
                s.normal_speed = V * std::cos(th);
                s.tangential_speed = V * std::sin(th);
                const ImpactResult r = runImpact(s);
                REQUIRE(r.separated);
                const double e = r.restitution;
                REQUIRE(std::tan(th) >= (1.0 + 1.0 / kappa) * mu * (1.0 + e));  // sliding
                const double et = 1.0 - mu * (1.0 + e) / std::tan(th);
                const double w = mu * (1.0 + e) * V * std::cos(th) / (kappa * R);
                const double tan_r = (std::tan(th) - (1.0 + 1.0 / kappa) * mu * (1.0 + e)) / e;
                const double arm = r.max_overlap / (2.0 * R);
                INFO((mm == MassMode::Disk ? "disk" : "sphere")
                     << " beta " << beta << " theta " << deg << ": e_t " << r.tangential_restitution
                     << " vs " << et << ", spin " << r.spin_out << " vs " << -w << ", arm " << arm);
                CHECK(r.tangential_restitution == Approx(et).epsilon(1e-5));
                CHECK(r.spin_out < 0.0);  // friction on the bottom of a ball moving to +x
                CHECK(-r.spin_out <= w * (1.0 + 1e-5));
                CHECK(-r.spin_out >= w * (1.0 - arm - 1e-4));
                // The rebound angle inherits the spin's lever-arm error through slip_out.
                const double slip_err = w * R * (arm + 1e-4) / (e * V * std::cos(th));
                CHECK(std::tan(r.contact_point_angle) == Approx(tan_r).margin(slip_err + 1e-5));
            }
}

TEST_CASE("hertz: driveContact follows the force law, the tangent and the Mindlin stiffness",
          "[hertz][drive]") {
    const double dt = 1e-6, umax = 2e-4;
    for (bool ball : {false, true}) {
        DriveSetup d;
        d.model = "hertz";
        d.props = hertzProps(kG, kNu);
        d.ball_target = ball;
        d.radius = kR;
        d.target_radius = 0.3;  // R* = 0.075 for the pair
        d.dt = dt;
        const double r_eff = ball ? kR * 0.3 / (kR + 0.3) : kR;
        const double es = eStar(kG, kNu, !ball);
        // Load to umax and unload: the force is a function of the overlap only (no memory).
        const int n = 400;
        for (int i = 1; i < n; ++i) d.overlap.push_back(umax * std::sin(M_PI * i / n));
        const DriveResult r = driveContact(d);
        for (std::size_t i = 0; i < d.overlap.size(); ++i) {
            const double u = d.overlap[i];
            const double f = 4.0 / 3.0 * es * std::sqrt(r_eff) * std::pow(u, 1.5);
            CHECK(r.trace[i].normal_force == Approx(f).epsilon(1e-12));
            CHECK(r.knest[i] == Approx(2.0 * es * std::sqrt(r_eff * u)).epsilon(1e-12));
        }
        // Strain energy from the law itself: int F du = (2/5) F u.
        CHECK(r.strain ==
              Approx(0.4 * r.trace.back().normal_force * d.overlap.back()).epsilon(1e-12));
    }

    SECTION("shear: Mindlin stiffness 8 G* sqrt(R* u), Coulomb cap, scaling on unloading") {
        for (bool ball : {false, true}) {
            const double r_eff = ball ? kR * 0.3 / (kR + 0.3) : kR;
            const double gs = kG / ((ball ? 2.0 : 1.0) * (2.0 - kNu));
            const double es = eStar(kG, kNu, !ball);
            DriveSetup d;
            d.model = "hertz";
            d.props = hertzProps(kG, kNu, 0.3);
            d.ball_target = ball;
            d.radius = kR;
            d.target_radius = 0.3;
            d.dt = dt;
            // Load to u1 with no shear, then shear in small steps at constant overlap.
            const double u1 = 1e-4, ds = 1e-9;
            for (int i = 1; i <= 10; ++i)
                d.overlap.push_back(u1 * i / 10.0), d.shear.push_back(0.0);
            for (int i = 1; i <= 10; ++i) d.overlap.push_back(u1), d.shear.push_back(ds * i);
            // Unload to u1/4 at constant shear displacement.
            d.overlap.push_back(0.25 * u1), d.shear.push_back(ds * 10);
            const DriveResult r = driveContact(d);
            const double kt = 8.0 * gs * std::sqrt(r_eff * u1);
            // F_s on end 2 along t opposes the shear displacement of end 2: -k_t us.
            for (int i = 1; i <= 10; ++i)
                CHECK(r.trace[9 + i].shear_force == Approx(-kt * ds * i).epsilon(1e-9));
            const double fs_before = r.trace[19].shear_force;
            // Unloading keeps F_s/k_t: the force scales with sqrt(u) (k_t ratio), as long as it
            // stays within friction.
            const double fs_after = r.trace[20].shear_force;
            const double fn_after = 4.0 / 3.0 * es * std::sqrt(r_eff) * std::pow(0.25 * u1, 1.5);
            REQUIRE(std::fabs(fs_before) * 0.5 < 0.3 * fn_after);
            CHECK(fs_after == Approx(0.5 * fs_before).epsilon(1e-12));
            CHECK(r.slip > 0.0);  // the stored shear energy lost by the scaling is slip work
            CHECK(r.slip == Approx(0.5 * fs_before * fs_before / kt * 0.5).epsilon(1e-9));

            // Past the Coulomb limit the force stays at fric F_n.
            DriveSetup e = d;
            e.overlap.resize(10), e.shear.resize(10);
            for (int i = 1; i <= 20; ++i) e.overlap.push_back(u1), e.shear.push_back(1e-5 * i);
            const DriveResult q = driveContact(e);
            const double fn1 = 4.0 / 3.0 * es * std::sqrt(r_eff) * std::pow(u1, 1.5);
            CHECK(q.trace.back().shear_force == Approx(-0.3 * fn1).epsilon(1e-12));
            CHECK(q.slip > 0.0);
            CHECK(q.strain ==
                  Approx(0.4 * fn1 * u1 + 0.5 * std::pow(0.3 * fn1, 2) / kt).epsilon(1e-9));
        }
    }
}

TEST_CASE("hertz: knest and ksest are the tangent stiffnesses raised for the dashpots",
          "[hertz][timestep]") {
    const double beta_n = 0.4, beta_s = 0.2;
    DriveSetup d;
    d.model = "hertz";
    d.props = hertzProps(kG, kNu, 0.5, beta_n, 0, beta_s);
    d.dt = 1e-7;
    d.overlap = {5e-5, 1e-4};
    const DriveResult r = driveContact(d);
    const double es = eStar(kG, kNu, true);
    auto factor = [](double b) {
        const double f = std::sqrt(1.0 + b * b) - b;
        return 1.0 / (f * f);
    };
    CHECK(r.knest[1] == Approx(2.0 * es * std::sqrt(kR * 1e-4) * factor(beta_n)).epsilon(1e-12));

    LawDriver drv("hertz", d.props, false, kR, 0.0, 10.0);
    ContactModel* c = drv.clone();
    CHECK(c->KnEstimate() == 0.0);  // not touching: the tangent at zero overlap
    FdBlock fd = drv.block(1e-4, 0.1, 0.0, 1e-7, nullptr);
    c->FDlaw(fd);
    const double gs = kG / (2.0 - kNu);
    CHECK(fd.ksest == Approx(8.0 * gs * std::sqrt(kR * 1e-4) * factor(beta_s)).epsilon(1e-12));
    CHECK(c->KnEstimate() == Approx(fd.knest).epsilon(1e-15));
    CHECK(c->KsEstimate() == Approx(fd.ksest).epsilon(1e-15));
}

TEST_CASE("hertz: the energy balance closes over damped, sliding impacts", "[hertz][energy]") {
    // Strain (2/5) F u + F_s^2/(2 k_t) from the law; dashpot and shear-spring works trapezoidal
    // (force at both ends of the step times the step's displacement), the work the engine's
    // leapfrog kinetic energy sees. What remains is a discretisation error, mostly the normal
    // spring's trapezoidal work against its exact integral; it must vanish as the step
    // shrinks. Measured at 30 / 100 steps: 1.1e-4 / 1.2e-5 of the
    // impact energy in modes 0 and 1, 2.3e-4 / 1.9e-5 in mode 3 (its shear dashpot switches at
    // the stick-slip transitions).
    for (int mode : {0, 1, 3}) {
        double residual[2];
        for (int k = 0; k < 2; ++k) {
            ImpactSetup s;
            s.model = "hertz";
            s.props = hertzProps(kG, kNu, 0.3, 0.3, mode, 0.2);
            s.normal_speed = 2.0;
            s.tangential_speed = 3.0;
            s.spin = 5.0;
            s.timestep.resolution = k == 0 ? 30 : 100;
            const ImpactResult r = runImpact(s);
            REQUIRE(r.separated);
            INFO("mode " << mode << ": dashpot " << r.energy.dashpot << ", slip " << r.energy.slip
                         << ", residual " << r.energy.balanceError());
            CHECK(r.energy.dashpot > 0.0);
            CHECK(r.energy.slip > 0.0);
            CHECK(r.energy_out < r.energy_in);
            residual[k] = std::fabs(r.energy.balanceError()) / r.energy_in;
        }
        CHECK(residual[0] < 5e-4);
        CHECK(residual[1] < residual[0] / 3.0);
    }
}

TEST_CASE("hertz: property errors name the property and the reason", "[hertz][props]") {
    const std::string unknown = modelError("hertz", {{"hz_modulus", 1e9}});
    CHECK_THAT(unknown, Contains("unknown property 'hz_modulus'") && Contains("'hertz'") &&
                            Contains("hz_shear") && Contains("hz_poiss") && Contains("dp_mode"));
    CHECK_THAT(modelError("hertz", {{"hz_shear", -1e9}}),
               Contains("'hz_shear' must be >= 0") && Contains("got -1e+09"));
    for (double nu : {0.5, 0.7, -0.1})
        CHECK_THAT(modelError("hertz", {{"hz_shear", 1e9}, {"hz_poiss", nu}}),
                   Contains("'hz_poiss' must be in [0, 0.5)") && Contains("incompressible"));
    CHECK_THAT(modelError("hertz", {{"hz_alpha", 2.0}}),
               Contains("'hz_alpha'") && Contains("only the Hertz exponent 1.5"));
    CHECK_THAT(modelError("hertz", {{"dp_mode", 4}}),
               Contains("'dp_mode' must be one of 0 = full") && Contains("got 4"));
    CHECK_THAT(modelError("hertz", {{"dp_nratio", 1.5}}),
               Contains("'dp_nratio' must be in [0, 1]"));
    CHECK_THAT(modelError("hertz", {{"fric", -0.1}}), Contains("'fric' must be >= 0"));
    CHECK_THAT(modelError("hertz", {{"hz_fn", 1.0}}), Contains("read-only"));
    CHECK(modelError("hertz", hertzProps(kG, 0.499, 0.5, 0.3, 3, 0.2)).empty());
    // Names are case-insensitive, as every property.
    CHECK(modelError("hertz", {{"HZ_SHEAR", 1e9}}).empty());
}

TEST_CASE("hertz: fric is inherited from the ends (minimum), the moduli are not",
          "[hertz][props]") {
    LawDriver drv("hertz", hertzProps(kG, kNu, 0.8), true, kR, kR, 1.0);
    PropBlock pb = drv.propBlock();
    pb.fric[0] = 0.3, pb.fric[1] = 0.5;
    const ContactModel& proto = drv.prototype();
    std::vector<std::max_align_t> storage(proto.ObjectSize() / sizeof(std::max_align_t) + 1);
    ContactModel* c = proto.Clone(pb, storage.data());
    REQUIRE(c);
    CHECK(c->ReturnProp(3) == 0.3);  // fric
    CHECK(c->ReturnProp(0) == kG);
    c->Destroy();
}

TEST_CASE("hertz: SaveRestore mid-contact continues bit for bit", "[hertz][save]") {
    for (bool ball : {false, true})
        for (int mode : {0, 1, 3}) {
            LawDriver drv("hertz", hertzProps(kG, kNu, 0.2, 0.3, mode, 0.1), ball, kR, 0.2, 40.0);
            std::vector<double> u, us;
            const int n = 200;
            for (int i = 1; i <= n + 5; ++i) {
                u.push_back(1e-4 * std::sin(M_PI * i / n) - (i > n ? 1e-6 : 0.0));
                us.push_back(2e-5 * std::sin(2.0 * M_PI * i / n));
            }
            int compared = 0;
            CHECK(saveRestoreContinuesExactly(drv, u, us, 1e-6, n / 3, &compared));
            CHECK(compared == static_cast<int>(u.size()) - n / 3);
        }
}

// ------------------------------------------------------------------ persistent contacts
//
// Equilibrium and steady sliding with a dashpot (sdk/dashpot.hpp, "The rest of
// the model"). With the prediction that left gravity out, a resting ball's dashpot pulled by
// 3.8% of the weight at beta 0.7 (the Hertz spring carrying that much more) and the disk below
// slid 0.9% too slowly. Scenes: tests/core/dashpot_rest_scenes.hpp. The transient is damped at
// beta omega (e-folding in < 0.02 s at the static overlap); after 3 s only round-off remains
// (measured 1e-13 of the weight), so 1e-9 is far above it and 1e7 below the defect.

TEST_CASE("hertz: resting ball and column: reaction = load, no dashpot force, no dashpot work",
          "[hertz][rest]") {
    using namespace talus::restscene;
    const double G = 1e8, nu = 0.3, tol = 1e-9;
    for (int mode = 0; mode <= 3; ++mode) {
        for (int n : {1, 4}) {
            const RestResult r =
                restingColumn("hertz", hertzProps(G, nu, 0.5, 0.7, mode, 0.3), n, 3.0, 5000);
            INFO("mode " << mode << ", " << n << " ball(s): reaction " << r.reaction_error
                         << ", spring " << r.spring_error << ", dp_fn " << r.dashpot_force
                         << ", dashpot work " << r.dashpot_growth);
            CHECK(std::fabs(r.reaction_error) < tol);
            CHECK(r.spring_error < tol);
            CHECK(r.dashpot_force < tol);
            CHECK(std::fabs(r.dashpot_growth) <= tol * r.strain);
        }
    }
    // hz_e sets the damping ratio (here 0.5 -> beta about 0.2): the same holds.
    const RestResult r =
        restingColumn("hertz", {{"hz_shear", G}, {"hz_poiss", nu}, {"hz_e", 0.5}, {"dp_mode", 1.0}},
                      1, 3.0, 5000);
    CHECK(std::fabs(r.reaction_error) < tol);
    CHECK(r.dashpot_force < tol);
}

TEST_CASE("hertz: a disk sliding down an incline follows the rigid-body closed forms",
          "[hertz][rest]") {
    // As for linear (tests/core/test_restitution.cpp): tan 25 deg > 3 mu, so the disk slides;
    // a = g (sin theta - mu cos theta), spin acceleration 2 mu g cos(theta) l / r^2. Leapfrog is
    // exact for constant accelerations; the defect's bias was -9e-3. Bound 1e-9 (round-off ~1e-12).
    using namespace talus::restscene;
    const double theta = 25.0 * M_PI / 180.0, mu = 0.1;
    const double a_exact = kGravity * (std::sin(theta) - mu * std::cos(theta));
    for (int mode : {0, 1, 2, 3}) {
        // Modes 0 and 1 keep a shear dashpot while sliding, which changes the closed form.
        const double beta_s = mode >= 2 ? 0.3 : 0.0;
        const SlideResult s =
            slidingDisk("hertz", hertzProps(1e8, 0.3, mu, 0.5, mode, beta_s), theta, 2.0, 1.0);
        INFO("mode " << mode << ": accel " << s.accel << " vs " << a_exact);
        CHECK(s.accel == Approx(a_exact).epsilon(1e-9));
        const double lever = s.lever / (s.radius * s.radius);  // l / r^2, l = r - overlap/2
        CHECK(s.spin_accel == Approx(2.0 * mu * kGravity * std::cos(theta) * lever).epsilon(1e-9));
    }
}
