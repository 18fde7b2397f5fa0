// SPDX-License-Identifier: MIT
//
// Energy tracing (PFC's energy tracing, docs/physics/energy.md): the balance identity
//   initial_kinetic + body + boundary = kinetic + strain + bond + slip + dashpot + plastic
//                                       + damping + released
// for bounces with dashpots and friction, free-fall body work, PFC local damping (accuracy-
// reference 3.4) and mass-proportional viscous damping.
//
// Time level: energies() is a snapshot at the last whole step the law of motion completed, one
// step behind time(), with KE = (1/2) m v(t - dt/2).v(t + dt/2). So a force computed in the last
// force loop has only half of its impulse in the reported KE; the tests read the energies a few
// steps after the last contact force, in free flight, where nothing is pending.
#include <catch2/catch.hpp>

#include "test_support.hpp"

using namespace talus;
using namespace talus::test;

namespace {

constexpr double kR = 0.05, kRho = 2600.0, kKn = 1e7;

struct Bounce {
    std::vector<PropValue> props;
    Vec2 vel{0.0, -1.0};
    double spin = 0.0;
};

/// One ball-wall impact with tracing on; steps_per_contact = 0: default automatic step, else a
/// fixed step T/(n + u), u random. Returns balance_error / energy in, read in free flight three
/// steps after the contact ended.
double balanceAfterBounce(const Bounce& c, int steps_per_contact, Rng& rng,
                          EnergyTotals* out = nullptr) {
    ModelDef def;
    Model m(def);
    m.setDefaultContactModel("linear", c.props);
    m.createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
    const double T = linearDuration(diskMass(kRho, kR), kKn);
    double dt = T / 30.0;
    if (steps_per_contact > 0) {
        dt = T / (steps_per_contact + rng.uniform());
        m.timestep() = fixedStep(dt);
        m.guard().resolution = GuardAction::Off;
    }
    BallDef bd = ballAt(Vec2(0.0, kR + dt * rng.uniform(1.0, 20.0)), kR, kRho, c.vel);
    bd.spin = c.spin;
    const BallId b = m.createBall(bd);
    m.setEnergyTracing(true);
    const Episode ep = runEpisode(m, b);
    REQUIRE(ep.ended);
    m.cycle(3);
    const EnergyTotals e = m.energies();
    if (out) *out = e;
    return e.balanceError() / e.initial_kinetic;
}

Stats balanceStats(const Bounce& c, int steps_per_contact, int samples, uint64_t seed) {
    Rng rng(seed);
    Stats st;
    for (int i = 0; i < samples; ++i) st.add(balanceAfterBounce(c, steps_per_contact, rng));
    return st;
}

}  // namespace

TEST_CASE("energy balance of a bounce with dashpot and sliding friction", "[core][energy]") {
    // Normal dashpot beta = 0.3 (mode 2: the shear dashpot, beta_s = 0.2, is off while the
    // contact slides), friction 0.1, tangential speed 2 m/s against a normal speed of 1 m/s: the
    // contact slides throughout (V_s = 2 > 3 mu (1 + e) v_n = 0.42), so the shear force is
    // mu F_n and vanishes with it at separation. Every energy term then has a second-order
    // bookkeeping error: the residual must decrease with the step at an observed order >= ~1.8
    // (10% allowance for 20 random phases per step), and be small at the default step. Bound at
    // the default: 2e-3 of the energy in (the fixed-step sweep gives ~1.5e-3 worst at 30 steps
    // per contact; the default step, a whole number of steps per contact, does better).
    const Bounce c{linearProps(kKn, 0.5 * kKn, 0.1, 0.3, 0.2, 2), Vec2(2.0, -1.0), 0.0};
    std::vector<double> h, mean;
    for (int n : {30, 60, 120, 240}) {
        const Stats st = balanceStats(c, n, 20, 100 + n);
        h.push_back(1.0 / (n + 0.5));
        mean.push_back(st.mean());
        report("balance, dashpot + sliding, %d steps/contact: |err|/E_in mean %.3e worst %.3e\n", n,
               st.mean(), st.worst);
    }
    const double p = fittedOrder(h, mean);
    const Stats def = balanceStats(c, 0, 20, 7);
    report("  fitted order %.2f; default step: mean %.3e worst %.3e\n", p, def.mean(), def.worst);
    CHECK(p >= 1.8);
    CHECK(def.worst < 2e-3);
    for (std::size_t i = 0; i + 1 < mean.size(); ++i) CHECK(mean[i + 1] < mean[i]);
}

