// SPDX-License-Identifier: MIT
//
// Tests of the `hysdamp` contact model (plugins/hysdamp, docs/models/hysdamp.md): loading and
// unloading stiffness k_load = 2 d kn_m/(1+d), k_unload = 2 kn_m/(1+d) (Shimizu & Cundall 2001 as
// cited by An 2006), the bilinear law of Walton & Braun 1986. Closed forms used:
//   e = sqrt(d)                  no tension (Walton & Braun 1986)
//   e = sqrt(d - (1-d)^2)        tension branch of slope k_load below u0 (docs/models/hysdamp.md:
//                                the bodies also climb out of it, losing (1/2) k_load u0^2)
//   u0 = (1 - d) u_max           residual overlap; force duration (pi/2)(1/w_load + 1/w_unload)
//                                (+ asin((1-d)/sqrt d)/w_load with tension)
// Tolerances: the law is piecewise linear, and the model pays the impulse central differences
// miss at each corner (touch, u0, separation), so the restitution converges fast: measured worst
// over random phases at the default step (30 steps per pi sqrt(m*/k_unload)) 7e-6 without and
// 7e-5 with tension (d = 0.4, where e = 0.2 is small); bounds 5e-5 and 3e-4.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "contact_law_support.hpp"

using namespace talus;
using namespace talus::lawtest;
using Catch::Matchers::Contains;

namespace {

constexpr double kKnm = 1e8, kR = 0.1, kRho = 2600.0;

std::vector<PropValue> hdProps(double d, bool tension, double ks = 0.0, double fric = 0.0) {
    return {{"kn_m", kKnm}, {"d", d}, {"tension", tension ? 1.0 : 0.0}, {"ks", ks}, {"fric", fric}};
}
double kLoad(double d) { return 2.0 * d * kKnm / (1.0 + d); }
double kUnload(double d) { return 2.0 * kKnm / (1.0 + d); }

/// One free impact of the rig's standard disk on a wall, with a random phase of first touch.
ImpactResult impact(double d, bool tension, double v0, Rng& rng, double resolution = 30.0) {
    ImpactSetup s;
    s.model = "hysdamp";
    s.props = hdProps(d, tension);
    s.normal_speed = v0;
    s.timestep.resolution = resolution;
    const double m = diskMass(kRho, kR);
    s.gap = v0 * M_PI * std::sqrt(m / kUnload(d)) / resolution * rng.uniform(1.0, 40.0);
    return runImpact(s);
}

}  // namespace

TEST_CASE("hysdamp: restitution is sqrt(d) without tension, at any speed", "[hysdamp]") {
    Rng rng(21);
    Stats err;
    for (double d : {0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 1.0})
        for (double v0 : {0.1, 1.0, 10.0})
            for (int i = 0; i < 3; ++i) {
                const ImpactResult r = impact(d, false, v0, rng);
                REQUIRE(r.separated);
                err.add((r.restitution - hysdampRestitution(d, false)) /
                        hysdampRestitution(d, false));
            }
    INFO("worst relative error " << err.worst << ", mean " << err.mean());
    CHECK(err.worst < 5e-5);
}

TEST_CASE("hysdamp: restitution with tension is sqrt(d - (1-d)^2), at any speed", "[hysdamp]") {
    Rng rng(22);
    Stats err;
    for (double d : {0.4, 0.5, 0.6, 0.8, 1.0})
        for (double v0 : {0.1, 1.0, 10.0})
            for (int i = 0; i < 3; ++i) {
                const ImpactResult r = impact(d, true, v0, rng);
                REQUIRE(r.separated);
                err.add((r.restitution - hysdampRestitution(d, true)) /
                        hysdampRestitution(d, true));
            }
    INFO("worst relative error " << err.worst << ", mean " << err.mean());
    CHECK(err.worst < 3e-4);
    // Tension costs energy: below sqrt(d) for every d < 1.
    Rng rng2(23);
    CHECK(impact(0.7, true, 1.0, rng2).restitution < std::sqrt(0.7) - 0.05);
}

