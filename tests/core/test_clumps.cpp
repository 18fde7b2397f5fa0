// SPDX-License-Identifier: MIT
//
// Rigid clumps in the engine (docs/physics/clumps.md): mass properties reaching the
// body, free motion (conservation), an off-centre elastic impact against the rigid-body impulse
// formula, a clump on a slope (sticks / slides with a = g (sin a - mu cos a)), bit-identity of a
// one-pebble clump with the same ball, pebbles of one clump never in contact, release, and the
// time step of a clump in free flight.
#include <catch2/catch.hpp>

#include "talus/clump_mass.hpp"
#include "test_support.hpp"

using namespace talus;
using namespace talus::test;

namespace {

constexpr double kRho = 2600.0;

ClumpDef clumpOf(std::vector<Pebble> pebbles, const Vec2& pos, double density = kRho) {
    ClumpDef d;
    d.pebbles = std::move(pebbles);
    d.pos = pos;
    d.density = density;
    return d;
}

/// Linear and angular momentum (about the origin) of every clump and free ball.
struct Momentum {
    Vec2 p{0.0, 0.0};
    double l = 0.0;
};
Momentum momentumOf(const Model& m) {
    Momentum out;
    for (ClumpId c : m.clumpIds()) {
        const double mass = m.clumpMass(c);
        out.p += mass * m.clumpVel(c);
        out.l += m.clumpInertia(c) * m.clumpSpin(c) + mass * cross(m.clumpPos(c), m.clumpVel(c));
    }
    for (BallId b : m.ballIds()) {
        const double mass = m.ballMass(b);
        out.p += mass * m.ballVel(b);
        out.l += m.ballInertia(b) * m.ballSpin(b) + mass * cross(m.ballPos(b), m.ballVel(b));
    }
    return out;
}

}  // namespace

TEST_CASE("clump mass properties reach the body", "[core][clumps]") {
    // Three overlapping pebbles (table 3.6 row of spacing R): the body's mass and inertia are
    // the module's union values times the density, to round-off (1e-12); a template placed at
    // scale 2 has 4x the mass and 16x the inertia (the same numbers scaled, 1e-12).
    const double R = 0.1;
    const std::vector<Pebble> peb = {{Vec2(-R, 0.0), R}, {Vec2(0.0, 0.0), R}, {Vec2(R, 0.0), R}};
    Model m;
    const ClumpId c = m.createClump(clumpOf(peb, Vec2(1.0, 2.0)));
    const MassProps u = unionMassProps(peb);
    CHECK(m.clumpMass(c) == Approx(kRho * u.area).epsilon(1e-12));
    CHECK(m.clumpInertia(c) == Approx(kRho * u.polar_moment).epsilon(1e-12));
    CHECK((m.clumpPos(c) - Vec2(1.0, 2.0)).norm() < 1e-15);
    CHECK(m.clumpCount() == 1);
    CHECK(m.ballCount() == 0);  // pebbles are not balls to the user
    CHECK(m.ballIds().empty());

    const int t = m.defineClumpTemplate(peb);
    ClumpDef d;
    d.template_id = t;
    d.pos = Vec2(5.0, 0.0);
    d.scale = 2.0;
    d.angle = 0.3;
    d.density = kRho;
    const ClumpId c2 = m.createClump(d);
    CHECK(m.clumpMass(c2) == Approx(4.0 * kRho * u.area).epsilon(1e-12));
    CHECK(m.clumpInertia(c2) == Approx(16.0 * kRho * u.polar_moment).epsilon(1e-12));
    const auto pw = m.clumpPebbles(c2);
    REQUIRE(pw.size() == 3);
    CHECK((pw[2].pos - (Vec2(5.0, 0.0) + 2.0 * R * Vec2(std::cos(0.3), std::sin(0.3)))).norm() <
          1e-14);
    CHECK(pw[2].radius == Approx(2.0 * R).epsilon(1e-15));

    // Plain sum (PFC 3.x) and direct modes.
    ClumpDef ds = clumpOf(peb, Vec2(0.0, 0.0));
    ds.mass_mode = ClumpMassMode::PlainSum;
    const MassProps sp = sumMassProps(peb);
    CHECK(m.clumpMass(m.createClump(ds)) == Approx(kRho * sp.area).epsilon(1e-12));
    ClumpDef dd = clumpOf(peb, Vec2(0.0, 5.0), kNotSet);
    dd.mass = 7.0;
    dd.inertia = 0.5;
    const ClumpId c3 = m.createClump(dd);
    CHECK(m.clumpMass(c3) == 7.0);
    CHECK(m.clumpInertia(c3) == 0.5);

    // Bad input.
    CHECK_THROWS_WITH(m.createClump(clumpOf({}, Vec2(0.0, 0.0))),
                      Catch::Contains("at least one pebble"));
    CHECK_THROWS_WITH(m.createClump(clumpOf({{Vec2(0.0, 0.0), -1.0}}, Vec2(0.0, 0.0))),
                      Catch::Contains("pebble 1 radius"));
    CHECK_THROWS_WITH(m.createClump(clumpOf(peb, Vec2(0.0, 0.0), 0.0)), Catch::Contains("density"));
    m.deleteClump(c3);
    CHECK_THROWS_WITH(m.clumpPos(c3), Catch::Contains("was deleted (stale id)"));
    ModelDef sphere;
    sphere.mass_mode = MassMode::Sphere;
    Model ms(sphere);
    CHECK_THROWS_WITH(ms.createClump(clumpOf(peb, Vec2(0.0, 0.0))),
                      Catch::Contains("union of spheres"));
}

