// SPDX-License-Identifier: MIT
//
// Tests of the `power` contact model (plugins/power, docs/models/power.md): An's
// elastic-perfectly plastic power-function model, An 2006 and An &
// Tannant 2007. Closed forms used:
//   e^2 = (1 + r) / (b + 1),  r = min(1, v_y^2 / v0^2),  v_y = T / sqrt(kn m*)      (An & Tannant)
//   W_L - W_U = (1/2) m* v0^2 (1 - e^2)                     (plastic work of one impact)
//   duration = t1 + t2 + t3                                  (An & Tannant 2007)
// Note on r = min(1, ...): below yield the model still unloads on the power curve (An
// 2006: a = F_B / u_B^b with F_B = kn u_B), so e = sqrt(2/(b+1)) there, continuous at v_y;
// An & Tannant 2007's "e = 1 below v_y" holds only for b = 1 (see docs/models/power.md).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "talus/contact_model.hpp"
#include "talus/errors.hpp"
#include "talus/impact_rig.hpp"
#include "talus/model.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/save_object.hpp"
#include "talus/splitmix.hpp"

using namespace talus;
using Catch::Matchers::Contains;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The rig's standard body: a unit-thickness disk, R = 0.1 m, 2600 kg/m^3 (81.7 kg).
constexpr double kR = 0.1, kRho = 2600.0, kKn = 1e8;
const double kMass = kRho * M_PI * kR * kR;
/// Transition force for a yield speed vy against a wall (m* = m): T = vy sqrt(kn m).
double tFor(double vy) { return vy * std::sqrt(kKn * kMass); }
// A yield speed of 1 m/s. The plastic overlap m (v0^2 - v_y^2) / (2T) stays below R up to
// v0 = 10 v_y; beyond that the ball would pass through the wall (Nejati 2008).
const double kT = tFor(1.0);

double closedFormE(double b, double v0, double vy) {
    const double r = v0 > vy ? (vy / v0) * (vy / v0) : 1.0;
    return std::sqrt((1.0 + r) / (b + 1.0));
}

/// Fixed-seed phases of first touch (fractions of a step).
std::vector<double> phases(int n, uint64_t seed) {
    SplitMix64 rng(seed);
    std::vector<double> out;
    for (int i = 0; i < n; ++i) out.push_back(rng.uniform());
    return out;
}

ImpactResult impact(double v0, std::vector<PropValue> props, double gap_fraction = 0.5) {
    ImpactSetup s;
    s.model = "power";
    s.props = std::move(props);
    s.radius = kR;
    s.density = kRho;
    s.normal_speed = v0;
    // The approach rule shrinks the step near the wall; the gap sets the phase of first touch.
    s.gap = kR * 1e-3 * (1.0 + gap_fraction);
    s.guard.energy = GuardAction::Error;
    s.guard.resolution = GuardAction::Error;
    const ImpactResult r = runImpact(s);
    REQUIRE(r.separated);
    return r;
}

// ------------------------------------------------------------------ direct drive of clones

PropBlock wallBlock(double mass) {
    PropBlock pb{};
    pb.size = sizeof(PropBlock);
    pb.version = TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR;
    pb.end2_type = kEndWall;
    for (int i = 0; i < 2; ++i) pb.kn[i] = pb.ks[i] = pb.fric[i] = std::nan("");
    pb.radius[0] = kR;
    pb.mass[0] = mass;
    pb.mass_eff = mass;
    return pb;
}

/// One per-contact object in host-like storage, driven FDlaw by FDlaw.
struct Clone {
    std::vector<std::max_align_t> words;
    ContactModel* model = nullptr;
    FdBlock fd{};
    double u_last = 0.0;
    Clone(const ContactModel& proto, const PropBlock& pb)
        : words((proto.ObjectSize() + sizeof(std::max_align_t) - 1) / sizeof(std::max_align_t)) {
        model = proto.Clone(pb, words.data());
        REQUIRE(model != nullptr);
        fd.size = sizeof(FdBlock);
        fd.version = TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR;
        fd.mass_eff = pb.mass_eff;
    }
    ~Clone() {
        if (model) model->Destroy();
    }
    Clone(const Clone&) = delete;
    Clone& operator=(const Clone&) = delete;
    void step(double u, double us, bool first, double dt = 1e-6) {
        fd.flags = (first ? kFdFirstCall : 0u) | kFdEnergyOn;
        fd.status = 0;
        fd.tdel = dt;
        fd.du_n = u - u_last;
        fd.u_dot_n = fd.du_n / dt;
        fd.du_s = us;
        fd.u_dot_s = us / dt;
        fd.u_n = u;
        for (double& e : fd.energy) e = 0.0;
        model->FDlaw(fd);
        REQUIRE(fd.status == 0);
        u_last = u;
    }
};