TEST_CASE("hysdamp: peak force, overlap and force duration follow the bilinear law", "[hysdamp]") {
    const double m = diskMass(kRho, kR), v0 = 2.0;
    Rng rng(5);
    for (bool tension : {false, true})
        for (double d : {0.4, 0.8}) {
            const double k1 = kLoad(d), k2 = kUnload(d);
            const double umax = v0 * std::sqrt(m / k1);
            double t_force = 0.5 * M_PI * (std::sqrt(m / k1) + std::sqrt(m / k2));
            if (tension) t_force += std::asin((1.0 - d) / std::sqrt(d)) * std::sqrt(m / k1);
            const ImpactResult r = impact(d, tension, v0, rng);
            // Sampled peaks: low by at most 1 - cos(pi/60) = 1.4e-3 (30 steps per half period).
            CHECK(r.max_overlap == Approx(umax).epsilon(1.5e-3));
            CHECK(r.peak_force == Approx(k1 * umax).epsilon(1.5e-3));
            // The rig ends the force by interpolating between the last step with force and the
            // first without; the step that passes u0 carries the corner impulse (a small
            // positive force), so the measured end lies up to two steps late.
            if (!tension) {
                CHECK(r.force_duration >= t_force * (1.0 - 1e-3));
                CHECK(r.force_duration <= t_force * (1.0 + 1e-3) + 2.0 * r.timestep);
            }
            // ContactDuration reports the time the force acts (what needs resolving).
            LawDriver drv("hysdamp", hdProps(d, tension), false, kR, 0.0, m);
            CHECK(drv.clone()->ContactDuration(m, v0) == Approx(t_force).epsilon(1e-12));
        }
}

TEST_CASE("hysdamp: the time step follows the unloading stiffness", "[hysdamp][timestep]") {
    // knest = k_unload (the larger): the resolution rule's bound pi sqrt(m*/knest)/N and the
    // stability rule safety sqrt(m/k) both use it.
    const double d = 0.2, m = diskMass(kRho, kR);
    DriveSetup ds;
    ds.model = "hysdamp";
    ds.props = hdProps(d, false, 3e7);
    ds.overlap = {1e-5, 2e-5, 1e-5};
    const DriveResult dr = driveContact(ds);
    for (double k : dr.knest) CHECK(k == Approx(kUnload(d)).epsilon(1e-15));
    LawDriver drv("hysdamp", hdProps(d, false, 3e7), false, kR, 0.0, m);
    CHECK(drv.clone()->KnEstimate() == Approx(kUnload(d)).epsilon(1e-15));  // before touch too
    CHECK(drv.clone()->KsEstimate() == 3e7);

    Rng rng(9);
    const ImpactResult res = impact(d, false, 1.0, rng, 30.0);
    CHECK(res.timestep <= M_PI * std::sqrt(m / kUnload(d)) / 30.0 * (1.0 + 1e-12));
    ImpactSetup s;
    s.model = "hysdamp";
    s.props = hdProps(d, false);
    s.timestep.resolution = 0;  // stability rule only
    s.timestep.safety = 0.1;
    const ImpactResult st = runImpact(s);
    CHECK(st.timestep == Approx(0.1 * std::sqrt(m / kUnload(d))).epsilon(1e-9));
    CHECK(st.restitution == Approx(std::sqrt(d)).epsilon(2e-4));
}

TEST_CASE(
    "hysdamp: driveContact loop: loading, unloading through u0, reloading to the loading "
    "line",
    "[hysdamp][drive]") {
    const double d = 0.5, k1 = kLoad(d), k2 = kUnload(d);
    for (bool tension : {false, true}) {
        DriveSetup s;
        s.model = "hysdamp";
        s.props = hdProps(d, tension);
        s.dt = 1e-6;
        // 0 -> 1e-4 (load), -> 2e-5 (unload below u0 = 5e-5), -> 1.5e-4 (reload past u_max).
        std::vector<double> path;
        for (int i = 1; i <= 100; ++i) path.push_back(1e-4 * i / 100);
        for (int i = 1; i <= 80; ++i) path.push_back(1e-4 - 8e-5 * i / 80);
        for (int i = 1; i <= 130; ++i) path.push_back(2e-5 + 1.3e-4 * i / 130);
        s.overlap = path;
        const DriveResult r = driveContact(s);
        const double u0 = (1.0 - d) * 1e-4;
        for (std::size_t i = 0; i < path.size(); ++i) {
            const double u = path[i];
            double f;
            if (i < 100) {
                f = k1 * u;  // loading line
            } else if (i < 180 || u <= 1e-4) {
                f = k2 * (u - u0);  // unloading / reloading line through u0
                if (f < 0.0) f = tension ? k1 * (u - u0) : 0.0;
            } else {
                f = k1 * u;  // back on the loading line past u_max
            }
            // The law itself, away from the corners (where the applied force carries the
            // corner impulse of central differences, a different quantity).
            const bool corner_step = (i > 0 && ((path[i - 1] > u0) != (u > u0))) ||
                                     (i > 180 && (path[i - 1] < 1e-4) != (u < 1e-4)) || i == 0;
            if (!corner_step) {
                INFO("sample " << i << " u " << u);
                CHECK(r.trace[i].normal_force == Approx(f).epsilon(1e-9).margin(1e-9));
            }
        }
    }
}

