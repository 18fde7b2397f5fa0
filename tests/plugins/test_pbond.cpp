// SPDX-License-Identifier: MIT
//
// Tests of the `pbond` contact model (plugins/pbond, docs/models/pbond.md): the linear contact in
// parallel with a Potyondy & Cundall (2004) / PFC `linearpbond` bond in 2D.
//
// Closed forms (PFC's linearpbond, Itasca's documentation and 1.5; t = 1):
//   A = 2 R_b, I = 2 R_b^3 / 3, R_b = pb_rmul min(R_A, R_B) (ball-wall: R)
//   pb_kn = pb_emod / (R_A + R_B) (ball-wall: / R), pb_ks = pb_kn / pb_kratio
//   tension break at opening        pb_ten / pb_kn
//   pure-bending break at rotation  pb_ten / (pb_mcf pb_kn R_b)
//   shear break at slip (sigma = 0) pb_coh / pb_ks
//   stored energy at tension break  (pb_ten A)^2 / (2 pb_kn A)
// The break thresholds are found by bisection on the opening (rotation, slip) of a single
// loading step from the bonded state, so they are measured to round-off, not to a step size.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "contact_law_support.hpp"
#include "talus/contact_model.hpp"
#include "talus/errors.hpp"
#include "talus/model.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/save_object.hpp"

using namespace talus;
using namespace talus::lawtest;
using Catch::Matchers::Contains;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// A strength out of reach (tests that predate inf strengths; pb_ten = inf is tested below).
constexpr double kHuge = 1e300;
// The inputs of PFC's linearpbond, Itasca's documentation.
constexpr double kEbar = 62e9, kRatio = 2.5, kStrength = 157e6;
constexpr double kDt = 1e-7;

double relErr(double a, double b) { return std::fabs(a - b) / std::fabs(b); }

/// True if `x` rounds to the table's printed value `printed` given with `digits` significant
/// digits: within half a unit of its last digit (plus round-off).
bool agreesPrinted(double x, double printed, int digits) {
    const double unit = std::pow(10.0, std::floor(std::log10(std::fabs(printed))) - digits + 1);
    return std::fabs(x - printed) <= 0.5 * unit * (1.0 + 1e-9);
}

std::vector<PropValue> vectorProps(double mcf = 1.0, double fa = 0.0) {
    return {{"pb_emod", kEbar}, {"pb_kratio", kRatio}, {"pb_ten", kStrength}, {"pb_coh", kStrength},
            {"pb_mcf", mcf},    {"pb_fa", fa},         {"bonded", 1.0}};
}

/// One loading step applied to a freshly bonded contact: an optional first step `pre` of
/// overlap (compression +), then (dn, ds, dth) in one step. Returns the FdBlock of that step.
struct Load {
    double dn = 0.0, ds = 0.0, dth = 0.0;
};
FdBlock loadOnce(LawDriver& drv, ContactModel* c, double u0, const Load& l) {
    FdBlock fd = drv.block(u0, 0.0, 0.0, kDt, nullptr);  // first call: bonds here
    c->FDlaw(fd);
    REQUIRE(!(fd.flags & kFdBroken));
    FdBlock next = drv.block(u0 + l.dn, l.dn / kDt, l.ds / kDt, kDt, &fd);
    next.dtheta = l.dth;
    next.t_dot_rel = l.dth / kDt;
    c->FDlaw(next);
    return next;
}

/// The smallest scale x of `dir` at which a single step breaks the bond, by bisection
/// (the bracket [lo, hi] must hold it).
double breakThreshold(LawDriver& drv, double u0, const Load& dir, double lo, double hi,
                      int* mode = nullptr) {
    for (int i = 0; i < 200 && hi - lo > 1e-17 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        const FdBlock fd =
            loadOnce(drv, drv.clone(), u0, Load{dir.dn * mid, dir.ds * mid, dir.dth * mid});
        if (fd.flags & kFdBroken) {
            hi = mid;
            if (mode) *mode = fd.break_mode;
        } else {
            lo = mid;
        }
    }
    return hi;
}

struct Case {
    const char* name;
    double ra, rb;  // rb = 0: ball-wall
    double mcf;
};

double propOf(const ContactModel& c, const char* name) {
    for (int32_t i = 0; i < c.PropCount(); ++i)
        if (std::string(c.PropInfoAt(i)->name) == name) return c.ReturnProp(i);
    FAIL("no property " << name);
    return NAN;
}

}  // namespace

// ============================================================================ test vectors