TEST_CASE("energy balance of a normal bounce in both dashpot modes", "[core][energy]") {
    // Mode 0 converges at second order; mode 1 (no tension) clips the dashpot within a step
    // without weighting the clip instant, which leaves a residual that still decreases but more
    // slowly (measured order ~1.3 between 30 and 240 steps per contact). Requirement: decreasing
    // at every halving, order >= 1.8 (mode 0) / >= 1 (mode 1), and below 3e-3 at the default.
    for (int mode : {0, 1}) {
        const Bounce c{linearProps(kKn, 0.0, 0.0, 0.3, 0.0, mode)};
        std::vector<double> h, mean;
        for (int n : {30, 60, 120, 240}) {
            const Stats st = balanceStats(c, n, 20, 200 + n);
            h.push_back(1.0 / (n + 0.5));
            mean.push_back(st.mean());
        }
        const double p = fittedOrder(h, mean);
        const Stats def = balanceStats(c, 0, 20, 8);
        report(
            "balance, normal dashpot mode %d: mean at 30..240 steps %.2e %.2e %.2e %.2e, order "
            "%.2f; default step mean %.3e worst %.3e\n",
            mode, mean[0], mean[1], mean[2], mean[3], p, def.mean(), def.worst);
        INFO("mode " << mode << " order " << p);
        CHECK(p >= (mode == 0 ? 1.8 : 1.0));
        for (std::size_t i = 0; i + 1 < mean.size(); ++i) CHECK(mean[i + 1] < mean[i]);
        CHECK(def.worst < 3e-3);
    }
}

// A sticking contact that separates while its shear spring is loaded must book the spring's
// energy 1/2 F_s^2 / k_s somewhere (the linear model reports it as slip work when the spring lets
// go; an earlier version dropped it and the balance missed 2.7% of the energy in at every step).
// Requirement: a residual that decreases with the step and is below 1% at the default.
TEST_CASE("energy balance when a loaded shear spring separates", "[core][energy]") {
    const Bounce c{linearProps(kKn, 0.5 * kKn, 1e9), Vec2(0.5, -1.0), 0.0};
    std::vector<double> mean;
    for (int n : {30, 60, 120, 240}) mean.push_back(balanceStats(c, n, 10, 300 + n).mean());
    const Stats def = balanceStats(c, 0, 10, 9);
    report(
        "balance, sticking shear spring: mean at 30..240 steps %.2e %.2e %.2e %.2e; default "
        "%.3e\n",
        mean[0], mean[1], mean[2], mean[3], def.mean());
    CHECK(def.worst < 1e-2);
    CHECK(mean[3] < 0.5 * mean[0]);
}

// runImpact (core/src/impact_rig.cpp) reads energies() one cycle after separation. With the
// product-form kinetic energy (a snapshot one step behind, HEAD 9e13f47) the closing dashpot
// impulse was then only half in the reported KE and the rig's balance had an O(dt) residual
// (beta = 0.3: 2.2e-3 at 30 steps, 1.3e-3 at 60, 5.8e-4 at 120); with KE at the half step it
// converges at second order like the model's. Requirement: order >= 1.8 between 30 and 240
// steps per contact.
TEST_CASE("the impact rig's energies close the balance like the model's", "[core][energy]") {
    Rng rng(12);
    std::vector<double> mean;
    const double T = linearDuration(diskMass(kRho, kR), kKn);
    for (int n : {30, 60, 120, 240}) {
        Stats st;
        for (int i = 0; i < 20; ++i) {
            ImpactSetup s;
            s.props = linearProps(kKn, 0.0, 0.0, 0.3);
            s.radius = kR;
            s.density = kRho;
            const double dt = T / (n + rng.uniform());
            s.timestep = fixedStep(dt);
            s.guard.resolution = GuardAction::Off;
            s.gap = dt * rng.uniform(1.0, 20.0);
            const ImpactResult r = runImpact(s);
            st.add(r.energy.balanceError() / r.energy_in);
        }
        mean.push_back(st.mean());
    }
    report("impact rig balance, dashpot 0.3: mean at 30..240 steps %.2e %.2e %.2e %.2e\n", mean[0],
           mean[1], mean[2], mean[3]);
    const double p = std::log(mean[0] / mean[3]) / std::log(8.0);
    INFO("order " << p);
    CHECK(p >= 1.8);
}