PluginRegistry::PrototypePtr prototype(const std::vector<PropValue>& props) {
    auto& reg = PluginRegistry::global();
    auto proto = reg.createPrototype(reg.find("power"));
    for (const auto& p : props) {
        int32_t idx = -1;
        for (int32_t i = 0; i < proto->PropCount(); ++i)
            if (p.name == proto->PropInfoAt(i)->name) idx = i;
        REQUIRE(idx >= 0);
        REQUIRE(proto->AcceptProp(idx, p.value) == 0);
    }
    return proto;
}

double prop(const ContactModel& m, const char* name) {
    for (int32_t i = 0; i < m.PropCount(); ++i)
        if (std::string(name) == m.PropInfoAt(i)->name) return m.ReturnProp(i);
    FAIL("no property " << name);
    return 0.0;
}

}  // namespace

// ============================================================================ restitution

TEST_CASE("power: restitution follows eq. 5.1 from below yield to 10x yield", "[power]") {
    // v0 / v_y from 0.5 (elastic) through 1 (just yields) to 10.
    const double vy = kT / std::sqrt(kKn * kMass);
    const auto ph = phases(3, 11);
    for (double b : {1.0, 2.0, 7.0}) {
        for (double ratio : {0.5, 1.0, 1.5, 2.0, 5.0, 10.0}) {
            const double v0 = ratio * vy;
            const double exact = closedFormE(b, v0, vy);
            for (double f : ph) {
                const ImpactResult r =
                    impact(v0, {{"kn", kKn}, {"transition", kT}, {"exponent", b}}, f);
                INFO("b = " << b << ", v0/v_y = " << ratio << ", phase " << f
                            << ": e = " << r.restitution << ", closed form " << exact);
                CHECK(r.restitution == Approx(exact).epsilon(2e-3));
                // Below yield with b = 1 the law is elastic: the plastic partition holds only the
                // discretisation error of touch and separation (either sign, ~1e-4 of the input).
                if (b == 1.0 && ratio < 1.0)
                    CHECK(std::fabs(r.energy.plastic) < 3e-4 * r.energy_in);
                if (ratio > 1.0) CHECK(r.energy.plastic > 0.0);
            }
        }
    }
}

TEST_CASE("power: elastic-power special case (T = inf) gives e = sqrt(2/(b+1)) at any speed",
          "[power]") {
    for (double b : {1.0, 2.0, 7.0, 82.0}) {
        for (double v0 : {0.05, 1.0, 20.0}) {
            const ImpactResult r = impact(v0, {{"kn", kKn}, {"exponent", b}});
            INFO("b = " << b << ", v0 = " << v0 << ", steps in contact " << r.steps_in_contact);
            CHECK(r.restitution == Approx(std::sqrt(2.0 / (b + 1.0))).epsilon(3e-3));
            // The step follows the stiffness b F/u of the power curve: even b = 82 is resolved.
            CHECK(r.steps_in_contact >= 20);
        }
    }
}

TEST_CASE("power: the triangular model (b = 1) never falls below sqrt(0.5)", "[power]") {
    const double vy = 0.01;  // low yield speed, so that 100 v_y stays within the radius
    double last = 1.0;
    for (double ratio : {1.0, 2.0, 5.0, 20.0, 100.0}) {
        const ImpactResult r =
            impact(ratio * vy, {{"kn", kKn}, {"transition", tFor(vy)}, {"exponent", 1.0}});
        INFO("v0/v_y = " << ratio << ": e = " << r.restitution);
        CHECK(r.restitution >= std::sqrt(0.5) * (1.0 - 5e-4));
        CHECK(r.restitution <= last + 1e-3);  // falls with speed (An 2006)
        last = r.restitution;
    }
    CHECK(last == Approx(std::sqrt(0.5)).epsilon(2e-3));  // 100 x yield: g -> 0
}