TEST_CASE("free clump: momentum, angular momentum and energy conserved", "[core][clumps]") {
    // No contacts, no gravity: the centroid moves at constant velocity and the clump spins at
    // constant rate; linear and angular momentum are conserved to round-off (relative 1e-12
    // after 2000 steps), the energy balance closes to round-off (1e-12 of the kinetic energy),
    // and the pebbles stay at their body-frame offsets (rigid to 1e-12 m).
    Model m;
    const double R = 0.1;
    const ClumpId c = m.createClump([&] {
        ClumpDef d = clumpOf(
            {{Vec2(-R, 0.0), R}, {Vec2(0.5 * R, 0.0), 0.7 * R}, {Vec2(0.0, 1.2 * R), 0.5 * R}},
            Vec2(0.0, 0.0));
        d.vel = Vec2(1.0, -0.5);
        d.spin = 3.0;
        return d;
    }());
    m.setEnergyTracing(true);  // after creation: initial_kinetic holds the clump's energy
    const Momentum m0 = momentumOf(m);
    const auto p0 = m.clumpPebbles(c);
    const double d01 = (p0[0].pos - p0[1].pos).norm();
    m.cycle(2000);
    const Momentum m1 = momentumOf(m);
    CHECK((m1.p - m0.p).norm() <= 1e-12 * m0.p.norm());
    CHECK(std::fabs(m1.l - m0.l) <= 1e-12 * std::fabs(m0.l) + 1e-12 * m0.p.norm());
    const EnergyTotals e = m.energies();
    report("free clump: t %.4g s, dt %.3g s, balance error %.3g J of %.6g J\n", m.time(),
           m.lastTimestep(), e.balanceError(), e.kinetic);
    CHECK(std::fabs(e.balanceError()) <= 1e-12 * e.kinetic);
    CHECK(m.clumpAngle(c) == Approx(3.0 * m.time()).epsilon(1e-12));
    const auto p1 = m.clumpPebbles(c);
    CHECK(std::fabs((p1[0].pos - p1[1].pos).norm() - d01) < 1e-12);
    // Free flight takes the large steps a ball takes: here only the kinematic rule limits it.
    CHECK(m.lastStepRule() != StepRule::Stability);
}

TEST_CASE("free fall of a clump: body work equals kinetic energy", "[core][clumps]") {
    // Central differences integrate free flight exactly for any step sequence: the balance
    // closes to round-off (1e-12 relative) and the centroid follows x0 + v0 t + g t^2/2.
    Model m(ModelDef{Vec2(0.0, -9.81)});
    m.setEnergyTracing(true);
    const ClumpId c =
        m.createClump(clumpOf({{Vec2(0.0, 0.0), 0.1}, {Vec2(0.15, 0.0), 0.1}}, Vec2(0.0, 10.0)));
    m.solveTime(1.0);
    const EnergyTotals e = m.energies();
    CHECK(std::fabs(e.balanceError()) <= 1e-12 * e.kinetic);
    CHECK(e.body == Approx(e.kinetic).epsilon(1e-12));
    CHECK(m.clumpPos(c).y() == Approx(10.0 - 0.5 * 9.81).epsilon(1e-12));
}