TEST_CASE("free fall: body work equals the kinetic energy gained", "[core][energy]") {
    // Gravity's work is booked with the displacements (velocities) the integrator uses, so with a
    // fixed step the kinetic energy gained between two readings equals the body work booked
    // between them to round-off. The balance residual itself depends on the time level at which
    // the kinetic energy is reported: with KE = (1/2) m v(t - dt/2).v(t + dt/2) (product form)
    // it is the constant (1/8) m |g|^2 dt^2 (the product form is the true KE minus that), with
    // KE at the half step and works as impulse times mean velocity it is zero. Either way
    // |balance_error| <= (1/8) m |g|^2 dt^2 (+ round-off).
    const Vec2 g(1.0, -9.81);
    for (double dt : {1e-4, 1e-3}) {
        ModelDef def;
        def.gravity = g;
        Model m(def);
        m.setDefaultContactModel("linear", linearProps(kKn));
        const BallId b = m.createBall(ballAt(Vec2(0.0, 0.0), kR, kRho, Vec2(3.0, 2.0)));
        m.timestep() = fixedStep(dt);
        m.setEnergyTracing(true);
        const double mass = m.ballMass(b);
        const double eighth = 0.125 * mass * g.squaredNorm() * dt * dt;
        m.cycle(2);
        const EnergyTotals e0 = m.energies();
        double worst_rel = 0.0, worst_resid = 0.0;
        for (int i = 0; i < 50; ++i) {
            m.cycle(20);
            const EnergyTotals e = m.energies();
            const double dbody = e.body - e0.body, dke = e.kinetic - e0.kinetic;
            worst_rel = std::max(worst_rel, std::fabs(dbody - dke) / std::fabs(dke));
            worst_resid = std::max(worst_resid, std::fabs(e.balanceError()));
            // Round-off of sums of ~1000 terms of the size of the kinetic energy.
            CHECK(std::fabs(dbody - dke) <= 1e-12 * e.kinetic);
            CHECK(std::fabs(e.balanceError()) <= eighth * (1.0 + 1e-9) + 1e-12 * e.kinetic);
        }
        report(
            "free fall dt = %g: |d(body) - d(KE)| / d(KE) worst %.2e; |balance error| worst "
            "%.3e J, m g^2 dt^2 / 8 = %.3e J\n",
            dt, worst_rel, worst_resid, eighth);
    }
    // With the automatic (growing, varying) step: reported only; the product-form KE changes
    // its offset with the step, the half-step form does not.
    ModelDef def;
    def.gravity = g;
    Model m(def);
    m.setDefaultContactModel("linear", linearProps(kKn));
    m.createBall(ballAt(Vec2(0.0, 0.0), kR, kRho, Vec2(3.0, 2.0)));
    m.setEnergyTracing(true);
    double worst = 0.0;
    for (int i = 0; i < 100; ++i) {
        m.cycle(10);
        const EnergyTotals e = m.energies();
        worst = std::max(worst, std::fabs(e.balanceError()) / e.kinetic);
    }
    report("free fall, automatic step: |balance error| / KE worst %.2e\n", worst);
}