TEST_CASE("power: plastic work of an impact equals W_L - W_U and the balance closes", "[power]") {
    const double vy = kT / std::sqrt(kKn * kMass);
    for (double b : {1.0, 2.0, 7.0}) {
        for (double ratio : {2.0, 8.0}) {
            const double v0 = ratio * vy;
            const ImpactResult r =
                impact(v0, {{"kn", kKn}, {"transition", kT}, {"exponent", b}, {"ks", 5e7}});
            const double e = closedFormE(b, v0, vy);
            // An & Tannant 2007 areas: W_L = T(de + 2p)/2 = m v0^2 / 2, W_U = e^2 W_L.
            const double de = kT / kKn;
            const double p = 0.5 * kMass * (v0 * v0 - vy * vy) / kT;
            const double wl = kT * (de + 2.0 * p) / 2.0;
            const double wu = kT * (de + p) / (b + 1.0);
            REQUIRE(wl == Approx(0.5 * kMass * v0 * v0).epsilon(1e-12));
            REQUIRE(wu / wl == Approx(e * e).epsilon(1e-12));
            INFO("b = " << b << ", v0/v_y = " << ratio << ": plastic " << r.energy.plastic
                        << " J, W_L - W_U = " << wl - wu << " J");
            CHECK(r.energy.plastic == Approx(wl - wu).epsilon(2e-3));
            CHECK(r.energy.strain == Approx(0.0).margin(1e-9 * wl));  // nothing left stored
            CHECK(std::fabs(r.energy.balanceError()) < 1e-3 * r.energy_in);
        }
    }
}

TEST_CASE("power: the measured duration matches ContactDuration (t1 + t2 + t3)", "[power]") {
    auto& reg = PluginRegistry::global();
    const double vy = kT / std::sqrt(kKn * kMass);
    for (double b : {1.0, 7.0}) {
        auto proto = prototype({{"kn", kKn}, {"transition", kT}, {"exponent", b}});
        for (double ratio : {0.5, 3.0}) {
            const double v0 = ratio * vy;
            const ImpactResult r = impact(v0, {{"kn", kKn}, {"transition", kT}, {"exponent", b}});
            INFO("b = " << b << ", v0/v_y = " << ratio);
            CHECK(r.duration == Approx(proto->ContactDuration(kMass, v0)).epsilon(1e-2));
        }
    }
    (void)reg;
}

// ============================================================================ exponent modes

namespace {

/// Drops a ball on a wall with the engine and reads the contact's state in mid-impact.
struct Midway {
    double b_used = 0.0, v_impact = 0.0;
};
Midway midImpact(double v0, const std::vector<PropValue>& props) {
    Model m;
    m.setDefaultContactModel("power", props);
    WallDef w;
    w.points = {Vec2(-10.0, 0.0), Vec2(10.0, 0.0)};
    m.createWall(w);
    BallDef b;
    b.pos = Vec2(0.0, kR + 1e-4);
    b.radius = kR;
    b.density = kRho;
    b.vel = Vec2(0.0, -v0);
    m.createBall(b);
    for (int i = 0; i < 100000 && m.contactCount() == 0; ++i) m.cycle(1);
    const auto c = m.contacts();
    REQUIRE(c.size() == 1);
    return Midway{m.contactProp(c[0].key, "b_used"), m.contactProp(c[0].key, "v_impact")};
}

}  // namespace