TEST_CASE("pbond: exact break vectors of PFC's linearpbond, Itasca's documentation", "[pbond]") {
    // Bisection brackets each threshold to 1e-17 relative; the bond law is a product and a
    // quotient of the inputs, so the measured thresholds must agree with the closed forms to a
    // few ulps. 1e-9 relative (the brief's bound) leaves room for nothing but a wrong formula.
    // The table's printed values (4 significant digits, energies 3) must be what the exact
    // values round to.
    const Case cases[] = {{"P1", 1e-3, 1e-3, 1.0},
                          {"P2", 2.7e-4, 4.48e-4, 1.0},
                          {"P3", 1e-3, 1e-3, 0.5},
                          {"P5", 1e-3, 0.0, 1.0}};
    struct Table {
        double rb, kn, knA, knI, open, rot, slip, epb;
    };
    const Table table[] = {
        {1e-3, 3.1e13, 6.2e10, 2.067e4, 5.065e-6, 5.065e-3, 1.266e-5, 0.795},
        {2.7e-4, 8.635e13, 4.663e10, 1.133e3, 1.818e-6, 6.734e-3, 4.545e-6, 0.0771},
        {1e-3, 3.1e13, 6.2e10, 2.067e4, 5.065e-6, 1.013e-2, 1.266e-5, 0.795},
        {1e-3, 6.2e13, 1.24e11, 4.133e4, 2.532e-6, 2.532e-3, 6.331e-6, 0.398}};
    for (int k = 0; k < 4; ++k) {
        const Case& cs = cases[k];
        const Table& tb = table[k];
        INFO(cs.name);
        const bool wall = cs.rb == 0.0;
        LawDriver drv("pbond", vectorProps(cs.mcf), !wall, cs.ra, cs.rb, 1e-3);
        ContactModel* probe = drv.clone();
        const double rbar = propOf(*probe, "pb_rad");
        const double L = wall ? cs.ra : cs.ra + cs.rb;
        const double kn = kEbar / L, ks = kn / kRatio;
        const double A = 2.0 * rbar, I = 2.0 * rbar * rbar * rbar / 3.0;
        CHECK(relErr(rbar, tb.rb) < 1e-15);
        CHECK(relErr(propOf(*probe, "pb_kn"), kn) < 1e-15);
        CHECK(agreesPrinted(kn, tb.kn, 4));
        CHECK(agreesPrinted(kn * A, tb.knA, 4));
        CHECK(agreesPrinted(kn * I, tb.knI, 4));
        {
            FdBlock fd = drv.block(0.0, 0.0, 0.0, kDt, nullptr);
            probe->FDlaw(fd);
            CHECK(relErr(fd.knest, kn * A) < 1e-15);  // the linear part has kn = 0 here
            CHECK(relErr(fd.ksest, ks * A) < 1e-15);
            CHECK(relErr(fd.krest, kn * I) < 1e-15);
        }

        int mode = 0;
        const double open = breakThreshold(drv, 0.0, Load{-1.0, 0, 0}, 0.0, 1e-3, &mode);
        CHECK(mode == kBreakTension);
        const double rot = breakThreshold(drv, 0.0, Load{0, 0, 1.0}, 0.0, 1.0, &mode);
        CHECK(mode == kBreakTension);  // bending fails the periphery in tension
        const double slip = breakThreshold(drv, 0.0, Load{0, 1.0, 0}, 0.0, 1e-3, &mode);
        CHECK(mode == kBreakShear);
        const double e_open = relErr(open, kStrength / kn);
        const double e_rot = relErr(rot, kStrength / (cs.mcf * kn * rbar));
        const double e_slip = relErr(slip, kStrength / ks);
        std::printf(
            "pbond %s: opening %.6e (rel err %.1e), rotation %.6e (%.1e), slip %.6e (%.1e)\n",
            cs.name, open, e_open, rot, e_rot, slip, e_slip);
        CHECK(e_open < 1e-9);
        CHECK(e_rot < 1e-9);
        CHECK(e_slip < 1e-9);
        CHECK(agreesPrinted(open, tb.open, 4));
        CHECK(agreesPrinted(rot, tb.rot, 4));
        CHECK(agreesPrinted(slip, tb.slip, 4));
        if (cs.mcf == 0.5) CHECK(agreesPrinted(kStrength * I / (0.5 * rbar), 209.3, 4));

        // Stored energy at the tension break equals the work put in: open in 1000 steps to
        // just below the threshold, summing the trapezoidal work of the bond force (exact for a
        // linear spring), and compare with (pb_ten A)^2 / (2 kn A).
        ContactModel* c = drv.clone();
        FdBlock fd = drv.block(0.0, 0.0, 0.0, kDt, nullptr);
        c->FDlaw(fd);
        const int n = 1000;
        const double target = open * (1.0 - 1e-12), du = -target / n;
        double work = 0.0, u = 0.0;
        for (int i = 0; i < n; ++i) {
            u += du;
            FdBlock next = drv.block(u, du / kDt, 0.0, kDt, &fd);
            c->FDlaw(next);
            REQUIRE(!(next.flags & kFdBroken));
            work += 0.5 * (fd.n_force + next.n_force) * du;
            fd = next;
        }
        const double e_theory = 0.5 * (kStrength * A) * (kStrength * A) / (kn * A);
        const double e_pb = fd.energy[kEnergyBondStrain];
        std::printf(
            "pbond %s: E_pb at tension break %.6e J (vs work rel err %.1e, vs closed "
            "form %.1e)\n",
            cs.name, e_pb, relErr(e_pb, work), relErr(e_pb, e_theory));
        CHECK(relErr(e_pb, work) < 1e-9);
        CHECK(relErr(e_pb, e_theory) < 1e-9);
        CHECK(agreesPrinted(e_pb, tb.epb, 3));
    }
}