TEST_CASE("local damping: free fall and bounce closed forms", "[core][energy]") {
    // PFC's local damping: F_d = -alpha |F| sign(v) per degree of freedom, F the unbalanced
    // force including gravity.
    const double alpha = 0.7, g = 9.81;
    SECTION("free fall with a downward initial velocity: a = g (1 - alpha), exact") {
        // sign(v) never changes, so the damped acceleration is constant and central differences
        // integrate it exactly: y = y0 + v0 t - g (1 - alpha) t^2 / 2. The damping work is
        // alpha m g times the distance fallen; it is booked as force times the velocity at the
        // force's time level, and the snapshot (one step behind time()) holds all damping
        // impulses but the last, whose work is half in its KE: so damping work and balance match
        // alpha m g d up to the work of one step, alpha m g |v| dt (bound).
        ModelDef def;
        def.gravity = Vec2(0.0, -g);
        Model m(def);
        m.setDefaultContactModel("linear", linearProps(kKn));
        const double v0 = -0.5;
        const BallId b = m.createBall(ballAt(Vec2(0.0, 0.0), kR, kRho, Vec2(0.0, v0)));
        m.damping().local = alpha;
        m.timestep() = fixedStep(1e-3);
        m.setEnergyTracing(true);
        m.cycle(1000);
        const double t = m.time();
        const double y = v0 * t - 0.5 * g * (1.0 - alpha) * t * t;
        CHECK(m.ballPos(b).y() == Approx(y).epsilon(1e-12));
        CHECK(m.ballPos(b).x() == 0.0);
        const EnergyTotals e = m.energies();
        const double ts = t - 1e-3;  // snapshot time
        const double fallen = -(v0 * ts - 0.5 * g * (1.0 - alpha) * ts * ts);
        const double mass = m.ballMass(b);
        report(
            "local damping free fall: y error %.2e m; damping work %.6g J vs alpha m g d = "
            "%.6g J; balance error %.2e J\n",
            m.ballPos(b).y() - y, e.damping, alpha * mass * g * fallen, e.balanceError());
        const double one_step = alpha * mass * g * std::fabs(m.ballVel(b).y()) * 1e-3;
        CHECK(std::fabs(e.damping - alpha * mass * g * fallen) < one_step);
        CHECK(std::fabs(e.balanceError()) < one_step);
    }
    SECTION("bounce: e = sqrt((1 - alpha)/(1 + alpha))") {
        // Derived here: on approach the damping force points along the contact force (v against
        // F), stiffening the spring to (1 + alpha) k; on rebound it opposes it, (1 - alpha) k. A
        // quarter period each way gives v_out/v_in = sqrt((1 - alpha)/(1 + alpha)) (0.420 for
        // alpha = 0.7), and the damping takes (1/2) m v0^2 (1 - e^2). No gravity.
        // The damping force switches sign at the turning point, between steps (sign of the
        // half-step velocity), and the resolution rule does not know that the approach is
        // stiffer by (1 + alpha): at the default step the error is several times the dashpot's.
        // Measured (10 phases): alpha 0.3 ~0.3% worst, alpha 0.7 ~4% worst; converging with the
        // step (~second order; 240 steps per contact: < 1e-3). Bounds: default 1% (0.3) and 6%
        // (0.7); 240 steps per contact 2e-3. Energy: the damping work must be what the ball lost,
        // (1/2) m (v_in^2 - v_out^2): measured 2.7e-3 of the energy in at the default step and
        // 4e-5 at 240 steps per contact (it converges); bounds 5e-3 and 2e-4.
        const double T = linearDuration(diskMass(kRho, kR), kKn);
        for (double a : {0.3, 0.7}) {
            for (int n : {0, 240}) {
                Rng rng(41);
                Stats st, bal;
                for (int i = 0; i < 10; ++i) {
                    ModelDef def;
                    Model m(def);
                    m.setDefaultContactModel("linear", linearProps(kKn));
                    m.createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
                    double dt = T / 30.0;
                    if (n > 0) {
                        dt = T / (n + rng.uniform());
                        m.timestep() = fixedStep(dt);
                    }
                    const BallId b = m.createBall(ballAt(
                        Vec2(0.0, kR + dt * rng.uniform(1.0, 20.0)), kR, kRho, Vec2(0.0, -1.0)));
                    m.damping().local = a;
                    m.setEnergyTracing(true);
                    const Episode ep = runEpisode(m, b);
                    REQUIRE(ep.ended);
                    m.cycle(3);
                    const double e = ep.v_out.y() / -ep.v_in.y();
                    st.add(e / std::sqrt((1.0 - a) / (1.0 + a)) - 1.0);
                    const EnergyTotals en = m.energies();
                    const double lost =
                        0.5 * m.ballMass(b) * (ep.v_in.squaredNorm() - ep.v_out.squaredNorm());
                    bal.add((en.damping - lost) / en.initial_kinetic);
                }
                report(
                    "local damping %.1f bounce, %s: e rel. error mean %.2e worst %.2e; damping "
                    "work - KE lost: worst %.2e of E_in\n",
                    a, n ? "240 steps/contact" : "default step", st.mean(), st.worst, bal.worst);
                INFO("alpha " << a << " n " << n);
                CHECK(st.worst < (n ? 2e-3 : (a < 0.5 ? 1e-2 : 6e-2)));
                CHECK(bal.worst < (n ? 2e-4 : 5e-3));
            }
        }
    }
}