TEST_CASE("power: exponent modes velocity and velocity_b choose b from the impact speed",
          "[power]") {
    const double vy = 5.0, T = tFor(vy);  // so that 15 m/s stays within the radius
    for (double v : {2.0, 5.0, 10.0, 15.0}) {
        const Midway a = midImpact(v, {{"kn", kKn}, {"transition", T}, {"exp_mode", 1}});
        const double eq52 = 0.0429 * v * v * v - 0.4744 * v * v + 2.5508 * v + 1.1489;
        CHECK(a.v_impact == Approx(v).epsilon(1e-12));  // no force before touch
        CHECK(a.b_used == Approx(eq52).epsilon(1e-12));
        const Midway t = midImpact(v, {{"kn", kKn}, {"transition", T}, {"exp_mode", 2}});
        CHECK(t.b_used == Approx(v > 4.0 ? 7.0 + std::pow(v / 8.0, 3) : 7.0).epsilon(1e-12));
        // The rebound follows eq. 5.1 with that b.
        const ImpactResult r = impact(v, {{"kn", kKn}, {"transition", T}, {"exp_mode", 1}});
        CHECK(r.restitution == Approx(closedFormE(eq52, v, vy)).epsilon(2e-3));
    }
}

TEST_CASE("power: restitution mode reproduces the target e across speeds", "[power]") {
    const double vy = kT / std::sqrt(kKn * kMass);
    for (double target : {0.3, 0.45, 0.7}) {
        for (double ratio : {0.3, 1.0, 2.0, 5.0, 10.0}) {
            const ImpactResult r =
                impact(ratio * vy,
                       {{"kn", kKn}, {"transition", kT}, {"exp_mode", 3}, {"target_e", target}});
            INFO("target " << target << ", v0/v_y = " << ratio);
            CHECK(r.restitution == Approx(target).epsilon(3e-3));
        }
        // Elastic-power with a target: b = 2/e^2 - 1 at every speed.
        const ImpactResult r = impact(3.0, {{"kn", kKn}, {"exp_mode", 3}, {"target_e", target}});
        CHECK(r.restitution == Approx(target).epsilon(3e-3));
    }
    // Above the triangular limit the target is out of reach at high speed: b stays 1.
    const ImpactResult r =
        impact(10.0 * vy, {{"kn", kKn}, {"transition", kT}, {"exp_mode", 3}, {"target_e", 0.9}});
    CHECK(r.restitution == Approx(closedFormE(1.0, 10.0 * vy, vy)).epsilon(2e-3));
}

// ============================================================================ force traces

TEST_CASE("power: driveContact trace: loading, plateau, unloading on the power curve", "[power]") {
    const double kn = 1e7, T = 1e3, b = 3.0;
    const double de = T / kn;  // elastic displacement, 1e-4 m
    DriveSetup d;
    d.model = "power";
    d.props = {{"kn", kn}, {"transition", T}, {"exponent", b}};
    const int n = 200;
    for (int i = 0; i <= n; ++i) d.overlap.push_back(3.0 * de * i / n);       // up to 3 de
    for (int i = n - 1; i >= -2; --i) d.overlap.push_back(3.0 * de * i / n);  // down to a gap
    const DriveResult r = driveContact(d);
    REQUIRE(r.trace.size() == d.overlap.size());
    const double ub = 3.0 * de;
    for (std::size_t i = 0; i < r.trace.size(); ++i) {
        const double u = r.trace[i].overlap, f = r.trace[i].normal_force;
        INFO("sample " << i << ", u = " << u);
        if (i <= std::size_t(n)) {
            CHECK(f == Approx(std::min(kn * u, T)).margin(1e-9 * T));  // elastic, then T
        } else if (u > 0.0) {
            CHECK(f == Approx(T * std::pow(u / ub, b)).epsilon(1e-12));  // a u^b, a = T/u_B^b
            CHECK(r.knest[i] == Approx(std::max(kn, b * f / u)).epsilon(1e-12));
        } else {
            CHECK(f == 0.0);  // no tension
        }
    }
    // At the turning point the reported stiffness is the power curve's tangent b T / u_B.
    CHECK(r.knest[n] == Approx(std::max(kn, b * T / ub)).epsilon(1e-12));
    // Elastic loading: the unloading tangent b kn is already reported.
    CHECK(r.knest[n / 10] == Approx(b * kn).epsilon(1e-12));
    // Plastic work of the path: W_L - W_U with the exact areas (the trace is fine: 0.3% sampling).
    const double wl = T * (de + 2.0 * (ub - de)) / 2.0, wu = T * ub / (b + 1.0);
    CHECK(r.plastic == Approx(wl - wu).epsilon(3e-3));
    CHECK(r.strain == 0.0);
}