TEST_CASE("pebbles of one clump never contact each other", "[core][clumps]") {
    // Heavily overlapping pebbles with a contact model: no pair, no force, no motion.
    auto m = makeModel(Vec2::Zero(), linearProps(1e7));
    const ClumpId c = m->createClump(clumpOf(
        {{Vec2(0.0, 0.0), 0.1}, {Vec2(0.05, 0.0), 0.1}, {Vec2(0.0, 0.05), 0.08}}, Vec2(0.0, 0.0)));
    m->cycle(100);
    CHECK(m->contactCount(false) == 0);
    CHECK(m->clumpForce(c).norm() == 0.0);
    CHECK(m->clumpVel(c).norm() == 0.0);
}

TEST_CASE("one-pebble clump moves bit for bit as the same ball", "[core][clumps]") {
    // A disk thrown spinning onto a frictional slope (gravity tilted): it bounces, then slides
    // and rolls. The ball and the clump of one pebble at its centroid must give identical
    // trajectories (==) at every step, with and without energy tracing and local damping.
    for (int variant = 0; variant < 3; ++variant) {
        auto run = [&](bool as_clump, std::vector<double>& trace) {
            const double a = 20.0 * M_PI / 180.0;
            auto m = makeModel(9.81 * Vec2(std::sin(a), -std::cos(a)),
                               linearProps(1e7, 5e6, 0.3, 0.2, 0.1));
            if (variant == 2) m->damping().local = 0.1;
            m->createWall(wallOf({Vec2(-10.0, 0.0), Vec2(10.0, 0.0)}));
            const Vec2 pos(0.0, 0.3), vel(0.5, -1.0);
            const double r = 0.1, spin = -4.0;
            std::function<void()> sample;
            if (as_clump) {
                ClumpDef d = clumpOf({{Vec2(0.0, 0.0), r}}, pos);
                d.vel = vel;
                d.spin = spin;
                const ClumpId c = m->createClump(d);
                sample = [&trace, mp = m.get(), c] {
                    const Vec2 x = mp->clumpPos(c), v = mp->clumpVel(c);
                    trace.insert(trace.end(), {x.x(), x.y(), v.x(), v.y(), mp->clumpSpin(c),
                                               mp->clumpAngle(c), mp->lastTimestep()});
                };
            } else {
                BallDef bd = ballAt(pos, r, kRho, vel);
                bd.spin = spin;
                const BallId b = m->createBall(bd);
                sample = [&trace, mp = m.get(), b] {
                    const Vec2 x = mp->ballPos(b), v = mp->ballVel(b);
                    trace.insert(trace.end(), {x.x(), x.y(), v.x(), v.y(), mp->ballSpin(b),
                                               mp->ballAngle(b), mp->lastTimestep()});
                };
            }
            if (variant == 1) m->setEnergyTracing(true);
            for (int i = 0; i < 3000; ++i) {
                m->cycle(1);
                sample();
            }
            return m->contactCount() > 0;
        };
        std::vector<double> tb, tc;
        const bool touching = run(false, tb);
        run(true, tc);
        INFO("variant " << variant);
        CHECK(touching);  // the scene reached the sliding/rolling phase
        REQUIRE(tb.size() == tc.size());
        std::size_t first_diff = tb.size();
        for (std::size_t i = 0; i < tb.size() && first_diff == tb.size(); ++i)
            if (!(tb[i] == tc[i])) first_diff = i;
        INFO("first difference at sample " << first_diff / 7 << " field " << first_diff % 7);
        CHECK(first_diff == tb.size());
    }
}