TEST_CASE("viscous damping in free flight: v(t) = v0 exp(-c t)", "[core][energy]") {
    // Mass-proportional damping, integrated implicitly (trapezoidal): per step the velocity is
    // multiplied by (1 - c w/2)/(1 + c w/2) = exp(-c w) (1 - (c w)^3/12 + ...). The first step
    // uses w = dt/2, so the half-step velocity after n steps approximates v0 exp(-c (t - dt/2)),
    // with a relative error (c dt)^2 c t / 12: second order. Checked at c dt = 0.02 and 0.01
    // (bound: twice the leading term) and the observed order between them (>= 1.9); the damping
    // work must equal the kinetic energy lost (balance).
    const double c = 2.0, t_end = 1.5;
    const Vec2 v0(3.0, -1.0);
    std::vector<double> errs;
    for (double dt : {0.01, 0.005}) {
        ModelDef def;
        Model m(def);
        m.setDefaultContactModel("linear", linearProps(kKn));
        const BallId b = m.createBall(ballAt(Vec2(0.0, 0.0), kR, kRho, v0));
        m.damping().viscous = c;
        m.timestep() = fixedStep(dt);
        m.setEnergyTracing(true);
        m.solveTime(t_end);
        const double t = m.time();
        const Vec2 v_exact = v0 * std::exp(-c * (t - 0.5 * dt));
        const double err = (m.ballVel(b) - v_exact).norm() / v_exact.norm();
        const double bound = 2.0 * (c * dt) * (c * dt) * c * t / 12.0;
        // Position: integral of the velocity, midpoint rule on the same exponential.
        const Vec2 x_exact = v0 * (1.0 - std::exp(-c * t)) / c;
        const double xerr = (m.ballPos(b) - x_exact).norm() / x_exact.norm();
        const EnergyTotals e = m.energies();
        report(
            "viscous c = %g, dt = %g: |v - v0 exp(-c t)|/|v| = %.3e (bound %.3e), position "
            "error %.3e, balance %.2e of E_in\n",
            c, dt, err, bound, xerr, e.balanceError() / e.initial_kinetic);
        CHECK(err < bound);
        CHECK(xerr < 1e-3);
        CHECK(std::fabs(e.balanceError()) < 1e-3 * e.initial_kinetic);
        CHECK(e.damping > 0.9 * e.initial_kinetic * (1.0 - std::exp(-2.0 * c * (t - dt))));
        errs.push_back(err);
    }
    CHECK(observedOrder(errs[0], errs[1]) >= 1.9);
}

TEST_CASE("undamped contact with a fixed step: the discrete energy is conserved inside it",
          "[core][energy]") {
    // A property of the integrator, independent of how tracing books the kinetic energy: for a
    // linear spring, central differences with a constant step conserve exactly
    //   E_n = (1/2) m v(t_n - dt/2) . v(t_n + dt/2) + (1/2) k delta_n^2
    // while the contact lasts (touch and separation steps excepted, where the force switches on
    // and off between steps). Computed here from the state: round-off only (bound 1e-12).
    ModelDef def;
    Model m(def);
    m.setDefaultContactModel("linear", linearProps(kKn));
    m.createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
    const BallId b = m.createBall(ballAt(Vec2(0.0, kR + 1.37e-4), kR, kRho, Vec2(0.0, -1.0)));
    m.timestep() = fixedStep(linearDuration(m.ballMass(b), kKn) / 40.3);
    const double mass = m.ballMass(b);
    std::vector<double> inside;
    double delta_prev = -1.0;
    Vec2 v_prev = m.ballVel(b);
    for (int i = 0; i < 200; ++i) {
        // After cycle k: position x_k, velocity v(k - 1/2); v_prev = v(k - 3/2) and delta_prev
        // = the overlap at t_(k-1), the whole step those two velocities straddle.
        m.cycle(1);
        const Vec2 v = m.ballVel(b);
        const double delta = kR - m.ballPos(b).y();
        if (delta_prev > 0.0 && delta > 0.0)
            inside.push_back(0.5 * mass * v_prev.dot(v) + 0.5 * kKn * delta_prev * delta_prev);
        v_prev = v;
        delta_prev = delta;
        if (!inside.empty() && delta <= 0.0) break;
    }
    REQUIRE(inside.size() > 30);
    double worst = 0.0;
    for (std::size_t i = 2; i < inside.size(); ++i)
        worst = std::max(worst, std::fabs(inside[i] - inside[1]) / inside[1]);
    report(
        "discrete energy inside a fixed-step undamped contact: worst relative change %.2e over "
        "%zu steps\n",
        worst, inside.size());
    CHECK(worst < 1e-12);
}