TEST_CASE("pbond: P4, Mohr-Coulomb shear strength under compression and its tensile cap",
          "[pbond]") {
    // P1 with pb_fa = 30 deg under a mean normal stress sigma = -0.5 pb_ten: tau_c = pb_coh +
    // 0.5 pb_ten tan 30 = 202.3 MPa (table); the slip at break is tau_c / pb_ks.
    LawDriver drv("pbond", vectorProps(1.0, 30.0), true, 1e-3, 1e-3, 1e-3);
    const double kn = kEbar / 2e-3, ks = kn / kRatio;
    const double pre = 0.5 * kStrength / kn;  // overlap step giving sigma = -0.5 pb_ten
    // The pre-load step precedes the shear step: drive both within loadOnce's two calls by
    // bonding at u0 = 0, compressing by `pre` in the first loaded step, then shearing.
    auto breaks = [&](double slip) {
        ContactModel* c = drv.clone();
        FdBlock fd = drv.block(0.0, 0.0, 0.0, kDt, nullptr);
        c->FDlaw(fd);
        FdBlock f1 = drv.block(pre, pre / kDt, 0.0, kDt, &fd);
        c->FDlaw(f1);
        REQUIRE(!(f1.flags & kFdBroken));
        REQUIRE(relErr(-propOf(*c, "pb_fn") / 2e-3, -0.5 * kStrength) < 1e-12);
        FdBlock f2 = drv.block(pre, 0.0, slip / kDt, kDt, &f1);
        c->FDlaw(f2);
        return (f2.flags & kFdBroken) != 0 && f2.break_mode == kBreakShear;
    };
    double lo = 0.0, hi = 1e-3;
    for (int i = 0; i < 200 && hi - lo > 1e-17 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        if (breaks(mid))
            hi = mid;
        else
            lo = mid;
    }
    const double tau_c = kStrength + 0.5 * kStrength * std::tan(M_PI / 6.0);
    std::printf("pbond P4: tau_c %.6e Pa (rel err %.1e)\n", hi * ks, relErr(hi * ks, tau_c));
    CHECK(relErr(hi * ks, tau_c) < 1e-9);
    CHECK(agreesPrinted(tau_c, 202.3e6, 4));

    // The envelope without a cap on its tension side (pb_ten = inf): a bond under a mean
    // tensile stress s >= pb_coh / tan(pb_fa) has no shear strength left and fails in shear at
    // the least shear. (PFC's cap, s limited to pb_ten, cannot change a break decision: s >
    // pb_ten means sigma >= s > pb_ten, and the tension check comes first.)
    LawDriver weak("pbond",
                   {{"pb_kn", kn},
                    {"pb_ks", ks},
                    {"pb_ten", kInf},
                    {"pb_coh", 1e6},
                    {"pb_fa", 45.0},
                    {"bonded", 1.0}},
                   true, 1e-3, 1e-3, 1e-3);
    ContactModel* c = weak.clone();
    FdBlock fd = weak.block(0.0, 0.0, 0.0, kDt, nullptr);
    c->FDlaw(fd);
    const double open = 1.0001e6 / kn;  // s = 1.0001 MPa > pb_coh / tan 45
    FdBlock f1 = weak.block(-open, -open / kDt, 1e-20 / kDt, kDt, &fd);
    c->FDlaw(f1);
    CHECK((f1.flags & kFdBroken));
    CHECK(f1.break_mode == kBreakShear);
    CHECK(propOf(*c, "pb_state") == 2.0);
}

// ============================================================================ energies

TEST_CASE("pbond: a break crossing the tensile range in one step: corner, release at failure",
          "[pbond]") {
    // Bonded at u = 0 (A = 2e-3 m^2, kbn = pb_kn A = 6e10 N/m, no linear part), compressed by
    // 1e-9 m (F_old = 60 N), then opened by 1e-8 m in one step: the trial force is -540 N, past
    // pb_ten A = 2 N. The failure is where F(g) = -2 N: g = 62/600. Owed on this step is the
    // ramp's integral from dt/2 to g dt, F_old (g - 1/2) + (F_t - F_old)(g^2 - 1/4)/2, and
    // released is what the spring held there, 2^2 / (2 kbn); the event's sigma is pb_ten.
    // Tolerances: g by bisection to 2^-60, so 1e-12 relative on forces and energies.
    const double ten = 1e3, A = 2e-3, kbn = 3e13 * A;
    LawDriver drv(
        "pbond",
        {{"pb_kn", 3e13}, {"pb_ks", 1e13}, {"pb_ten", ten}, {"pb_coh", 1e8}, {"bonded", 1.0}}, true,
        1e-3, 2e-3, 1e-3);
    ContactModel* c = drv.clone();
    FdBlock fd = drv.block(0.0, 0.0, 0.0, kDt, nullptr);
    c->FDlaw(fd);
    FdBlock f1 = drv.block(1e-9, 1e-9 / kDt, 0.0, kDt, &fd);
    c->FDlaw(f1);
    REQUIRE(!(f1.flags & kFdBroken));
    CHECK(relErr(f1.n_force, kbn * 1e-9) < 1e-12);
    FdBlock f2 = drv.block(-9e-9, -1e-8 / kDt, 0.0, kDt, &f1);
    c->FDlaw(f2);
    REQUIRE((f2.flags & kFdBroken) != 0);
    CHECK(f2.break_mode == kBreakTension);
    const double f_old = kbn * 1e-9, f_t = f_old - kbn * 1e-8, f_g = -ten * A;
    const double g = (f_old - f_g) / (f_old - f_t);
    const double corner = f_old * (g - 0.5) + 0.5 * (f_t - f_old) * (g * g - 0.25);
    CHECK(relErr(f2.n_force, corner) < 1e-12);
    CHECK(relErr(f2.energy[kEnergyReleased], f_g * f_g / (2.0 * kbn)) < 1e-12);
    CHECK(f2.energy[kEnergyReleased] > 0.0);  // F_old F_trial / 2k would be -2.7e-8 J
    CHECK((f2.flags & kFdBreakStress) != 0);
    CHECK(relErr(f2.reserved[0], ten) < 1e-12);
    CHECK(f2.reserved[1] == 0.0);
    CHECK(relErr(propOf(*c, "pb_sigma"), ten) < 1e-12);
}