TEST_CASE("power: reloading before separation runs back up the same power curve", "[power]") {
    const double kn = 1e7, T = 1e3, b = 2.5, de = T / kn;
    DriveSetup d;
    d.model = "power";
    d.props = {{"kn", kn}, {"transition", T}, {"exponent", b}};
    // 0 -> 2 de (plastic) -> 0.8 de (unload) -> 3 de (reload past u_B) -> 0
    auto ramp = [&](double a, double z, int k) {
        for (int i = 1; i <= k; ++i) d.overlap.push_back(a + (z - a) * i / k);
    };
    d.overlap.push_back(0.0);
    ramp(0.0, 2.0 * de, 100);
    ramp(2.0 * de, 0.8 * de, 60);
    ramp(0.8 * de, 3.0 * de, 110);
    ramp(3.0 * de, 0.0, 150);
    const DriveResult r = driveContact(d);
    for (std::size_t i = 1; i < r.trace.size(); ++i) {
        const double u = r.trace[i].overlap, f = r.trace[i].normal_force;
        INFO("sample " << i << ", u/de = " << u / de);
        if (i <= 100) {
            CHECK(f == Approx(std::min(kn * u, T)).margin(1e-9 * T));  // virgin curve
        } else if (i <= 270) {
            // Unloading, and reloading up the same curve to (u_B, F_B) = (2 de, T); then
            // plastic again along the virgin curve.
            if (u < 2.0 * de)
                CHECK(f == Approx(T * std::pow(u / (2.0 * de), b)).epsilon(1e-12));
            else
                CHECK(f == Approx(T).epsilon(1e-12));
        } else {
            CHECK(f == Approx(T * std::pow(u / (3.0 * de), b)).epsilon(1e-12));  // new turn
        }
    }
    // The unload-reload loop below u_B is elastic: the plastic work is that of the envelope.
    const double wl = T * (de + 2.0 * (3.0 * de - de)) / 2.0, wu = T * 3.0 * de / (b + 1.0);
    CHECK(r.plastic == Approx(wl - wu).epsilon(5e-3));
}

TEST_CASE("power: an elastic contact (T = inf) reloads past u_B on the loading line", "[power]") {
    const double kn = 1e7, b = 2.0;
    DriveSetup d;
    d.model = "power";
    d.props = {{"kn", kn}, {"exponent", b}};
    d.overlap = {0.0, 1e-4, 2e-4, 1e-4, 2e-4, 3e-4, 0.0, 1e-4};
    const DriveResult r = driveContact(d);
    CHECK(r.trace[2].normal_force == Approx(kn * 2e-4));
    CHECK(r.trace[3].normal_force == Approx(kn * 2e-4 * 0.25));  // (1/2)^2 on the power curve
    CHECK(r.trace[4].normal_force == Approx(kn * 2e-4));         // back at (u_B, F_B)
    CHECK(r.trace[5].normal_force == Approx(kn * 3e-4));         // on along kn u
    CHECK(r.trace[6].normal_force == 0.0);
    // Separated: the host deletes the contact; the next touch is a fresh impact (virgin curve).
    CHECK(r.trace[7].normal_force == Approx(kn * 1e-4));
}

// ============================================================================ per-contact state

TEST_CASE("power: two contacts never share turning points (An's 2006 static-state bug)",
          "[power]") {
    // Regression test for An 2006: An (2006) kept (u_B, F_B) in function statics.
    auto proto = prototype({{"kn", 1e7}, {"transition", 1e3}, {"exponent", 4.0}});
    const PropBlock pb = wallBlock(2.0);
    auto history = [](int k, double scale) {
        return scale * 1e-4 * std::sin(0.02 * k);  // up to the turn and back, then a gap
    };
    const int n = 180;
    // Alone.
    std::vector<double> fa, fb;
    {
        Clone a(*proto, pb);
        for (int k = 1; k < n; ++k)
            a.step(history(k, 5.0), 0.0, k == 1), fa.push_back(a.fd.n_force);
        Clone c(*proto, pb);
        for (int k = 1; k < n; ++k)
            c.step(history(k, 1.5), 0.0, k == 1), fb.push_back(c.fd.n_force);
    }
    // Interleaved: the deeper impact turns first, then the shallower one.
    Clone a(*proto, pb), c(*proto, pb);
    for (int k = 1; k < n; ++k) {
        a.step(history(k, 5.0), 0.0, k == 1);
        c.step(history(k, 1.5), 0.0, k == 1);
        REQUIRE(a.fd.n_force == fa[std::size_t(k - 1)]);
        REQUIRE(c.fd.n_force == fb[std::size_t(k - 1)]);
        if (k == 90) {
            // Both are past their maximum: their turning points differ.
            CHECK(prop(*a.model, "u_max") == Approx(5e-4 * std::sin(0.02 * 78)).epsilon(1e-3));
            CHECK(prop(*c.model, "u_max") == Approx(1.5e-4 * std::sin(0.02 * 78)).epsilon(1e-3));
            CHECK(prop(*a.model, "f_max") == Approx(1e3));
            CHECK(prop(*c.model, "f_max") == Approx(1e3));  // both yielded, at different u_B
        }
    }
}