// ---------------------------------------------------------------- tracing switched on in motion

namespace {

/// Tracing switched on while bodies move (docs/physics/energy.md, "Switching tracing on"). Two
/// copies of a scene run the same steps (tracing does not change a bit of the motion: the law
/// of motion's general loop and the models' energy outputs leave the forces as they are): A
/// traced from its start, B switched on after `before` steps. B's books open at a whole step,
/// the next snapshot, or with contacts active the one after (their models report what they
/// hold only while tracing is on); from there B must book exactly what A books: B's balance
/// error at every step is A's less A's at B's opening, and so per group. The tolerance is
/// round-off: the same items summed from another start, 1e-12 of the throughput (sums of ~1e3
/// terms, each with a relative round-off of 1e-16, in A's larger totals). B warns of nothing
/// (no energy created, no dissipation gone negative). Returns B's worst
/// |balance_error| over its own throughput, for the checks that need an absolute bound.
double startInMotion(const std::function<std::unique_ptr<Model>()>& scene, int before, int after,
                     const std::vector<std::string>& groups = {}) {
    auto a = scene();
    auto b = scene();
    WarningLog log;  // B warns of nothing (it warned of energy created)
    log.attach(*b);
    a->setEnergyTracing(true);
    std::vector<double> a_balance;
    std::vector<std::vector<double>> a_groups(groups.size());
    auto step = [&](bool b_too) {
        a->cycle(1);
        if (b_too) b->cycle(1);
        a_balance.push_back(a->energies().balanceError());
        for (std::size_t g = 0; g < groups.size(); ++g)
            a_groups[g].push_back(a->energies(groups[g]).balanceError());
    };
    for (int i = 0; i < before; ++i) step(true);
    REQUIRE(a->time() == b->time());
    const bool loaded = b->contactCount(true) > 0;
    b->setEnergyTracing(true);
    // The opening snapshot is the one after step `before` + 1 (+ 1 with contacts active).
    const std::size_t open = static_cast<std::size_t>(before) + (loaded ? 1 : 0);
    double worst = 0.0, worst_b = 0.0;
    for (int i = 0; i < after; ++i) {
        step(true);
        const std::size_t k = a_balance.size() - 1;
        if (k < open) continue;
        const EnergyTotals eb = b->energies();
        const EnergyTotals ea = a->energies();
        const double through = std::max({ea.input(), ea.kinetic + ea.strain + ea.bond, 1e-300});
        const double diff = eb.balanceError() - (a_balance[k] - a_balance[open]);
        worst = std::max(worst, std::fabs(diff) / through);
        for (std::size_t g = 0; g < groups.size(); ++g) {
            const double dg =
                b->energies(groups[g]).balanceError() - (a_groups[g][k] - a_groups[g][open]);
            worst = std::max(worst, std::fabs(dg) / through);
        }
        worst_b = std::max(worst_b, std::fabs(eb.balanceError()) /
                                        std::max({eb.input(), eb.kinetic + eb.strain + eb.bond}));
        if (k == open) CHECK(eb.balanceError() == 0.0);  // the books open balanced
    }
    REQUIRE(a->time() == b->time());  // the same steps: the same motion
    CHECK(log.texts.empty());
    if (!log.texts.empty()) report("  B warned: %s\n", log.texts.front().c_str());
    INFO("B's balance against A's from B's opening: worst " << worst << " of the throughput");
    report("  B's balance against A's from B's opening: worst %.2e of the throughput\n", worst);
    CHECK(worst <= 1e-12);
    return worst_b;
}

std::unique_ptr<Model> fallingBall() {
    auto m = makeModel(Vec2(0.0, -9.81), linearProps(kKn));
    m->createBall(ballAt(Vec2(0.0, 10.0), kR, kRho, Vec2(1.0, 0.0)));
    return m;
}

}  // namespace