TEST_CASE("hysdamp: the residual overlap does not drift over repeated cycles", "[hysdamp][drive]") {
    // Seed digest section 4: an incremental hysteretic law moves the zero-force overlap inward
    // on every cycle. Here u0 = (1 - d) u_max depends on the largest overlap only: the loops of
    // a repeated cycle coincide, u0 stays in [0, u_max), and a new touch starts from u0 = 0.
    for (bool tension : {false, true}) {
        const double d = tension ? 0.6 : 0.3, k2 = kUnload(d);
        DriveSetup s;
        s.model = "hysdamp";
        s.props = hdProps(d, tension);
        s.dt = 1e-6;
        const int per = 64, cycles = 200;
        const double hi = 1e-4, lo = 0.2e-4;
        for (int c = 0; c < cycles; ++c)
            for (int i = 0; i < per; ++i)
                s.overlap.push_back(lo + (hi - lo) * 0.5 * (1.0 + std::cos(2.0 * M_PI * i / per)));
        const DriveResult r = driveContact(s);
        const double u0 = (1.0 - d) * hi;
        // Same force at the same point of every cycle after the first.
        for (int i = 0; i < per; ++i) {
            const double f1 = r.trace[per + i].normal_force;
            const double fn = r.trace[(cycles - 1) * per + i].normal_force;
            CHECK(fn == f1);
        }
        // The zero-force overlap read off the unloading line, u - F/k_unload, on every
        // unloading sample with F > 0: always u0.
        Stats drift;
        for (std::size_t i = per; i < r.trace.size(); ++i) {
            const double u = r.trace[i].overlap, f = r.trace[i].normal_force;
            const double u_prev = r.trace[i - 1].overlap;
            // Unloading samples above u0 whose step did not pass a corner (a corner step's
            // applied force carries the corner impulse of central differences).
            if (u < u_prev && u > u0 && u_prev > u0 && u < hi * (1.0 - 1e-9))
                drift.add((u - f / k2 - u0) / u0);
        }
        CHECK(drift.n > 100);
        CHECK(drift.worst < 1e-9);

        // Growing amplitude: u0 follows (1-d) u_max, never above the largest overlap.
        LawDriver drv("hysdamp", hdProps(d, tension), false, kR, 0.0, 50.0);
        ContactModel* c = drv.clone();
        const int iu0 = 8, iumax = 7;  // hd_u0 and hd_umax in the property table
        REQUIRE(std::string(c->PropInfoAt(iu0)->name) == "hd_u0");
        REQUIRE(std::string(c->PropInfoAt(iumax)->name) == "hd_umax");
        FdBlock fd{};
        bool have = false;
        double u_prev = 0.0, largest = 0.0;
        for (int k = 0; k < 50; ++k) {
            const double peak = 1e-5 * (1 + k), valley = 0.3 * peak;
            for (double u : {peak, valley}) {
                FdBlock next = drv.block(u, (u - u_prev) / 1e-6, 0.0, 1e-6, have ? &fd : nullptr);
                c->FDlaw(next);
                fd = next, have = true, u_prev = u;
                largest = std::max(largest, u);
                // u_max is the largest sample, raised at a turn by the parabola through the
                // last two half-step rates: at most (v_before - v_after) dt / 8, here
                // 1.7 peak / 8 (this drive turns abruptly).
                const double res = c->ReturnProp(iu0);
                CHECK(res >= 0.0);
                CHECK(res < c->ReturnProp(iumax));
                CHECK(res >= (1.0 - d) * largest * (1.0 - 1e-12));
                CHECK(res <= (1.0 - d) * (largest + 1.7 * peak / 8.0));
            }
        }
        // Separation: the engine and driveContact clone a fresh object for the next touch, so
        // the next loading starts on the loading line from zero.
        DriveSetup t;
        t.model = "hysdamp";
        t.props = hdProps(d, tension);
        // Touch half a step before the sample: the onset corner impulse (frac - 1/2)^2 is zero.
        t.overlap = {1e-4, 5e-5, -2e-5, 2e-5};
        const DriveResult q = driveContact(t);
        CHECK(q.trace[3].normal_force == Approx(kLoad(d) * 2e-5).epsilon(1e-12));
    }
}