namespace {

/// Off-centre elastic impact of a two-pebble clump on a horizontal frictionless wall, fixed step
/// dt = T* / steps_per_contact (T* the half period with the true effective mass at the contact
/// point). Returns the relative errors of the linear and angular velocity changes against the
/// rigid-body impulse formula.
std::pair<double, double> offCentreImpact(double steps_per_contact, double phase) {
    // Pebble A (r 0.15) hits; B (r 0.1) sits on the same horizontal line through the centroid,
    // so A's arm about the centroid is horizontal: it changes only to second order in the
    // rotation during the contact ((w T)^2 ~ 1e-6 at kn = 1e11), and B (bottom 0.05 m higher)
    // stays clear.
    const double kn = 1e11;
    auto m = makeModel(Vec2::Zero(), linearProps(kn));
    const double ra = 0.15, rb = 0.1;
    ClumpDef d;
    d.pebbles = {{Vec2(0.0, 0.0), ra}, {Vec2(0.35, 0.0), rb}};
    d.density = kRho;
    d.vel = Vec2(0.0, -1.0);
    const ClumpId c = m->createClump(d);  // world frame: A's centre at the origin
    // (the wall after the clump: a pebble is not placed through a wall, api/walls.cpp; the clump
    // is moved above it below)
    m->createWall(wallOf({Vec2(-2.0, 0.0), Vec2(2.0, 0.0)}));
    const double mass = m->clumpMass(c), inertia = m->clumpInertia(c);
    const Vec2 xc = m->clumpPos(c);

    // Rigid-body impulse (e = 1): contact point P below A's centre, normal n = +y;
    // rho = P - x_c, rho x n = rho_x; v_n = v_y + w rho_x = -1.
    const double rho_x = -xc.x();
    const double inv_m_eff = 1.0 / mass + rho_x * rho_x / inertia;
    const double J = 2.0 * 1.0 / inv_m_eff;
    const double dv_exact = J / mass, dw_exact = rho_x * J / inertia;
    const double T = M_PI * std::sqrt(1.0 / (inv_m_eff * kn));
    m->timestep() = fixedStep(T / steps_per_contact);
    // A's bottom 0.1 mm above the wall plus `phase` of a step's travel: where within a step the
    // contact begins (the restitution error of a discrete impact depends on it).
    m->setClumpPos(c, xc + Vec2(0.0, ra + 1e-4 + phase * T / steps_per_contact));
    bool touched = false;
    for (int i = 0; i < 100000; ++i) {
        m->cycle(1);
        const bool now = m->contactCount() > 0 && m->contacts().front().overlap > 0.0;
        if (now) touched = true;
        if (touched && !now) break;
    }
    REQUIRE(touched);
    const double ev = std::fabs((m->clumpVel(c).y() + 1.0) - dv_exact) / std::fabs(dv_exact);
    const double ew = std::fabs(m->clumpSpin(c) - dw_exact) / std::fabs(dw_exact);
    return {ev, ew};
}

}  // namespace

TEST_CASE("off-centre impact: rigid-body impulse, converging with the step", "[core][clumps]") {
    // The impulse formula is the limit of a stiff elastic contact resolved finely. The error of
    // a discrete impact depends on where within a step the contact begins, so each step size is
    // run at four onset phases and the largest error counts. Central differences give a
    // restitution error of order (dt/T)^2 (measured: 0.53 (dt/T)^2 at 20, 40 and 80 steps per
    // contact), so at 20 steps it must be below 2e-3 = 0.8 (1/20)^2, and halving the step must
    // shrink it by a factor >= 3 (second order: 4).
    auto worst = [](double n) {
        double ev = 0.0, ew = 0.0;
        for (double phase : {0.0, 0.25, 0.5, 0.75}) {
            const auto [v, w] = offCentreImpact(n, phase);
            ev = std::max(ev, v), ew = std::max(ew, w);
        }
        return std::make_pair(ev, ew);
    };
    const auto [ev20, ew20] = worst(20.0);
    const auto [ev40, ew40] = worst(40.0);
    report(
        "off-centre impact, worst of 4 onset phases: dv error %.3g (20 steps/contact) %.3g "
        "(40), ratio %.2f; dw error %.3g / %.3g, ratio %.2f\n",
        ev20, ev40, ev20 / ev40, ew20, ew40, ew20 / ew40);
    if (reportOn()) {
        const auto [ev80, ew80] = worst(80.0);
        report("  80 steps/contact: dv error %.3g, dw error %.3g\n", ev80, ew80);
    }
    CHECK(ev20 < 2e-3);
    CHECK(ew20 < 2e-3);
    CHECK(ev40 < ev20 / 3.0);
    CHECK(ew40 < ew20 / 3.0);
}