// History: until 2026-11-28 the books opened when tracing was switched on, between two steps,
// with the kinetic energy of the half-step velocities while every later snapshot takes it at
// the whole step: a ball falling for 10 steps then traced for 10 booked -1.01 J, 1.7% of the
// throughput, and the guard warned of energy created.
TEST_CASE("tracing switched on in free fall: the balance closes to round-off", "[core][energy]") {
    // Central differences integrate free fall exactly, and the snapshot's kinetic energy at the
    // whole step is exact for a constant acceleration: B's balance is round-off.
    for (int before : {10, 100}) {
        INFO(before << " steps before");
        const double worst = startInMotion(fallingBall, before, 100);
        report("free fall, tracing on after %d steps: |balance| / throughput worst %.2e\n", before,
               worst);
        CHECK(worst <= 1e-12);
    }
    // The books start at the whole step after the switch: initial_kinetic is (1/2) m v(t)^2
    // there, v(t) = v0 + g t exactly.
    auto m = fallingBall();
    m->cycle(10);
    m->setEnergyTracing(true);
    const double t = m->time();
    m->cycle(1);
    const EnergyTotals e = m->energies();
    const double vy = -9.81 * t, mass = diskMass(kRho, kR);
    CHECK(e.initial_kinetic == Approx(0.5 * mass * (1.0 + vy * vy)).epsilon(1e-13));
    CHECK(e.kinetic == e.initial_kinetic);
}

TEST_CASE("tracing switched on while a clump is thrown with spin: round-off", "[core][energy]") {
    // A two-pebble clump (R 0.05 m, centres 0.06 m apart) thrown at (3, 5) m/s spinning at
    // 20 rad/s: the same exact free flight, for the clump's translation and rotation.
    auto scene = [] {
        auto m = makeModel(Vec2(0.0, -9.81), linearProps(kKn));
        ClumpDef c;
        c.pebbles = {{Vec2(-0.03, 0.0), kR}, {Vec2(0.03, 0.0), kR}};
        c.pos = Vec2(0.0, 2.0);
        c.density = kRho;
        c.vel = Vec2(3.0, 5.0);
        c.spin = 20.0;
        m->createClump(c);
        return m;
    };
    const double worst = startInMotion(scene, 37, 200);
    report("clump thrown with spin, tracing on after 37 steps: |balance| / throughput %.2e\n",
           worst);
    CHECK(worst <= 1e-12);
}

TEST_CASE(
    "tracing switched on during a bounce and in a loaded contact books what a run traced "
    "from its start books",
    "[core][energy]") {
    // A ball dropped on a floor, linear contact with dashpots and friction (dp_nratio 0.3, fric
    // 0.4), automatic step: tracing switched on in flight (no contact: the next snapshot) and
    // during the first impact (a loaded contact: the one after), then three bounces. B's balance
    // is A's from B's opening to round-off (startInMotion checks it), and itself the scheme's
    // second-order error of the impacts (bounded here by 1e-3 of the throughput, as a bounce
    // traced from its start: docs/physics/energy.md).
    auto drop = [] {
        auto m = makeModel(Vec2(0.0, -9.81), linearProps(kKn, kKn, 0.4, 0.3, 0.3));
        m->createWall(wallOf({Vec2(-10.0, 0.0), Vec2(10.0, 0.0)}));
        m->createBall(ballAt(Vec2(0.0, 0.5), kR, kRho, Vec2(0.5, 0.0)));
        return m;
    };
    auto probe = drop();
    int touch = 0;
    while (probe->contactCount(true) == 0) probe->cycle(1), ++touch;
    for (int before : {touch / 2, touch + 10}) {
        INFO(before << " steps before (first touch at step " << touch << ")");
        const double worst = startInMotion(drop, before, 3000);
        report("bounce, tracing on after %d steps (touch at %d): |balance| / throughput %.2e\n",
               before, touch, worst);
        CHECK(worst <= 1e-3);
    }
}