TEST_CASE("power: two simultaneous impacts in one model each follow eq. 5.1", "[power]") {
    // Two balls hit the same wall at 2 v_y and 8 v_y; their contacts overlap in time.
    const double vy = kT / std::sqrt(kKn * kMass);
    Model m;
    m.setDefaultContactModel("power", {{"kn", kKn}, {"transition", kT}, {"exponent", 3.0}});
    WallDef w;
    w.points = {Vec2(-10.0, 0.0), Vec2(10.0, 0.0)};
    m.createWall(w);
    const double speeds[2] = {2.0 * vy, 8.0 * vy};
    BallId ids[2];
    for (int i = 0; i < 2; ++i) {
        BallDef b;
        b.pos = Vec2(i == 0 ? -1.0 : 1.0, kR + 1e-4 * (1 + 3 * i));
        b.radius = kR;
        b.density = kRho;
        b.vel = Vec2(0.0, -speeds[i]);
        ids[i] = m.createBall(b);
    }
    bool both = false;
    for (int k = 0; k < 200000; ++k) {
        m.cycle(1);
        if (m.contactCount() == 2) both = true;
        if (k > 10 && m.contactCount() == 0 && m.ballVel(ids[0]).y() > 0 &&
            m.ballVel(ids[1]).y() > 0)
            break;
    }
    REQUIRE(both);
    for (int i = 0; i < 2; ++i) {
        const double e = m.ballVel(ids[i]).y() / speeds[i];
        INFO("ball " << i << ": e = " << e);
        CHECK(e == Approx(closedFormE(3.0, speeds[i], vy)).epsilon(2e-3));
    }
}

// ============================================================================ properties