namespace {

/// A two-pebble clump on a frictional wall with gravity tilted by `slope` (the same as a
/// slope): returns the displacement along the slope and the acceleration measured between
/// t = 0.5 s and 1.5 s.
std::pair<double, double> onSlope(double slope, double mu) {
    const double r = 0.1, kn = 1e8, ks = 1e8, g = 9.81;
    // Normal dashpot (dp_nratio 0.3) settles the start; no shear dashpot, so a sliding contact
    // carries exactly fric * Fn.
    auto m = makeModel(g * Vec2(std::sin(slope), -std::cos(slope)), linearProps(kn, ks, mu, 0.3));
    m->createWall(wallOf({Vec2(-50.0, 0.0), Vec2(50.0, 0.0)}));
    ClumpDef d = clumpOf({{Vec2(-0.15, 0.0), r}, {Vec2(0.15, 0.0), r}}, Vec2::Zero());
    const double mass = kRho * 2.0 * M_PI * r * r;
    d.pos = Vec2(0.0, r - 0.5 * mass * g * std::cos(slope) / kn);  // static overlap
    const ClumpId c = m->createClump(d);
    m->solveTime(0.5);
    const double x1 = m->clumpPos(c).x(), v1 = m->clumpVel(c).x(), t1 = m->time();
    m->solveTime(1.0);
    const double v2 = m->clumpVel(c).x(), t2 = m->time();
    // Velocities are at half steps: both half a step before their times, and solveTime keeps
    // the step equal here (no rule changes), so the difference quotient is exact for constant
    // acceleration.
    return {m->clumpPos(c).x() - x1, (v2 - v1) / (t2 - t1)};
}

}  // namespace

TEST_CASE("clump on a slope: sticks below, slides above the friction angle", "[core][clumps]") {
    const double g = 9.81;
    {
        // 10 degrees, mu 0.5 (friction angle 26.6 degrees): sticks. It may creep no more than
        // the elastic shear stretch m g sin(a) / (2 ks) of its two contacts (~1.4e-5 m).
        const double a = 10.0 * M_PI / 180.0;
        const auto [dx, acc] = onSlope(a, 0.5);
        const double stretch = kRho * 2.0 * M_PI * 0.01 * g * std::sin(a) / (2.0 * 1e8);
        report("slope 10 deg, mu 0.5: moved %.3g m in 1 s (shear stretch %.3g m)\n", dx, stretch);
        CHECK(std::fabs(dx) < stretch);
        CHECK(std::fabs(acc) < 1e-3 * g);
    }
    {
        // 30 degrees, mu 0.3: slides with a = g (sin a - mu cos a). Tolerance 1e-4 relative:
        // the normal oscillation of the start has decayed (dp_nratio 0.3, period ~3 ms, 500
        // periods) and the acceleration of a constant force is integrated exactly.
        const double a = 30.0 * M_PI / 180.0, mu = 0.3;
        const auto [dx, acc] = onSlope(a, mu);
        const double exact = g * (std::sin(a) - mu * std::cos(a));
        report("slope 30 deg, mu 0.3: a = %.9g, exact %.9g, rel. error %.3g\n", acc, exact,
               std::fabs(acc / exact - 1.0));
        CHECK(dx > 0.0);
        CHECK(acc == Approx(exact).epsilon(1e-4));
    }
}

TEST_CASE("release: pebbles become balls, momentum conserved", "[core][clumps]") {
    // Non-overlapping pebbles (union = sum of disks): the balls' total linear and angular
    // momentum equals the clump's to round-off (1e-12).
    Model m;
    ClumpDef d = clumpOf({{Vec2(-0.2, 0.0), 0.1}, {Vec2(0.2, 0.05), 0.15}}, Vec2(1.0, 1.0));
    d.vel = Vec2(0.3, 0.1);
    d.spin = 2.0;
    const ClumpId c = m.createClump(d);
    m.cycle(10);
    const Momentum before = momentumOf(m);
    const auto balls = m.releaseClump(c);
    CHECK(balls.size() == 2);
    CHECK(m.clumpCount() == 0);
    CHECK(m.ballCount() == 2);
    const Momentum after = momentumOf(m);
    CHECK((after.p - before.p).norm() <= 1e-12 * before.p.norm());
    CHECK(std::fabs(after.l - before.l) <= 1e-12 * std::fabs(before.l));
    CHECK(m.ballMass(balls[0]) == Approx(diskMass(kRho, 0.1)).epsilon(1e-15));
    CHECK_FALSE(m.isAlive(c));
}