TEST_CASE(
    "pbond: combined loading stores exactly the work put in, a break releases F_old F_trial / 2k",
    "[pbond]") {
    LawDriver drv(
        "pbond",
        {{"pb_kn", 3e13}, {"pb_ks", 1e13}, {"pb_ten", 1e8}, {"pb_coh", 1e8}, {"bonded", 1.0}}, true,
        1e-3, 2e-3, 1e-3);
    ContactModel* c = drv.clone();
    FdBlock fd = drv.block(0.0, 0.0, 0.0, kDt, nullptr);
    c->FDlaw(fd);
    // Opening, shear and rotation together, in steps of varying size (the work of a linear
    // spring under any path is exactly its stored energy: trapezoidal sums are exact here).
    double work = 0.0, u = 0.0;
    int steps = 0;
    FdBlock prev = fd;
    for (;; ++steps) {
        const double s = 1.0 + 0.5 * std::sin(0.37 * steps);
        const double dn = -2e-9 * s, ds = 3e-9 * s, dth = 1e-6 * s;
        u += dn;
        FdBlock next = drv.block(u, dn / kDt, ds / kDt, kDt, &prev);
        next.dtheta = dth;
        c->FDlaw(next);
        if (next.flags & kFdBroken) {
            // released = sum over the springs of F_old F_trial / (2k); reconstruct the trial
            // forces from the increments.
            const double A = 2e-3, I = 2e-9 / 3.0;
            const double kbn = 3e13 * A, kbs = 1e13 * A, kbr = 3e13 * I;
            const double fn_t = prev.n_force + kbn * dn, fs_t = prev.s_force - kbs * ds,
                         m_t = prev.moment - kbr * dth;
            const double want = 0.5 * (prev.n_force * fn_t / kbn + prev.s_force * fs_t / kbs +
                                       prev.moment * m_t / kbr);
            CHECK(relErr(next.energy[kEnergyReleased], want) < 1e-12);
            CHECK(next.energy[kEnergyBondStrain] == 0.0);
            CHECK(next.n_force == 0.0);  // linear part: separated, no force
            CHECK(next.s_force == 0.0);
            CHECK(next.moment == 0.0);
            CHECK(next.knest == 0.0);
            CHECK(next.krest == 0.0);
            CHECK(!(next.flags & kFdKeep));
            CHECK(c->OKToDelete());
            break;
        }
        CHECK(relErr(next.energy[kEnergyBondStrain],
                     work + 0.5 * ((prev.n_force + next.n_force) * dn -
                                   (prev.s_force + next.s_force) * ds -
                                   (prev.moment + next.moment) * dth)) < 1e-9);
        work += 0.5 * ((prev.n_force + next.n_force) * dn - (prev.s_force + next.s_force) * ds -
                       (prev.moment + next.moment) * dth);
        CHECK((next.flags & kFdKeep));
        CHECK(!c->OKToDelete());
        prev = next;
        REQUIRE(steps < 100000);
    }
    CHECK(steps > 10);
}

// ============================================================================ properties

TEST_CASE("pbond: bad input is refused, naming the property", "[pbond]") {
    CHECK_THAT(modelError("pbond", {{"pb_kn", -1.0}}), Contains("pb_kn"));
    CHECK_THAT(modelError("pbond", {{"pb_rmul", 0.0}}), Contains("pb_rmul"));
    CHECK_THAT(modelError("pbond", {{"pb_rmul", -2.0}}), Contains("pb_rmul"));
    CHECK_THAT(modelError("pbond", {{"pb_ten", NAN}}), Contains("pb_ten"));
    CHECK_THAT(modelError("pbond", {{"pb_ks", NAN}}), Contains("pb_ks"));
    CHECK_THAT(modelError("pbond", {{"pb_mcf", 1.5}}), Contains("pb_mcf"));
    CHECK_THAT(modelError("pbond", {{"pb_fa", -3.0}}), Contains("pb_fa"));
    CHECK_THAT(modelError("pbond", {{"pb_kn", kInf}}), Contains("pb_kn"));
    CHECK_THAT(modelError("pbond", {{"kn", -1.0}}), Contains("kn"));
    CHECK_THAT(modelError("pbond", {{"lin_mode", 2.0}}), Contains("lin_mode"));
    CHECK_THAT(modelError("pbond", {{"bonded", 0.5}}), Contains("bonded"));
    CHECK_THAT(modelError("pbond", {{"pb_state", 3.0}}), Contains("read-only"));
    CHECK_THAT(modelError("pbond", {{"pb_emod", 1e9}}), Contains("pb_kratio"));
    CHECK_THAT(modelError("pbond", {{"emod", 1e9}}), Contains("kratio"));
    // An unbreakable bond: +inf strengths pass the host (props.cpp lets +inf through for a
    // stress) and pbond accepts them; -inf is no stress, and a modulus in Pa stays finite.
    CHECK(modelError("pbond", {{"pb_ten", kInf}, {"pb_coh", kInf}}).empty());
    CHECK_THAT(modelError("pbond", {{"pb_ten", -kInf}}), Contains("pb_ten"));
    CHECK_THAT(modelError("pbond", {{"pb_emod", kInf}}), Contains("pb_emod"));
    CHECK_THAT(modelError("pbond", {{"emod", kInf}}), Contains("emod"));
    CHECK(modelError("pbond", {{"pb_ten", kHuge}, {"pb_coh", kHuge}}).empty());
    CHECK(modelError("pbond", {{"kn", 1e8}, {"pb_kn", 1e12}, {"bonded", 1.0}}).empty());
}