TEST_CASE("hysdamp: every contact keeps its own state (no shared turning points)", "[hysdamp]") {
    // An's (2006) UDM kept turning points in static variables (An 2006). Two
    // impacts at different speeds in one model, simultaneously: each residual overlap must
    // belong to its own maximum overlap.
    Model m;
    m.setDefaultContactModel("hysdamp", hdProps(0.5, false));
    WallDef w;
    w.points = {Vec2(-5.0, 0.0), Vec2(5.0, 0.0)};
    m.createWall(w);
    BallDef a;
    a.radius = kR;
    a.density = kRho;
    a.pos = Vec2(-1.0, kR + 1e-4);
    a.vel = Vec2(0.0, -0.5);
    BallDef b = a;
    b.pos = Vec2(1.0, kR + 1e-4);
    b.vel = Vec2(0.0, -3.0);
    const BallId ia = m.createBall(a), ib = m.createBall(b);
    double umax[2] = {0.0, 0.0}, u0[2] = {0.0, 0.0};
    for (int i = 0; i < 4000; ++i) {
        m.cycle(1);
        for (const ContactInfo& c : m.contacts()) {
            const int k = c.ball1 == ia ? 0 : 1;
            umax[k] = std::max(umax[k], m.contactProp(c.key, "hd_umax"));
            u0[k] = m.contactProp(c.key, "hd_u0");
        }
    }
    const double mass = diskMass(kRho, kR), k1 = kLoad(0.5);
    CHECK(umax[0] == Approx(0.5 * std::sqrt(mass / k1)).epsilon(2e-3));
    CHECK(umax[1] == Approx(3.0 * std::sqrt(mass / k1)).epsilon(2e-3));
    CHECK(u0[0] == Approx(0.5 * umax[0]).epsilon(1e-12));
    CHECK(u0[1] == Approx(0.5 * umax[1]).epsilon(1e-12));
    CHECK(m.ballVel(ia).y() == Approx(0.5 * std::sqrt(0.5)).epsilon(1e-4));
    CHECK(m.ballVel(ib).y() == Approx(3.0 * std::sqrt(0.5)).epsilon(1e-4));
}

TEST_CASE("hysdamp: plastic work is the energy an impact loses, and the books close",
          "[hysdamp][energy]") {
    // A ball on a wall, run until the contact has ended and the closing impulse is applied (the
    // energy snapshot is taken at the start of a step, so a few steps more).
    for (bool tension : {false, true})
        for (double d : {0.4, 0.9})
            for (double vt : {0.0, 1.0}) {
                Model m;
                m.setDefaultContactModel("hysdamp", hdProps(d, tension, 5e7, 0.3));
                WallDef w;
                w.points = {Vec2(-5.0, 0.0), Vec2(5.0, 0.0)};
                m.createWall(w);
                BallDef b;
                b.radius = kR;
                b.density = kRho;
                b.pos = Vec2(0.0, kR + 1e-4);
                b.vel = Vec2(vt, -2.0);
                const BallId ball = m.createBall(b);
                m.setEnergyTracing(true);
                bool touched = false;
                for (int i = 0; i < 100000 && !(touched && m.contactCount() == 0); ++i) {
                    m.cycle(1);
                    touched = touched || m.contactCount() > 0;
                }
                m.cycle(3);
                const EnergyTotals e = m.energies();
                const double mass = m.ballMass(ball);
                const double en = hysdampRestitution(d, tension);
                const double loss_n = 0.5 * mass * 4.0 * (1.0 - en * en);
                INFO("tension " << tension << " d " << d << " vt " << vt << ": plastic "
                                << e.plastic << " vs " << loss_n << ", residual "
                                << e.balanceError());
                CHECK(m.ballVel(ball).y() == Approx(2.0 * en).epsilon(3e-4));
                CHECK(e.plastic == Approx(loss_n).epsilon(3e-4));
                // The normal books close exactly (trapezoidal plastic work); what remains with
                // sliding is the engine's O(dt^2) residual of a sliding contact (the linear
                // model shows 4e-4 in the same scene).
                if (vt == 0.0) CHECK(std::fabs(e.balanceError()) < 1e-9 * e.initial_kinetic);
                if (vt != 0.0) CHECK(e.slip > 0.0);
                CHECK(std::fabs(e.balanceError()) < 5e-4 * e.initial_kinetic);
            }
}