TEST_CASE("tracing switched on over a ball resting on a floor and over a compressed pack",
          "[core][energy]") {
    // A ball settled on a floor (dashpot, gravity): its contact holds m g / kn of overlap when
    // tracing starts. B opens one step later, from what the model reports; nothing moves, so
    // its balance stays at round-off of the stored and potential energies.
    auto rest = [] {
        auto m = makeModel(Vec2(0.0, -9.81), linearProps(kKn, kKn, 0.5, 0.5, 0.5));
        m->createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
        m->createBall(ballAt(Vec2(0.0, kR), kR, kRho));
        m->cycle(3000);
        return m;
    };
    const double at_rest = startInMotion(rest, 5, 500);
    report("ball at rest on a floor: |balance| / throughput %.2e\n", at_rest);
    CHECK(at_rest <= 1e-9);
    // A pack of 25 balls in a box compressed by its lid (0.05 m/s), gravity, friction,
    // dashpots, local damping; the left and right halves are groups. Tracing switched on while
    // the lid moves: the wall's work, the damping and the dashpots' impulses span the opening
    // snapshot, and the groups exchange work across their border.
    auto pack = [] {
        auto m = makeModel(Vec2(0.0, -9.81), linearProps(1e6, 5e5, 0.5, 0.3, 0.3));
        m->damping().local = 0.1;
        m->createWall(wallOf({Vec2(0.0, 1.0), Vec2(0.0, 0.0), Vec2(0.5, 0.0), Vec2(0.5, 1.0)}));
        WallDef lid = wallOf({Vec2(-0.1, 0.55), Vec2(0.6, 0.55)});
        lid.vel = Vec2(0.0, -0.05);
        m->createWall(lid);
        Rng rng(7);
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 5; ++i) {
                BallDef bd = ballAt(Vec2(0.05 + 0.1 * i, 0.05 + 0.1 * j),
                                    0.048 + 0.002 * rng.uniform(), kRho);
                bd.groups = {i < 2 ? "left" : "right"};
                m->createBall(bd);
            }
        m->cycle(200);
        return m;
    };
    const double pack_worst = startInMotion(pack, 400, 800, {"left", "right"});
    report("compressed pack: |balance| / throughput %.2e\n", pack_worst);
    CHECK(pack_worst <= 1e-2);
}

// History: until 2026-11-28 a moving wall's work over the window around each force was booked
// with the velocity of the step after it, also for the half before, when the wall moved at the
// velocity of the step before: off by F (v - v_before) dt / 2 whenever the velocity changed. A
// servo wall changes it every step: tests/scripting/regress/servo_pack.lua's pack, loaded to
// twice its stress, closed to -0.67 J of 818 J of boundary work (8e-4); now 2.5e-3 J (3e-6).
TEST_CASE(
    "a wall whose velocity changes every step: its work is booked with the velocity it "
    "moved at",
    "[core][energy]") {
    // A ball (R 0.05 m, 20 kg) between a floor and a lid that squeezes it, v = -0.2 sin(2 pi 20 t)
    // m/s, set before every step (as a servo sets it): 2.6 J stored at each squeeze. No gravity,
    // undamped linear contacts (kn 1e6 N/m: ~1000 steps per period of the ball between them).
    // The balance closes to second order in the step: measured 7.3e-7 and 1.8e-7 of the
    // throughput at 2e-5 and 1e-5 s; the left-out term made it first order, 7.4e-3 and 3.7e-3.
    double worst[2];
    for (int k = 0; k < 2; ++k) {
        const double dt = k == 0 ? 2e-5 : 1e-5;
        auto m = makeModel(Vec2::Zero(), linearProps(1e6));
        m->createWall(wallOf({Vec2(-1.0, 0.0), Vec2(1.0, 0.0)}));
        const WallId lid = m->createWall(wallOf({Vec2(-1.0, 2.0 * kR), Vec2(1.0, 2.0 * kR)}));
        m->createBall(ballAt(Vec2(0.0, kR), kR, kRho));
        m->timestep() = fixedStep(dt);
        m->setEnergyTracing(true);
        double worst_error = 0.0, through = 0.0;
        const int steps = static_cast<int>(0.25 / dt);
        for (int i = 0; i < steps; ++i) {
            m->setWallVel(lid, Vec2(0.0, -0.2 * std::sin(2.0 * M_PI * 20.0 * m->time())));
            m->cycle(1);
            const EnergyTotals e = m->energies();
            worst_error = std::max(worst_error, std::fabs(e.balanceError()));
            through = std::max({through, e.input(), e.kinetic + e.strain});
        }
        worst[k] = worst_error / through;
        report("oscillating lid, dt %g: worst |balance| / throughput %.3e\n", dt, worst[k]);
    }
    CHECK(worst[0] < 2e-6);
    CHECK(worst[0] / worst[1] > 3.0);  // second order (4)
}