TEST_CASE("pbond: declares itself a bond, bonded is settable, pb_state read-only", "[pbond]") {
    LawDriver drv("pbond",
                  {{"kn", 1e8},
                   {"ks", 1e8},
                   {"pb_kn", 1e12},
                   {"pb_ks", 1e12},
                   {"pb_ten", kHuge},
                   {"pb_coh", kHuge}},
                  true, 0.01, 0.02, 1.0);
    CHECK(drv.prototype().Traits() == (kTraitThreadSafe | kTraitBond));
    ContactModel* c = drv.clone();
    CHECK(propOf(*c, "pb_state") == 0.0);
    CHECK(c->OKToDelete());
    int32_t ib = -1;
    for (int32_t i = 0; i < c->PropCount(); ++i)
        if (std::string(c->PropInfoAt(i)->name) == "bonded") ib = i;
    REQUIRE(ib >= 0);
    // Touching at 1e-6 m overlap, then bonded by the host (m:bond's path).
    FdBlock fd = drv.block(1e-6, 0.0, 0.0, kDt, nullptr);
    c->FDlaw(fd);
    CHECK(fd.n_force == Approx(100.0));
    REQUIRE(c->AcceptProp(ib, 1.0) == 0);
    CHECK(propOf(*c, "pb_state") == 3.0);
    CHECK(!c->OKToDelete());
    CHECK(c->KnEstimate() == Approx(1e8 + 1e12 * 0.02));
    // The bond starts force-free at the current geometry: the next step's increment is not
    // counted; the one after is.
    FdBlock f1 = drv.block(1e-6, 0.0, 0.0, kDt, &fd);
    c->FDlaw(f1);
    CHECK(propOf(*c, "pb_fn") == 0.0);
    CHECK((f1.flags & kFdBonded));
    FdBlock f2 = drv.block(1e-6 - 1e-9, -1e-9 / kDt, 0.0, kDt, &f1);
    c->FDlaw(f2);
    CHECK(propOf(*c, "pb_fn") == Approx(-1e12 * 0.02 * 1e-9));
    CHECK(f2.n_force == Approx(1e8 * (1e-6 - 1e-9) - 1e12 * 0.02 * 1e-9));
    // Unbonding: no event, the bond's force gone from the next step on, and that step releases
    // what the bond took from the bodies: F_old F_trial / (2k), F_old = -20 N the force of its
    // last step, F_trial = -40 N the one the next step's opening (another 1e-9 m) would give.
    REQUIRE(c->AcceptProp(ib, 0.0) == 0);
    CHECK(propOf(*c, "pb_state") == 0.0);
    CHECK(propOf(*c, "pb_fn") == 0.0);
    const double kbn = 1e12 * 0.02;
    // The pending release survives a save and restore (pbond version 2).
    BinarySaveObject saver(c->Version());
    c->SaveRestore(saver);
    ContactModel* restored = drv.clone();
    BinarySaveObject loader(saver.bytes(), c->Version());
    restored->SaveRestore(loader);
    CHECK(loader.atEnd());
    FdBlock f3 = drv.block(1e-6 - 2e-9, -1e-9 / kDt, 0.0, kDt, &f2);
    FdBlock r3 = f3;
    c->FDlaw(f3);
    restored->FDlaw(r3);
    CHECK(r3.energy[kEnergyReleased] == f3.energy[kEnergyReleased]);
    CHECK(!(f3.flags & (kFdBroken | kFdBonded | kFdKeep)));
    CHECK(relErr(f3.energy[kEnergyReleased], 20.0 * 40.0 / (2.0 * kbn)) < 1e-9);
    CHECK(f3.energy[kEnergyBondStrain] == 0.0);
    CHECK(f3.n_force == Approx(1e8 * (1e-6 - 2e-9)));
    // Released once.
    FdBlock f4 = drv.block(1e-6 - 2e-9, 0.0, 0.0, kDt, &f3);
    c->FDlaw(f4);
    CHECK(f4.energy[kEnergyReleased] == 0.0);
}