TEST_CASE("clump time step: large steps in flight, a resolved impact", "[core][clumps]") {
    // A three-pebble clump falls 1 m onto a wall: in flight the step grows far beyond the
    // contact's scale (kinematic rule only), and the impact is resolved in at least
    // `resolution` (30) steps: the time-step rules use a lower bound of the effective mass at an
    // off-centre pebble (docs/physics/clumps.md "Time step"), so the contact, shorter than
    // pi sqrt(m/kn) of the clump's mass, gets at least 30 steps all the same.
    auto m = makeModel(Vec2(0.0, -9.81), linearProps(1e7));
    m->createWall(wallOf({Vec2(-2.0, 0.0), Vec2(2.0, 0.0)}));
    // Turned by 0.4 rad: one pebble hits alone, off the centroid (two simultaneous contacts
    // would add their stiffnesses, which no per-contact rule sees, for balls neither).
    ClumpDef d = clumpOf({{Vec2(-0.1, 0.0), 0.1}, {Vec2(0.1, 0.0), 0.1}, {Vec2(0.0, 0.15), 0.08}},
                         Vec2(0.0, 1.2));
    d.angle = 0.4;
    const ClumpId c = m->createClump(d);
    const double contact_dt = M_PI * std::sqrt(m->clumpMass(c) / 1e7) / 30.0;
    double max_flight_dt = 0.0;
    int steps_in_contact = 0;
    bool touched = false;
    for (int i = 0; i < 200000 && !(touched && m->contactCount() == 0); ++i) {
        m->cycle(1);
        if (m->contactCount() > 0) {
            touched = true;
            ++steps_in_contact;
        } else if (!touched) {
            max_flight_dt = std::max(max_flight_dt, m->lastTimestep());
        }
    }
    report("clump drop: flight step up to %.3g s (contact step %.3g s), %d steps in contact\n",
           max_flight_dt, contact_dt, steps_in_contact);
    REQUIRE(touched);
    CHECK(max_flight_dt > 20.0 * contact_dt);
    CHECK(steps_in_contact >= 30);
}

TEST_CASE("clump from balls: ids, contacts and momentum kept", "[core][clumps]") {
    // Two touching balls (no overlap, so the clump's mass equals theirs) moving apart and
    // spinning become one clump: their mutual pair goes, their momentum and angular momentum
    // are kept (round-off, 1e-12), and a free ball's contact with one of them survives.
    auto m = makeModel(Vec2::Zero(), linearProps(1e6));
    WarningLog log;  // `other` is placed overlapping (a placement warning)
    log.attach(*m);
    const BallId a = m->createBall(ballAt(Vec2(0.0, 0.0), 0.1, kRho, Vec2(-0.1, 0.0)));
    BallDef bd = ballAt(Vec2(0.2, 0.0), 0.1, kRho, Vec2(0.05, 0.3));
    bd.spin = 1.0;
    const BallId b = m->createBall(bd);
    const BallId other = m->createBall(ballAt(Vec2(0.0, 0.199), 0.1, kRho));
    m->cycle(1);
    CHECK(m->contactCount(false) >= 2);
    const Momentum before = momentumOf(*m);
    const ClumpId c = m->createClumpFromBalls({a, b});
    const Momentum after = momentumOf(*m);
    CHECK((after.p - before.p).norm() <= 1e-12 * before.p.norm());
    CHECK(std::fabs(after.l - before.l) <= 1e-12 * std::fabs(before.l));
    CHECK(m->clumpMass(c) == Approx(2.0 * diskMass(kRho, 0.1)).epsilon(1e-12));
    CHECK(m->ballCount() == 1);
    CHECK(m->clumpOf(a) == c);
    for (const ContactInfo& ci : m->contacts(false)) {
        CHECK_FALSE((ci.clump1 == c && ci.clump2 == c));  // no pair inside the clump
    }
    bool kept = false;
    for (const ContactInfo& ci : m->contacts(true))
        kept |= (ci.ball1 == other || ci.ball2 == other) && (ci.clump1 == c || ci.clump2 == c);
    CHECK(kept);
    CHECK_THROWS_WITH(m->deleteBall(a), Catch::Contains("is a pebble of clump"));
    m->cycle(10);
}