TEST_CASE("power: property errors name the property and the reason", "[power]") {
    Model m;
    auto err = [&](std::vector<PropValue> props) -> std::string {
        try {
            m.setDefaultContactModel("power", props);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    const std::string b = err({{"kn", 1e7}, {"exponent", 0.5}});
    CHECK_THAT(b, Contains("'exponent' must be >= 1") &&
                      Contains("An & Tannant 2007: b >= 1 keeps the model dissipative"));
    CHECK_THAT(err({{"exponent", kInf}}), Contains("'exponent' must be finite"));
    CHECK_THAT(err({{"transition", 0.0}}), Contains("'transition' must be > 0"));
    CHECK_THAT(err({{"transition", -5.0}}), Contains("'transition' must be > 0"));
    CHECK(err({{"kn", 1e7}, {"transition", kInf}}).empty());  // the elastic-power model
    CHECK_THAT(err({{"exp_mode", 4}}),
               Contains("0 = fixed, 1 = velocity, 2 = velocity_b, 3 = restitution"));
    CHECK_THAT(err({{"exp_mode", 1.5}}), Contains("'exp_mode' must be one of"));
    CHECK_THAT(err({{"target_e", 0.0}}), Contains("'target_e' must be in (0, 1]"));
    CHECK_THAT(err({{"target_e", 1.2}}), Contains("'target_e'"));
    CHECK_THAT(err({{"kn", -1.0}}), Contains("'kn' must be >= 0"));
    CHECK_THAT(err({{"u_max", 1.0}}), Contains("'u_max' is read-only"));
    CHECK_THAT(err({{"bogus", 1.0}}),
               Contains("unknown property 'bogus'") && Contains("transition"));

    // kn from nowhere: the contact cannot be made, and the error names the contact and model.
    Model z;
    z.setDefaultContactModel("power", {{"transition", 100.0}});
    WallDef w;
    w.points = {Vec2(-1.0, 0.0), Vec2(1.0, 0.0)};
    z.createWall(w);
    BallDef ball;
    ball.pos = Vec2(0.0, 0.1005);
    ball.radius = 0.1;
    ball.density = 1000.0;
    ball.vel = Vec2(0.0, -1.0);
    z.createBall(ball);
    try {
        z.cycle(50);
        FAIL("a contact without kn was created");
    } catch (const PluginError& e) {
        CHECK_THAT(std::string(e.what()), Contains("'power'") && Contains("'kn' must be > 0"));
    }
}

TEST_CASE("power: a ball pushed through the wall stops the run with a clear error", "[power]") {
    // Nejati (2008): with too low a T the plastic overlap m (v0^2 - v_y^2) / (2T) exceeds the
    // radius and balls pass through walls. Here 30 v_y gives 0.4 m of plastic overlap for R = 0.1
    // m.
    ImpactSetup s;
    s.model = "power";
    s.props = {{"kn", kKn}, {"transition", kT}, {"exponent", 3.0}};
    s.radius = kR;
    s.density = kRho;
    s.normal_speed = 30.0;
    try {
        runImpact(s);
        FAIL("the ball went through the wall silently");
    } catch (const PluginError& e) {
        CHECK_THAT(std::string(e.what()),
                   Contains("(model 'power')") && Contains("within a step of the ball radius") &&
                       Contains("passing through") && Contains("raise 'transition'"));
    }
}

TEST_CASE("power: kn, ks and fric are inherited from the ends (PFC rules)", "[power]") {
    auto proto = prototype({{"kn", 5.0}, {"ks", 6.0}, {"fric", 0.9}, {"transition", 10.0}});
    PropBlock pb = wallBlock(1.0);
    pb.kn[0] = 2e7, pb.kn[1] = 2e7;
    pb.fric[0] = 0.3, pb.fric[1] = 0.6;
    Clone c(*proto, pb);
    CHECK(prop(*c.model, "kn") == Approx(1e7));  // springs in series
    CHECK(prop(*c.model, "ks") == 6.0);          // not set on the ends: the model's own
    CHECK(prop(*c.model, "fric") == 0.3);        // minimum
}

// ============================================================================ SaveRestore

TEST_CASE("power: SaveRestore mid-contact continues bit for bit", "[power]") {
    auto proto = prototype({{"kn", 1e7},
                            {"ks", 4e6},
                            {"fric", 0.4},
                            {"transition", 800.0},
                            {"exp_mode", 3},
                            {"target_e", 0.4}});
    const PropBlock pb = wallBlock(3.0);
    auto u = [](int k) { return 3e-4 * std::sin(0.015 * k) - 1e-6; };
    auto us = [](int k) { return 2e-7 * std::cos(0.2 * k); };
    for (int cut : {40, 120}) {  // on the plateau, and while unloading
        Clone a(*proto, pb);
        for (int k = 1; k <= cut; ++k) a.step(u(k), us(k), k == 1);
        BinarySaveObject save(a.model->Version());
        a.model->SaveRestore(save);
        Clone b(*proto, pb);
        BinarySaveObject load(save.bytes(), save.DataVersion());
        b.model->SaveRestore(load);
        REQUIRE(load.atEnd());
        b.fd = a.fd;
        b.u_last = a.u_last;
        for (int k = cut + 1; k < 230; ++k) {
            a.step(u(k), us(k), false);
            b.step(u(k), us(k), false);
            REQUIRE(a.fd.n_force == b.fd.n_force);
            REQUIRE(a.fd.s_force == b.fd.s_force);
            REQUIRE(a.fd.knest == b.fd.knest);
            for (int e = 0; e < kEnergyCount; ++e) REQUIRE(a.fd.energy[e] == b.fd.energy[e]);
        }
        CHECK(prop(*a.model, "plastic") == 1.0);
        CHECK(prop(*b.model, "b_used") == prop(*a.model, "b_used"));
    }
}