TEST_CASE("pbond: first call adopts the entry forces, lin_mode 1 is incremental", "[pbond]") {
    const double kn = 1e8, ks = 5e7;
    SECTION("incremental: the old contact's forces plus this step's increment") {
        LawDriver drv("pbond", {{"kn", kn}, {"ks", ks}, {"fric", 0.5}, {"lin_mode", 1.0}}, true,
                      0.01, 0.01, 1.0);
        ContactModel* c = drv.clone();
        FdBlock fd = drv.block(2e-6, 1e-3, 2e-3, kDt, nullptr);
        fd.n_force = 150.0;  // the old model's forces on entry (m:bond)
        fd.s_force = -20.0;
        c->FDlaw(fd);
        CHECK(fd.n_force == Approx(150.0 + kn * 1e-3 * kDt).epsilon(1e-12));
        CHECK(fd.s_force == Approx(-20.0 - ks * 2e-3 * kDt).epsilon(1e-12));
        // reset = true: zero entry forces, stress-free start although overlapping.
        ContactModel* r = drv.clone();
        FdBlock fr = drv.block(2e-6, 0.0, 0.0, kDt, nullptr);
        r->FDlaw(fr);
        CHECK(fr.n_force == 0.0);
        FdBlock fr2 = drv.block(2e-6 + 1e-8, 1e-8 / kDt, 0.0, kDt, &fr);
        r->FDlaw(fr2);
        CHECK(fr2.n_force == Approx(kn * 1e-8).epsilon(1e-9));
        // Unloading by more than it carries: no tension in the linear part.
        FdBlock fr3 = drv.block(2e-6 - 1e-8, -2e-8 / kDt, 0.0, kDt, &fr2);
        r->FDlaw(fr3);
        CHECK(fr3.n_force == 0.0);
    }
    SECTION("absolute: kn u_n, the shear force carried over") {
        LawDriver drv("pbond", {{"kn", kn}, {"ks", ks}, {"fric", 0.5}}, true, 0.01, 0.01, 1.0);
        ContactModel* c = drv.clone();
        FdBlock fd = drv.block(2e-6, 1e-3, 2e-3, kDt, nullptr);
        fd.n_force = 150.0;
        fd.s_force = -20.0;
        c->FDlaw(fd);
        CHECK(fd.n_force == Approx(kn * 2e-6).epsilon(1e-12));
        CHECK(fd.s_force == Approx(-20.0 - ks * 2e-3 * kDt).epsilon(1e-12));
    }
}

TEST_CASE("pbond: unbonded it is the linear model, sample by sample", "[pbond]") {
    // An oblique impact history with dashpots (dp_nratio 0.3, dp_sratio 0.2): approach from a
    // gap, load, slide, separate. pbond without a bond must give linear's forces and energies
    // bit for bit (the same SDK pieces in the same order).
    const std::vector<PropValue> props = {{"kn", 1e7},        {"ks", 6e6},        {"fric", 0.3},
                                          {"dp_nratio", 0.3}, {"dp_sratio", 0.2}, {"dp_mode", 0.0}};
    LawDriver lin("linear", props, true, 0.05, 0.07, 2.0);
    LawDriver pb("pbond", props, true, 0.05, 0.07, 2.0);
    ContactModel* a = lin.clone();
    ContactModel* b = pb.clone();
    FdBlock fa{}, fb{};
    bool have = false;
    const double dt = 1e-5;
    int n = 0;
    for (int i = 0; i < 400; ++i) {
        const double t = i * dt;
        const double u = -1e-6 + 2e-3 * std::sin(M_PI * t / 2e-3);
        const double uprev = -1e-6 + 2e-3 * std::sin(M_PI * (t - dt) / 2e-3);
        if (u <= 0.0 && !have) continue;
        FdBlock na =
            lin.block(u, (u - uprev) / dt, 0.3 * std::cos(t * 900.0), dt, have ? &fa : nullptr);
        FdBlock nb = na;
        if (have) nb.n_force = fb.n_force, nb.s_force = fb.s_force, nb.moment = fb.moment;
        a->FDlaw(na);
        b->FDlaw(nb);
        CHECK(na.n_force == nb.n_force);
        CHECK(na.s_force == nb.s_force);
        CHECK(na.knest == nb.knest);
        for (int k = 0; k < kEnergyCount; ++k) CHECK(na.energy[k] == nb.energy[k]);
        fa = na, fb = nb, have = true;
        ++n;
        if (u < 0.0) break;
    }
    CHECK(n > 50);
}

TEST_CASE("pbond: save/restore continues bit-identically, bonded and after the break", "[pbond]") {
    LawDriver drv("pbond",
                  {{"kn", 1e8},
                   {"ks", 5e7},
                   {"fric", 0.4},
                   {"dp_nratio", 0.2},
                   {"lin_mode", 1.0},
                   {"pb_emod", 1e10},
                   {"pb_kratio", 2.0},
                   {"pb_ten", 2e6},
                   {"pb_coh", 3e7},
                   {"pb_fa", 20.0},
                   {"bonded", 1.0}},
                  true, 0.01, 0.015, 0.5);
    // Compress, then pull apart with shear until the bond breaks (about step 140 of 200).
    std::vector<double> u, us;
    for (int i = 0; i < 200; ++i) {
        u.push_back(1e-6 + 2e-8 * i - 4e-10 * i * i);
        us.push_back(3e-9 * i);
    }
    for (std::size_t split : {std::size_t(30), std::size_t(150)}) {
        int compared = 0;
        CHECK(saveRestoreContinuesExactly(drv, u, us, 1e-6, split, &compared));
        CHECK(compared > 0);
    }
}

// ============================================================================ engine