TEST_CASE("hysdamp: range errors cite the rule for each tension mode", "[hysdamp][props]") {
    const std::string with = modelError("hysdamp", {{"kn_m", 1e8}, {"d", 0.3}, {"tension", 1}});
    CHECK_THAT(with, Contains("'d' must be in [0.4, 1] when tension = 1") &&
                         Contains("hysteretic damping as An (2006) gives it") &&
                         Contains("got 0.3"));
    // The message cites the source by author and year (not a file of the project's own notes).
    CHECK_THAT(with, !Contains("digest") && !Contains("section 4"));
    const std::string without = modelError("hysdamp", {{"kn_m", 1e8}, {"d", 0.04}});
    CHECK_THAT(without, Contains("'d' must be in [0.05, 1]") && Contains("without tension") &&
                            Contains("hysteretic damping as An (2006) gives it"));
    CHECK_THAT(modelError("hysdamp", {{"d", 1.2}}), Contains("'d' must be in [0.05, 1]"));
    CHECK(modelError("hysdamp", {{"kn_m", 1e8}, {"d", 0.3}, {"tension", 0}}).empty());
    CHECK(modelError("hysdamp", {{"kn_m", 1e8}, {"d", 0.4}, {"tension", 1}}).empty());
    // The order of assignments does not matter: the combination is checked before cycling.
    CHECK_FALSE(modelError("hysdamp", {{"tension", 1}, {"d", 0.2}}).empty());
    CHECK_THAT(modelError("hysdamp", {{"tension", 2}}),
               Contains("'tension' must be one of 0 = off, 1 = on"));
    CHECK_THAT(modelError("hysdamp", {{"kn_m", -1.0}}), Contains("'kn_m' must be >= 0"));
    CHECK_THAT(modelError("hysdamp", {{"dee", 0.5}}),
               Contains("unknown property 'dee'") && Contains("kn_m") && Contains("tension"));
    CHECK_THAT(modelError("hysdamp", {{"hd_u0", 0.0}}), Contains("read-only"));
}

TEST_CASE("hysdamp: kn_m, ks and fric are inherited from the ends (PFC rules)",
          "[hysdamp][props]") {
    LawDriver drv("hysdamp", hdProps(0.5, false, 1e7, 0.9), true, kR, kR, 1.0);
    PropBlock pb = drv.propBlock();
    pb.kn[0] = 2e8, pb.kn[1] = 2e8;  // in series: 1e8
    pb.ks[0] = 4e7;                  // one end only: that value
    pb.fric[0] = 0.4, pb.fric[1] = 0.2;
    const ContactModel& proto = drv.prototype();
    std::vector<std::max_align_t> storage(proto.ObjectSize() / sizeof(std::max_align_t) + 1);
    ContactModel* c = proto.Clone(pb, storage.data());
    REQUIRE(c);
    CHECK(c->ReturnProp(0) == Approx(1e8));
    CHECK(c->ReturnProp(2) == 4e7);
    CHECK(c->ReturnProp(3) == 0.2);
    c->Destroy();
}

TEST_CASE("hysdamp: SaveRestore mid-contact continues bit for bit", "[hysdamp][save]") {
    for (bool tension : {false, true}) {
        LawDriver drv("hysdamp", hdProps(0.5, tension, 5e7, 0.3), false, kR, 0.0, 30.0);
        std::vector<double> u, us;
        for (int i = 1; i <= 300; ++i) {
            u.push_back(1e-4 * std::fabs(std::sin(M_PI * i / 100.0)) * (1.0 + i / 300.0) + 1e-7);
            us.push_back(1e-5 * std::sin(M_PI * i / 70.0));
        }
        u.push_back(-1e-6), us.push_back(0.0);
        int compared = 0;
        CHECK(saveRestoreContinuesExactly(drv, u, us, 1e-6, 130, &compared));
        CHECK(compared == static_cast<int>(u.size()) - 130);
    }
}