namespace {

constexpr double kR = 0.01, kPbKn = 2e13, kPbKs = 1e13, kEngineDt = 1e-8;

/// Two balls on the x axis overlapping by 1e-9 m, bonded on the first cycle (a rule with
/// bonded = 1), then held at constant velocities by fixity.
struct Pair {
    Model m;
    BallId a, b;
    std::vector<Event> events;
    explicit Pair(double ten, double coh, double mcf = 1.0) {
        m.setDefaultContactModel("pbond", {{"kn", 1e6},
                                           {"ks", 1e6},
                                           {"fric", 0.5},
                                           {"pb_kn", kPbKn},
                                           {"pb_ks", kPbKs},
                                           {"pb_ten", ten},
                                           {"pb_coh", coh},
                                           {"pb_mcf", mcf},
                                           {"bonded", 1.0}});
        m.timestep().automatic = false;
        m.timestep().fixed = kEngineDt;
        m.guard().resolution = GuardAction::Off;
        BallDef d;
        d.radius = kR;
        d.density = 2600.0;
        d.pos = Vec2(-kR + 0.5e-9, 0.0);
        a = m.createBall(d);
        d.pos = Vec2(kR - 0.5e-9, 0.0);
        b = m.createBall(d);
        for (BallId id : {a, b}) m.setBallFixity(id, kFixX | kFixY | kFixSpin);
        m.setEventHandler([this](const Event& e) { events.push_back(e); });
        m.cycle(1);
    }
    double prop(const char* name) const {
        const auto all = m.contacts();
        REQUIRE(all.size() == 1);
        return m.contactProp(all[0].key, name);
    }
    ContactInfo contact() const {
        const auto all = m.contacts();
        REQUIRE(all.size() == 1);
        return all[0];
    }
};

}  // namespace

TEST_CASE("pbond on the engine: pure tension breaks at opening pb_ten / pb_kn", "[pbond]") {
    const double ten = 1e7, v = 0.3;  // opening at break 5e-7 m = v k dt at k = 166.7 -> 167
    Pair p(ten, kHuge);
    CHECK(p.prop("pb_state") == 3.0);
    CHECK(p.prop("pb_rad") == Approx(kR));
    p.m.setBallVel(p.a, Vec2(-0.5 * v, 0.0));
    p.m.setBallVel(p.b, Vec2(0.5 * v, 0.0));
    const int k_break = int(std::ceil(ten / (kPbKn * v * kEngineDt) - 1e-9));
    const double A = 2.0 * kR;
    for (int k = 1; k < k_break; ++k) {
        p.m.cycle(1);
        CHECK(p.prop("pb_fn") == Approx(-kPbKn * A * v * k * kEngineDt).epsilon(1e-6));
        CHECK(p.prop("pb_sigma") == Approx(kPbKn * v * k * kEngineDt).epsilon(1e-6));
    }
    CHECK(p.events.empty());
    CHECK(p.contact().overlap < 0.0);  // kept although separated: bonded
    p.m.cycle(1);
    REQUIRE(p.events.size() == 1);
    CHECK(p.events[0].kind == EventKind::BondBreak);
    CHECK(p.events[0].mode == kBreakTension);
    CHECK(p.events[0].model == "pbond");
    CHECK(p.m.contactCount() == 0);  // separated and unbonded: gone in the breaking step
}

TEST_CASE("pbond on the engine: pure shear breaks at slip pb_coh / pb_ks, then slides", "[pbond]") {
    const double coh = 5e6, w = 0.2;  // slip at break 5e-7 m: k = 250 (exactly; ceil)
    Pair p(kHuge, coh);
    p.m.setBallVel(p.b, Vec2(0.0, w));
    const int k_break = int(std::ceil(coh / (kPbKs * w * kEngineDt) * (1 + 1e-12)));
    const double A = 2.0 * kR;
    for (int k = 1; k < k_break - 1; ++k) p.m.cycle(1);
    CHECK(std::fabs(p.prop("pb_fs")) ==
          Approx(kPbKs * A * w * (k_break - 2) * kEngineDt).epsilon(1e-4));
    CHECK(p.events.empty());
    p.m.cycle(3);
    REQUIRE(p.events.size() == 1);
    CHECK(p.events[0].mode == kBreakShear);
    CHECK(p.prop("pb_state") == 2.0);
    CHECK(p.prop("pb_fs") == 0.0);
    // The linear part carries on: overlap 1e-9 m, kn 1e6 -> F_n 1e-3 N; it slides at fric F_n.
    p.m.cycle(50);
    const ContactInfo c = p.contact();
    CHECK(c.sliding);
    CHECK(std::fabs(c.shear_force) == Approx(0.5 * c.normal_force).epsilon(1e-6));
}

TEST_CASE("pbond on the engine: pure bending breaks at rotation pb_ten / (mcf pb_kn R)",
          "[pbond]") {
    // Opposite spins: the contact point does not slide (w R each way), the relative rotation
    // grows at w. M = -pb_kn I theta, sigma = mcf |M| R / I = mcf pb_kn R theta.
    const double ten = 1e7, w = 2.0, mcf = 0.5;  // theta at break 1e-4 rad: k = 5000
    Pair p(ten, kHuge, mcf);
    p.m.setBallSpin(p.a, -0.5 * w);
    p.m.setBallSpin(p.b, 0.5 * w);
    const double I = 2.0 * kR * kR * kR / 3.0;
    const int k_break = int(std::ceil(ten / (mcf * kPbKn * kR * w * kEngineDt) * (1 + 1e-12)));
    p.m.cycle(k_break - 2);
    CHECK(p.prop("pb_m") == Approx(-kPbKn * I * w * (k_break - 2) * kEngineDt).epsilon(1e-6));
    CHECK(std::fabs(p.prop("pb_fs")) < 1e-9 * std::fabs(p.prop("pb_m")) / kR);
    CHECK(p.events.empty());
    p.m.cycle(3);
    REQUIRE(p.events.size() == 1);
    CHECK(p.events[0].mode == kBreakTension);
    CHECK(p.prop("pb_state") == 1.0);
    CHECK(p.prop("pb_m") == 0.0);
}

namespace {

/// A ball (R 0.05 m) dropped from 1 m on a floor, or a pair of balls meeting obliquely with spin
/// (`pair`), gravity, traced for 3 s of bounces at the default step; returns balance_error over
/// the throughput.
double bounceBalance(const std::string& model, double lin_mode, double beta, bool pair) {
    ModelDef def;
    def.gravity = Vec2(0.0, -9.81);
    Model m(def);
    std::vector<PropValue> props = {
        {"kn", 1e6}, {"ks", 5e5}, {"fric", 0.3}, {"dp_nratio", beta}, {"dp_sratio", beta}};
    if (model == "pbond") props.push_back({"lin_mode", lin_mode});
    m.setDefaultContactModel(model, props);
    m.setWarningHandler([](const std::string&) {});
    WallDef floor;
    floor.points = {Vec2(-10.0, 0.0), Vec2(10.0, 0.0)};
    m.createWall(floor);
    BallDef d;
    d.radius = 0.05;
    d.density = 2600.0;
    if (pair) {
        d.pos = Vec2(0.0, 0.3), d.vel = Vec2(1.0, 0.0);
        m.createBall(d);
        d.pos = Vec2(0.3, 0.5), d.vel = Vec2(-1.0, -1.0), d.spin = -20.0;
        m.createBall(d);
    } else {
        d.pos = Vec2(0.0, 1.0);
        m.createBall(d);
    }
    m.setEnergyTracing(true);
    m.solveTime(3.0);
    const EnergyTotals e = m.energies();
    return e.balanceError() / std::max(e.input(), e.kinetic + e.strain);
}

}  // namespace

// History: until 2026-11-28 the linear law in incremental mode (lin_mode 1, which m:bond's
// reset = true switches on) paid no normal corner and no dashpot corner at separation, and its
// normal force there left the books: a ball bouncing for 3 s on pbond with lin_mode 1 lost
// 1.1e-3 of its throughput unbooked, against linear's 3e-7. Now the force is paid the corner of
// a force that runs on at kn u_dot_n from its last value to separation
// (talus/sdk/corners.hpp, incrementalClosing), and what it still holds there is released.
TEST_CASE("pbond lin_mode 1, unbonded: a bouncing ball's balance closes as linear's", "[pbond]") {
    for (double beta : {0.0, 0.3}) {
        // On a floor the normal does not turn: the incremental force is kn u_n to round-off,
        // and the books are linear's.
        const double lin = bounceBalance("linear", 0.0, beta, false);
        const double inc = bounceBalance("pbond", 1.0, beta, false);
        INFO("dp_nratio " << beta << ": linear " << lin << ", pbond lin_mode 1 " << inc);
        if (beta == 0.0) CHECK(std::fabs(lin) < 1e-4);
        CHECK(std::fabs(inc - lin) <= 1e-9);
        // Two balls meeting obliquely with spin: the normal turns, the incremental force is not
        // kn u_n, the balance closes to the same order (measured 1.91e-3 against linear's
        // 1.89e-3 at dp_nratio 0.2; 2.49e-3 before).
        const double lin_pair = bounceBalance("linear", 0.0, beta, true);
        const double inc_pair = bounceBalance("pbond", 1.0, beta, true);
        INFO("pair: linear " << lin_pair << ", pbond lin_mode 1 " << inc_pair);
        CHECK(std::fabs(inc_pair) < 1.2 * std::fabs(lin_pair) + 1e-6);
    }
}

// The bond_break event carries the bond's half width as the model had it when the bond broke
// (Event::radius): pb_rmul min(R). The pair is pulled apart, so its contact ends in the
// breaking step and the model object is a fresh one by the time the event is delivered; until
// 2026-11-28 the event had no size and cracks took the smaller ball's radius.
TEST_CASE("pbond on the engine: the bond_break event carries the bond's radius", "[pbond]") {
    for (double rmul : {0.5, 1.5}) {
        Model m;
        m.setDefaultContactModel("pbond", {{"kn", 1e6},
                                           {"ks", 1e6},
                                           {"pb_kn", kPbKn},
                                           {"pb_ks", kPbKs},
                                           {"pb_ten", 1e7},
                                           {"pb_coh", kHuge},
                                           {"pb_rmul", rmul},
                                           {"bonded", 1.0}});
        std::vector<Event> events;
        m.setEventHandler([&](const Event& e) { events.push_back(e); });
        BallDef d;
        d.density = 2600.0;
        d.radius = kR;
        d.pos = Vec2(-kR + 0.5e-9, 0.0);
        const BallId a = m.createBall(d);
        d.radius = 0.6 * kR;
        d.pos = Vec2(0.6 * kR - 0.5e-9, 0.0);
        const BallId b = m.createBall(d);
        m.cycle(1);
        m.setBallVel(a, Vec2(-1.0, 0.0));
        m.setBallVel(b, Vec2(1.0, 0.0));
        for (int i = 0; i < 5000 && events.empty(); ++i) m.cycle(1);
        REQUIRE(events.size() == 1);
        CHECK(m.contactCount() == 0);
        CHECK(events[0].radius == Approx(rmul * 0.6 * kR).epsilon(1e-15));
    }
}
