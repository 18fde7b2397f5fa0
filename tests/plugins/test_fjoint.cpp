// SPDX-License-Identifier: MIT
//
// Tests of the `fjoint` contact model (plugins/fjoint, docs/models/fjoint.md): the 2D flat joint
// of Potyondy (2012).
//
// Closed forms for an interface of half-length R, N elements of length L = 2R/N centred at
// x_e = -R + (e + 1/2) L, stiffnesses kn, ks per unit area, t = 1:
//   A = 2R, I = 2R^3/3; bonded: F_n = kn A d, M = -kn I theta (a Winkler layer, exact for any N)
//   tension: every element has sigma = kn d, so all N break together at opening fj_ten / kn
//   shear (sigma = 0): all break together at slip fj_coh / ks; with a pre-compression sigma,
//     at slip (fj_coh - sigma tan fj_fa) / ks
//   bending (d = 0): element e's centroid stress is kn |x_e| theta; the j-th break (j = 1 the
//     outermost) comes at theta_j = fj_ten / (kn (R - (j - 1/2) L)); the first at
//     theta_1 = fj_ten / (kn R (1 - 1/N)), with moment M_1 = kn I theta_1 = (2/3) R^2 fj_ten
//     N / (N - 1); with k elements broken (open) M = -kn theta sum_intact (L x_e^2 + L^3/12)
//   an unbonded interface at closure d and rotation theta: the continuum Winkler integrals over
//     the closed part; at a constant normal force F, once it rocks on its edge, the contact
//     width is w = sqrt(2F / (kn theta)) and M = -F (R - w/3): |M| < F R, tending to F R.
// Thresholds are found by bisection on the size of a single loading step, so they are
// measured to round-off, not to a step size.
#include <algorithm>
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
#include "talus/save_object.hpp"

using namespace talus;
using namespace talus::lawtest;
using Catch::Matchers::Contains;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDt = 1e-7;
constexpr double kRad = 1e-3;  // both balls: R = fj_rmul min(R_A, R_B) = 1 mm
constexpr double kKn = 1e13, kKs = 4e12, kTen = 1e7, kCoh = 2e7;

double relErr(double a, double b) { return std::fabs(a - b) / std::fabs(b); }

int propIndex(const ContactModel& c, const char* name) {
    for (int32_t i = 0; i < c.PropCount(); ++i)
        if (std::string(c.PropInfoAt(i)->name) == name) return i;
    return -1;
}
double propOf(const ContactModel& c, const char* name) {
    const int i = propIndex(c, name);
    if (i < 0) FAIL("no property " << name);
    return c.ReturnProp(i);
}
void setProp(ContactModel& c, const char* name, double v) {
    const int i = propIndex(c, name);
    REQUIRE(i >= 0);
    REQUIRE(c.AcceptProp(i, v) == 0);
}

std::vector<PropValue> props(int n, std::vector<PropValue> extra = {}) {
    std::vector<PropValue> p = {{"fj_kn", kKn},   {"fj_ks", kKs},       {"fj_ten", kTen},
                                {"fj_coh", kCoh}, {"fj_nr", double(n)}, {"fj_fric", 0.5},
                                {"bonded", 1.0}};
    for (const auto& e : extra) {
        bool found = false;
        for (auto& q : p)
            if (q.name == e.name) q.value = e.value, found = true;
        if (!found) p.push_back(e);
    }
    return p;
}

/// One contact driven through the ABI: installed (or touched) at overlap u0 by its first call,
/// then steps of (dn, ds, dth) with the increments given exactly. Sums the trapezoidal work of
/// the reported forces and the booked slip and release.
struct Run {
    LawDriver& drv;
    ContactModel* c;
    FdBlock prev{};
    double u;
    double work = 0.0, slip = 0.0, released = 0.0, work_abs = 0.0;
    Run(LawDriver& d, double u0 = 0.0, double fn_entry = 0.0, double fs_entry = 0.0)
        : drv(d), c(d.clone()), u(u0) {
        prev = drv.block(u0, 0.0, 0.0, kDt, nullptr);
        prev.n_force = fn_entry;
        prev.s_force = fs_entry;
        c->FDlaw(prev);
        released += prev.energy[kEnergyReleased];
    }
    FdBlock step(double dn, double ds, double dth) {
        u += dn;
        FdBlock fd = drv.block(u, dn / kDt, ds / kDt, kDt, &prev);
        fd.du_n = dn;
        fd.du_s = ds;
        fd.dtheta = dth;
        fd.t_dot_rel = dth / kDt;
        c->FDlaw(fd);
        const double w = 0.5 * ((prev.n_force + fd.n_force) * dn -
                                (prev.s_force + fd.s_force) * ds - (prev.moment + fd.moment) * dth);
        work += w;
        work_abs += std::fabs(w);
        slip += fd.energy[kEnergySlip];
        released += fd.energy[kEnergyReleased];
        prev = fd;
        return fd;
    }
    double stored() const { return prev.energy[kEnergyStrain] + prev.energy[kEnergyBondStrain]; }
    /// Work put in minus what is stored, slid and released [J].
    double residual() const { return work - stored() - slip - released; }
    double prop(const char* name) const { return propOf(*c, name); }
};

double elemCentre(int e, int n) { return -kRad + (e + 0.5) * 2.0 * kRad / n; }

/// The smallest x at which `breaks(x)` holds, by bisection in [lo, hi].
template <class F>
double threshold(F breaks, double lo, double hi) {
    for (int i = 0; i < 200 && hi - lo > 1e-16 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        (breaks(mid) ? hi : lo) = mid;
    }
    return hi;
}

}  // namespace

// ============================================================================ properties

TEST_CASE("fjoint: properties by name, geometry, deformability", "[fjoint]") {
    LawDriver drv("fjoint",
                  {{"fj_emod", 6e10}, {"fj_kratio", 2.5}, {"fj_rmul", 0.8}, {"fj_nr", 4.0}}, true,
                  1e-3, 3e-3, 1e-3);
    CHECK(drv.prototype().Traits() == (kTraitThreadSafe | kTraitBond));
    ContactModel* c = drv.clone();
    for (const char* name :
         {"fj_kn",    "fj_ks",     "fj_emod",  "fj_kratio", "fj_nr",    "fj_rmul", "fj_ten",
          "fj_coh",   "fj_fa",     "fj_fric",  "fj_gap0",   "fj_mtype", "bonded",  "fj_elem",
          "fj_nbond", "fj_radius", "fj_area",  "fj_gap",    "fj_relbr", "fj_fn",   "fj_fs",
          "fj_m",     "fj_state",  "fj_sigma", "fj_tau",    "fj_shear", "fj_egap", "fj_slip"})
        CHECK(propIndex(*c, name) >= 0);
    // fj_kn = E / (R_A + R_B), fj_ks = fj_kn / kratio; R = rmul min(R_A, R_B); L = 2R/N.
    CHECK(relErr(propOf(*c, "fj_kn"), 6e10 / 4e-3) < 1e-15);
    CHECK(relErr(propOf(*c, "fj_ks"), 6e10 / 4e-3 / 2.5) < 1e-15);
    CHECK(relErr(propOf(*c, "fj_radius"), 0.8e-3) < 1e-15);
    CHECK(relErr(propOf(*c, "fj_area"), 2.0 * 0.8e-3 / 4.0) < 1e-15);
    CHECK(c->OKToDelete());
    const int ro = propIndex(*c, "fj_nbond");
    CHECK((c->PropInfoAt(ro)->flags & kPropReadOnly));
    CHECK(c->AcceptProp(ro, 1.0) != 0);
    CHECK_THAT(std::string(c->LastError()), Contains("read-only"));
    // Ball-wall: R = rmul R_ball, fj_kn = E / R_ball.
    LawDriver wall("fjoint", {{"fj_emod", 6e10}, {"fj_kratio", 2.5}}, false, 2e-3, 0.0, 1e-3);
    ContactModel* w = wall.clone();
    CHECK(relErr(propOf(*w, "fj_kn"), 6e10 / 2e-3) < 1e-15);
    CHECK(relErr(propOf(*w, "fj_radius"), 2e-3) < 1e-15);
}

TEST_CASE("fjoint: bad input is refused, naming the property", "[fjoint]") {
    CHECK_THAT(modelError("fjoint", {{"fj_emod", -1.0}}), Contains("fj_emod"));
    CHECK_THAT(modelError("fjoint", {{"fj_emod", -1.0}}), Contains(">= 0"));
    CHECK_THAT(modelError("fjoint", {{"fj_nr", 0.0}}), Contains("fj_nr"));
    CHECK_THAT(modelError("fjoint", {{"fj_nr", 17.0}}), Contains("fj_nr"));
    CHECK_THAT(modelError("fjoint", {{"fj_nr", 2.5}}), Contains("fj_nr"));
    CHECK_THAT(modelError("fjoint", {{"fj_elem", 0.0}}), Contains("fj_elem"));
    CHECK_THAT(modelError("fjoint", {{"fj_elem", 3.0}}),
               Contains("'fj_elem' (3) must be <= 'fj_nr' (2)"));
    CHECK(modelError("fjoint", {{"fj_nr", 4.0}, {"fj_elem", 3.0}}).empty());
    CHECK(modelError("fjoint", {{"fj_elem", 3.0}, {"fj_nr", 4.0}}).empty());  // any order
    CHECK_THAT(modelError("fjoint", {{"fj_rmul", 0.0}}), Contains("fj_rmul"));
    CHECK_THAT(modelError("fjoint", {{"fj_kn", -1.0}}), Contains("fj_kn"));
    CHECK_THAT(modelError("fjoint", {{"fj_kn", kInf}}), Contains("fj_kn"));
    CHECK_THAT(modelError("fjoint", {{"fj_fa", 90.0}}), Contains("fj_fa"));
    CHECK_THAT(modelError("fjoint", {{"fj_fric", -0.1}}), Contains("fj_fric"));
    CHECK_THAT(modelError("fjoint", {{"fj_gap0", -1e-6}}), Contains("fj_gap0"));
    CHECK_THAT(modelError("fjoint", {{"fj_mtype", 3.0}}), Contains("fj_mtype"));
    CHECK_THAT(modelError("fjoint", {{"fj_ten", NAN}}), Contains("fj_ten"));
    CHECK_THAT(modelError("fjoint", {{"fj_ten", -kInf}}), Contains("fj_ten"));
    CHECK_THAT(modelError("fjoint", {{"fj_state", 1.0}}), Contains("read-only"));
    CHECK_THAT(modelError("fjoint", {{"fj_emod", 1e9}}), Contains("fj_kratio"));
    CHECK_THAT(modelError("fjoint", {{"fj_nonsense", 1.0}}), Contains("fj_nonsense"));
    CHECK(modelError("fjoint", {{"fj_ten", kInf}, {"fj_coh", kInf}}).empty());
    CHECK(modelError("fjoint", props(4)).empty());
    // An installed interface keeps its number of elements.
    LawDriver drv("fjoint", props(4), true, kRad, kRad, 1e-3);
    Run r(drv);
    CHECK(r.c->AcceptProp(propIndex(*r.c, "fj_nr"), 3.0) != 0);
    CHECK_THAT(std::string(r.c->LastError()), Contains("fj_nr"));
    CHECK(r.c->AcceptProp(propIndex(*r.c, "fj_elem"), 5.0) != 0);
    CHECK_THAT(std::string(r.c->LastError()), Contains("fj_elem"));
}

// ============================================================================ closed forms

TEST_CASE("fjoint: pure tension, every element breaks at opening fj_ten / fj_kn", "[fjoint]") {
    for (int n : {1, 2, 3, 5, 8}) {
        INFO("N = " << n);
        LawDriver drv("fjoint", props(n), true, kRad, kRad, 1e-3);
        // Force-displacement before the break: F_n = -kn A d, no moment, no shear.
        {
            Run r(drv);
            CHECK(r.prop("fj_nbond") == n);
            CHECK(!r.c->OKToDelete());
            const FdBlock fd = r.step(-1e-7, 0.0, 0.0);
            CHECK(relErr(fd.n_force, -kKn * 2.0 * kRad * 1e-7) < 1e-14);
            CHECK(std::fabs(fd.moment) < 1e-14 * std::fabs(fd.n_force) * kRad);
            CHECK((fd.flags & kFdKeep));
            CHECK((fd.flags & kFdBonded));
            CHECK(relErr(fd.knest, kKn * 2.0 * kRad) < 1e-15);
            CHECK(relErr(fd.ksest, kKs * 2.0 * kRad) < 1e-15);
            CHECK(relErr(fd.krest, kKn * 2.0 * kRad * kRad * kRad / 3.0) < 1e-15);
        }
        int first = -1;
        auto broken = [&](double open, int& count) {
            Run r(drv);
            const FdBlock fd = r.step(-open, 0.0, 0.0);
            count = n - int(r.prop("fj_nbond"));
            return fd;
        };
        const double at_first =
            threshold([&](double x) { return broken(x, first).flags & kFdBroken; }, 0.0, 1e-5);
        const double at_last = threshold(
            [&](double x) {
                int k;
                broken(x, k);
                return k == n;
            },
            0.0, 1e-5);
        int k_below = -1;
        broken(at_first * (1.0 - 1e-12), k_below);
        const FdBlock at = broken(at_first, first);
        std::printf(
            "fjoint tension N=%d: first break at %.9e m, last at %.9e m (closed form "
            "%.9e, rel err %.1e)\n",
            n, at_first, at_last, kTen / kKn, relErr(at_first, kTen / kKn));
        CHECK(relErr(at_first, kTen / kKn) < 1e-12);
        CHECK(at_last == at_first);  // all N in the same step
        CHECK(k_below == 0);
        CHECK(first == n);
        CHECK(at.break_mode == kBreakTension);
        CHECK((at.flags & kFdBreakStress));
        CHECK(relErr(at.reserved[0], kTen) < 1e-12);  // sigma at failure
        CHECK(at.n_force == 0.0);                     // broken and open: nothing left
        CHECK(!(at.flags & kFdKeep));
    }
}

TEST_CASE(
    "fjoint: pure shear breaks at slip fj_coh / fj_ks, Mohr-Coulomb under compression, then "
    "slides at fj_fric F_n",
    "[fjoint]") {
    const int n = 4;
    // sigma = 0: every element at tau = ks s.
    {
        LawDriver drv("fjoint", props(n), true, kRad, kRad, 1e-3);
        int count = 0;
        const double s = threshold(
            [&](double x) {
                Run r(drv);
                const FdBlock fd = r.step(0.0, x, 0.0);
                count = n - int(r.prop("fj_nbond"));
                return (fd.flags & kFdBroken) != 0 && fd.break_mode == kBreakShear;
            },
            0.0, 1e-4);
        std::printf("fjoint shear: break at slip %.9e m (closed form %.9e, rel err %.1e)\n", s,
                    kCoh / kKs, relErr(s, kCoh / kKs));
        CHECK(relErr(s, kCoh / kKs) < 1e-12);
        CHECK(count == n);
    }
    // fj_fa = 30 deg, pre-compressed to sigma = -0.5 fj_ten: tau_c = coh + 0.5 ten tan 30.
    LawDriver drv("fjoint", props(n, {{"fj_fa", 30.0}}), true, kRad, kRad, 1e-3);
    const double pre = 0.5 * kTen / kKn;
    const double s = threshold(
        [&](double x) {
            Run r(drv);
            r.step(pre, 0.0, 0.0);
            const FdBlock fd = r.step(0.0, x, 0.0);
            return (fd.flags & kFdBroken) != 0 && fd.break_mode == kBreakShear;
        },
        0.0, 1e-4);
    const double tau_c = kCoh + 0.5 * kTen * std::tan(M_PI / 6.0);
    std::printf(
        "fjoint shear, fj_fa 30 deg, sigma -0.5 fj_ten: tau_c %.9e Pa (closed form %.9e, "
        "rel err %.1e)\n",
        s * kKs, tau_c, relErr(s * kKs, tau_c));
    CHECK(relErr(s * kKs, tau_c) < 1e-12);
    // After the break: unbonded elements in compression hold the normal force and slide at
    // fj_fric F_n; the slider's work is booked as slip and the books close.
    Run r(drv);
    r.step(pre, 0.0, 0.0);
    const FdBlock b = r.step(0.0, 1.01 * s, 0.0);
    REQUIRE((b.flags & kFdBroken));
    CHECK(b.break_mode == kBreakShear);
    CHECK(relErr(b.reserved[1], tau_c) < 1e-9);  // tau at failure
    CHECK(r.prop("fj_nbond") == 0.0);
    CHECK(relErr(b.n_force, 0.5 * kTen * 2.0 * kRad) < 1e-12);
    CHECK(relErr(b.s_force, -0.5 * b.n_force) < 1e-12);  // end 2 moved +t: force along -t
    CHECK(b.energy[kEnergyReleased] > 0.0);
    for (int i = 0; i < 20; ++i) {
        const FdBlock f = r.step(0.0, 1e-7, 0.0);
        CHECK((f.flags & kFdSliding));
        CHECK(relErr(f.s_force, -0.5 * f.n_force) < 1e-12);
        CHECK(f.energy[kEnergySlip] > 0.0);
        CHECK(std::fabs(r.residual()) < 1e-12 * r.work_abs);
    }
    CHECK(relErr(r.slip, 0.5 * b.n_force * 20 * 1e-7) < 1e-9);
}

TEST_CASE("fjoint: pure bending, the first break and the moment it takes, for N = 1 .. 8",
          "[fjoint]") {
    const double inertia = 2.0 * kRad * kRad * kRad / 3.0;
    for (int n = 1; n <= 8; ++n) {
        INFO("N = " << n);
        LawDriver drv("fjoint", props(n), true, kRad, kRad, 1e-3);
        // Elastic: M = -kn I theta for any N (each element carries its own moment).
        {
            Run r(drv);
            const FdBlock fd = r.step(0.0, 0.0, 1e-6);
            CHECK(relErr(fd.moment, -kKn * inertia * 1e-6) < 1e-13);
            CHECK(std::fabs(fd.n_force) < 1e-12 * kKn * 2.0 * kRad * kRad * 1e-6);
        }
        if (n == 1) {
            // One element: its centre does not move in bending; it never breaks so.
            Run r(drv);
            const FdBlock fd = r.step(0.0, 0.0, 1.0);
            CHECK(!(fd.flags & kFdBroken));
            continue;
        }
        const double th = threshold(
            [&](double x) {
                Run r(drv);
                return (r.step(0.0, 0.0, x).flags & kFdBroken) != 0;
            },
            0.0, 1.0);
        const double th_cf = kTen / (kKn * kRad * (1.0 - 1.0 / n));
        Run r(drv);
        const FdBlock below = r.step(0.0, 0.0, th * (1.0 - 1e-13));
        const double m1 = std::fabs(below.moment);
        const double m1_cf = 2.0 / 3.0 * kRad * kRad * kTen * n / (n - 1.0);
        std::printf(
            "fjoint bending N=%d: first break at theta %.9e (closed form %.9e, rel err "
            "%.1e), moment %.9e N m (closed form %.9e, rel err %.1e; parallel bond "
            "%.4e)\n",
            n, th, th_cf, relErr(th, th_cf), m1, m1_cf, relErr(m1, m1_cf),
            2.0 / 3.0 * kRad * kRad * kTen);
        CHECK(relErr(th, th_cf) < 1e-12);
        CHECK(relErr(m1, m1_cf) < 1e-12);
        Run b(drv);
        const FdBlock at = b.step(0.0, 0.0, th);
        CHECK(at.break_mode == kBreakTension);
        CHECK(b.prop("fj_nbond") == n - 1);  // one element: the outermost on the opening side
        setProp(*b.c, "fj_elem", 1.0);
        CHECK(b.prop("fj_state") == 1.0);  // broken in tension
        CHECK(b.prop("fj_egap") > 0.0);    // open
        setProp(*b.c, "fj_elem", double(n));
        CHECK(b.prop("fj_state") == 3.0);  // bonded
    }
}

TEST_CASE("fjoint: an interface loses its elements one by one under rising bending", "[fjoint]") {
    for (int n : {2, 3, 4, 5, 8}) {
        INFO("N = " << n);
        const double L = 2.0 * kRad / n;
        LawDriver drv("fjoint", props(n), true, kRad, kRad, 1e-3);
        // Thresholds of the j-th break, by single-step bisection, against the closed form.
        const int n_open = n / 2;  // elements whose centre is on the opening side (x < 0)
        std::vector<double> th_j;
        for (int j = 1; j <= n_open; ++j) {
            const double th = threshold(
                [&](double x) {
                    Run r(drv);
                    r.step(0.0, 0.0, x);
                    return n - int(r.prop("fj_nbond")) >= j;
                },
                0.0, 10.0);
            const double cf = kTen / (kKn * (kRad - (j - 0.5) * L));
            std::printf(
                "fjoint bending N=%d: break %d at theta %.9e (closed form %.9e, rel err "
                "%.1e)\n",
                n, j, th, cf, relErr(th, cf));
            CHECK(relErr(th, cf) < 1e-12);
            th_j.push_back(cf);
        }
        // The moment-rotation curve, step by step to past the last break: the closed form of
        // the intact elements, each stage.
        Run r(drv);
        const double dth = th_j.empty() ? 1e-5 : th_j.back() / 997.3;
        double theta = 0.0, worst_m = 0.0, worst_f = 0.0;
        int breaks = 0;
        for (int i = 0; i < 1100; ++i) {
            const FdBlock fd = r.step(0.0, 0.0, dth);
            theta += dth;
            if (fd.flags & kFdBroken) ++breaks;
            double sum_m = 0.0, sum_f = 0.0;
            int intact = 0;
            for (int e = 0; e < n; ++e) {
                const double x = elemCentre(e, n);
                const bool broken = e < n_open && theta >= th_j[std::size_t(e)];
                if (broken) continue;  // open: no force, no moment
                ++intact;
                sum_m += L * x * x + L * L * L / 12.0;
                sum_f += L * x;
            }
            CHECK(r.prop("fj_nbond") == intact);
            const double m_cf = -kKn * theta * sum_m, f_cf = kKn * theta * sum_f;
            worst_m = std::max(worst_m, relErr(fd.moment, m_cf));
            worst_f =
                std::max(worst_f, std::fabs(fd.n_force - f_cf) / (kKn * theta * 2.0 * kRad * kRad));
            // The books: the springs are linear and the broken elements open, so the work put
            // in is what is stored plus what the breaks released, to round-off.
            CHECK(std::fabs(r.residual()) < 1e-12 * r.work_abs);
        }
        std::printf(
            "fjoint bending N=%d: %d breaks, moment-rotation worst rel err %.1e, normal "
            "force %.1e\n",
            n, breaks, worst_m, worst_f);
        CHECK(breaks == n_open);
        CHECK(worst_m < 1e-12);
        CHECK(worst_f < 1e-12);
    }
}

TEST_CASE("fjoint: an unbonded interface under compression resists rotation up to F R",
          "[fjoint]") {
    // An interface installed unbonded (fj_mtype 1) is a Winkler layer that carries no tension:
    // under a closure d it resists rotation elastically up to theta = d / R, then rocks on its
    // edge. The elements integrate over their closed parts, so the result is the continuum's
    // for any N.
    const double d = 1e-7;
    for (int n : {1, 2, 3, 8}) {
        INFO("N = " << n);
        LawDriver drv("fjoint", props(n, {{"fj_mtype", 1.0}}), true, kRad, kRad, 1e-3);
        Run r(drv);
        CHECK(r.prop("fj_nbond") == 0.0);
        CHECK(r.prop("bonded") == 0.0);
        r.step(d, 0.0, 0.0);
        double theta = 0.0, worst = 0.0;
        const double dth = 20.0 * d / kRad / 400.0;
        for (int i = 0; i < 400; ++i) {
            const FdBlock fd = r.step(0.0, 0.0, dth);
            theta += dth;
            // Closed part [x0, R] (theta > 0 closes x > 0), x0 = max(-R, -d / theta).
            const double x0 = std::max(-kRad, -d / theta);
            const double f_cf = kKn * (d * (kRad - x0) + theta * (kRad * kRad - x0 * x0) / 2.0);
            const double m_cf = -kKn * (d * (kRad * kRad - x0 * x0) / 2.0 +
                                        theta * (kRad * kRad * kRad - x0 * x0 * x0) / 3.0);
            worst = std::max({worst, relErr(fd.n_force, f_cf), relErr(fd.moment, m_cf)});
        }
        std::printf(
            "fjoint unbonded, fixed closure, N=%d: worst rel err against the Winkler "
            "integrals %.1e\n",
            n, worst);
        CHECK(worst < 1e-9);
        // At a constant normal force F: d follows theta so that the edge zone carries F.
        Run q(drv);
        const double F = 100.0;
        const double d0 = F / (kKn * 2.0 * kRad);
        q.step(d0, 0.0, 0.0);
        double th = 0.0, dd = d0, worst_m = 0.0, ratio = 0.0;
        const double rock = F / (2.0 * kKn * kRad * kRad);  // w = 2R: rocking starts
        for (int i = 1; i <= 200; ++i) {
            const double th_new = rock * std::pow(1.05, i);
            const double w = std::sqrt(2.0 * F / (kKn * th_new));
            const double d_new = w * th_new - kRad * th_new;
            const FdBlock fd = q.step(d_new - dd, 0.0, th_new - th);
            th = th_new, dd = d_new;
            worst_m = std::max(worst_m, relErr(fd.moment, -F * (kRad - w / 3.0)));
            CHECK(relErr(fd.n_force, F) < 1e-6);
            CHECK(std::fabs(fd.moment) < F * kRad);
            ratio = std::fabs(fd.moment) / (F * kRad);
        }
        std::printf(
            "fjoint unbonded, F = 100 N, N=%d: M against -F (R - w/3) worst rel err "
            "%.1e; |M| / (F R) at theta = %.3g rad: %.6f\n",
            n, worst_m, th, ratio);
        CHECK(worst_m < 1e-6);
        CHECK(ratio > 0.99);
        CHECK(ratio < 1.0);
    }
}

// ============================================================================ energies

TEST_CASE("fjoint: the books close through every break, and a write of bonded = 0 releases",
          "[fjoint]") {
    const int n = 4;
    LawDriver drv("fjoint", props(n), true, kRad, kRad, 1e-3);
    // Bending to lose the opening side: every step exact to round-off (the bonded springs are
    // linear, the broken elements open).
    Run r(drv);
    int breaks = 0;
    const double theta = 400 * 1.3e-5;
    for (int i = 0; i < 400; ++i) {
        const FdBlock f = r.step(0.0, 0.0, 1.3e-5);
        if (f.flags & kFdBroken) ++breaks;
        CHECK(std::fabs(r.residual()) < 1e-12 * r.work_abs);
    }
    CHECK(breaks == 2);
    // Then pulling the rest apart: a broken element that stays partly closed (its closed part
    // shrinks towards its edge) stores kn (d + x_edge theta)^3 / (6 theta), a cubic in the
    // opening d, and the trapezoidal work of one step misses its change by kn dn^3 / (12 theta)
    // (the trapezoidal rule's error for a cubic): the time integration's own third-order term,
    // not booked anywhere. Bound: that per element and step.
    double bound = 0.0;
    const double dn = -3e-9;
    while (r.prop("fj_nbond") > 0) {
        const FdBlock f = r.step(dn, 0.0, 0.0);
        if (f.flags & kFdBroken) ++breaks;
        bound += n * kKn * std::fabs(dn * dn * dn) / (12.0 * theta);
        CHECK(std::fabs(r.residual()) < 1e-12 * r.work_abs + bound);
        REQUIRE(r.u > -1e-5);
    }
    CHECK(breaks >= 3);
    CHECK(r.released > 0.0);
    std::printf(
        "fjoint energy, bending then tension: released %.6e J of %.6e J put in, "
        "residual %.1e J (bound %.1e J)\n",
        r.released, r.work, r.residual(), bound);
    // A break in tension releases F_old F_trial / (2k) per spring (pbond's rule): one step.
    {
        Run t(drv);
        t.step(-0.9 * kTen / kKn, 0.0, 0.0);
        const double f_old = t.prev.n_force;
        const FdBlock f = t.step(-0.2 * kTen / kKn, 0.0, 0.0);
        REQUIRE((f.flags & kFdBroken));
        const double k = kKn * 2.0 * kRad, f_trial = f_old - k * 0.2 * kTen / kKn;
        CHECK(relErr(f.energy[kEnergyReleased], f_old * f_trial / (2.0 * k)) < 1e-12);
    }
    // m:unbond's write: no event; the next step releases what the bonds held plus the half
    // step's work, and the books stay closed.
    Run u(drv);
    u.step(-0.5 * kTen / kKn, 1e-7, 2e-5);
    const double held = u.prev.energy[kEnergyBondStrain];
    CHECK(held > 0.0);
    setProp(*u.c, "bonded", 0.0);
    CHECK(u.prop("fj_nbond") == 0.0);
    CHECK(u.c->OKToDelete() == false);  // (until its next FDlaw finds it open)
    const FdBlock f = u.step(-1e-9, 0.0, 0.0);
    CHECK(!(f.flags & (kFdBroken | kFdBonded)));
    CHECK(f.energy[kEnergyReleased] > 0.0);
    CHECK(f.energy[kEnergyBondStrain] == 0.0);
    CHECK(std::fabs(u.residual()) < 1e-12 * u.work_abs);
    const FdBlock g = u.step(-1e-9, 0.0, 0.0);
    CHECK(g.energy[kEnergyReleased] == 0.0);  // released once
}

TEST_CASE("fjoint: installation states adopt the entry forces; slit opens by fj_gap0", "[fjoint]") {
    const int n = 4;
    const double A = 2.0 * kRad;
    SECTION("bonded: the old contact's forces spread over the elements") {
        LawDriver drv("fjoint", props(n), true, kRad, kRad, 1e-3);
        Run r(drv, 1e-6, 120.0, -30.0);
        CHECK(r.prev.n_force == Approx(120.0).epsilon(1e-14));
        CHECK(r.prev.s_force == Approx(-30.0).epsilon(1e-14));
        CHECK(r.prev.moment == 0.0);
        const FdBlock f = r.step(-1e-9, 0.0, 0.0);
        CHECK(f.n_force == Approx(120.0 - kKn * A * 1e-9).epsilon(1e-13));
        CHECK(relErr(r.prop("fj_gap"), -120.0 / (kKn * A) + 1e-9) < 1e-9);
        setProp(*r.c, "fj_elem", 2.0);
        CHECK(r.prop("fj_tau") == Approx(30.0 / 4.0 / (A / 4.0)).epsilon(1e-14));
    }
    SECTION("unbonded: compression kept, shear within friction, no tension") {
        LawDriver drv("fjoint", props(n, {{"fj_mtype", 1.0}}), true, kRad, kRad, 1e-3);
        Run r(drv, 1e-6, 120.0, -90.0);
        CHECK(r.prop("fj_nbond") == 0.0);
        CHECK(r.prev.n_force == Approx(120.0).epsilon(1e-14));
        CHECK(r.prev.s_force == Approx(-60.0).epsilon(1e-14));  // fj_fric 0.5
        const FdBlock f = r.step(-2.0 * 120.0 / (kKn * A), 0.0, 0.0);
        CHECK(f.n_force == 0.0);
        CHECK(f.s_force == 0.0);
        CHECK(!(f.flags & kFdKeep));
        CHECK(r.c->OKToDelete());
    }
    SECTION("slit: force-free, open by fj_gap0, closes after it") {
        const double g0 = 2e-8;
        LawDriver drv("fjoint", props(n, {{"fj_mtype", 2.0}, {"fj_gap0", g0}}), true, kRad, kRad,
                      1e-3);
        Run r(drv, 1e-6, 120.0, -30.0);
        CHECK(r.prev.n_force == 0.0);
        CHECK(r.prev.s_force == 0.0);
        CHECK(r.prop("fj_gap") == g0);
        CHECK((r.prev.flags & kFdKeep));
        FdBlock f = r.step(0.9 * g0, 0.0, 0.0);
        CHECK(f.n_force == 0.0);
        f = r.step(0.2 * g0, 0.0, 0.0);
        CHECK(relErr(f.n_force, kKn * A * 0.1 * g0) < 1e-9);
        // Opened to twice its gap, it lets go.
        f = r.step(-2.0 * g0, 0.0, 0.0);
        CHECK((f.flags & kFdKeep));
        f = r.step(-0.2 * g0, 0.0, 0.0);
        CHECK(!(f.flags & kFdKeep));
    }
    SECTION("a rule that bonds at touch does not bond a pair whose bond broke") {
        LawDriver drv("fjoint", props(n), true, kRad, kRad, 1e-3);
        ContactModel* c = drv.clone();
        FdBlock fd = drv.block(1e-9, 1e-3, 0.0, kDt, nullptr);
        fd.flags |= kFdNoAutoBond;
        c->FDlaw(fd);
        CHECK(propOf(*c, "fj_nbond") == 0.0);
        // Closed by the overlap, plus linear's onset corner (the touch at lead = 1 step before:
        // k |rate| dt (lead - 1/2)^2 / 2).
        CHECK(fd.n_force ==
              Approx(kKn * A * 1e-9 + 0.5 * kKn * A * 1e-3 * kDt * 0.25).epsilon(1e-12));
    }
}

TEST_CASE("fjoint: unbonded at touch it is the linear model, corners included", "[fjoint]") {
    // An oblique impact (approach from a gap, load, slide, separate) without rotation: an
    // unbonded interface is a linear spring kn = fj_kn 2R with the slider, and pays linear's
    // onset and closing corners. Same forces and energies as `linear` to round-off (fjoint
    // accumulates the overlap from its increments where linear takes it whole).
    const double kn = 1e7, ks = 6e6, fric = 0.3, r1 = 0.05, r2 = 0.07;
    LawDriver lin("linear", {{"kn", kn}, {"ks", ks}, {"fric", fric}}, true, r1, r2, 2.0);
    LawDriver fj(
        "fjoint",
        {{"fj_kn", kn / (2.0 * r1)}, {"fj_ks", ks / (2.0 * r1)}, {"fj_fric", fric}, {"fj_nr", 3.0}},
        true, r1, r2, 2.0);
    ContactModel* a = lin.clone();
    ContactModel* b = fj.clone();
    FdBlock fa{}, fb{};
    bool have = false;
    const double dt = 1e-5;
    int n = 0, slid = 0;
    double worst = 0.0, worst_e = 0.0;
    for (int i = 0; i < 400; ++i) {
        const double t = i * dt;
        const double u = -1e-6 + 2e-3 * std::sin(M_PI * t / 2e-3);
        const double uprev = -1e-6 + 2e-3 * std::sin(M_PI * (t - dt) / 2e-3);
        if (u <= 0.0 && !have) continue;
        FdBlock na =
            lin.block(u, (u - uprev) / dt, 0.3 * std::cos(t * 900.0), dt, have ? &fa : nullptr);
        na.du_n = u - uprev;
        FdBlock nb = na;
        if (have) nb.n_force = fb.n_force, nb.s_force = fb.s_force, nb.moment = fb.moment;
        a->FDlaw(na);
        b->FDlaw(nb);
        const double scale = kn * 2e-3;
        worst = std::max({worst, std::fabs(na.n_force - nb.n_force) / scale,
                          std::fabs(na.s_force - nb.s_force) / scale});
        worst_e = std::max(
            {worst_e,
             std::fabs(na.energy[kEnergyStrain] - nb.energy[kEnergyStrain]) / (0.5 * scale * 2e-3),
             std::fabs(na.energy[kEnergySlip] - nb.energy[kEnergySlip]) / (0.5 * scale * 2e-3)});
        CHECK((na.flags & kFdSliding) == (nb.flags & kFdSliding));
        CHECK(std::fabs(nb.moment) < 1e-14 * kn * 2e-3 * r1);
        if (na.flags & kFdSliding) ++slid;
        fa = na, fb = nb, have = true;
        ++n;
        if (u < 0.0) break;
    }
    std::printf(
        "fjoint unbonded against linear, oblique impact: %d steps (%d sliding), worst "
        "force difference %.1e, energy %.1e of the peak\n",
        n, slid, worst, worst_e);
    CHECK(n > 50);
    CHECK(slid > 0);
    CHECK(worst < 1e-12);
    CHECK(worst_e < 1e-12);
}

// ============================================================================ save / restore

TEST_CASE("fjoint: save/restore continues bit-identically, through breaks and sliding",
          "[fjoint]") {
    LawDriver drv("fjoint", props(5, {{"fj_fa", 20.0}, {"fj_ten", 2e6}}), true, kRad, 1.5 * kRad,
                  1e-3);
    // Compress, then shear and rotate while opening, until every element broke and slid.
    auto incr = [](int i) {
        struct {
            double dn, ds, dth;
        } s{i < 20 ? 5e-10 : -1e-9 * (1.0 + 0.3 * std::sin(0.1 * i)), 4e-9 * std::cos(0.05 * i),
            4e-6 * std::sin(0.03 * i + 0.2)};
        return s;
    };
    const int steps = 400;
    for (int split : {10, 120, 260}) {
        INFO("split " << split);
        Run a(drv, 0.0);
        for (int i = 0; i < split; ++i) {
            const auto s = incr(i);
            a.step(s.dn, s.ds, s.dth);
        }
        BinarySaveObject saver(a.c->Version());
        a.c->SaveRestore(saver);
        Run b(drv, 0.0);
        BinarySaveObject loader(saver.bytes(), a.c->Version());
        b.c->SaveRestore(loader);
        CHECK(loader.atEnd());
        b.prev = a.prev;
        b.u = a.u;
        int breaks = 0, sliding = 0;
        bool same = true;
        for (int i = split; i < steps; ++i) {
            const auto s = incr(i);
            const FdBlock fa = a.step(s.dn, s.ds, s.dth);
            const FdBlock fb = b.step(s.dn, s.ds, s.dth);
            same = same && fa.n_force == fb.n_force && fa.s_force == fb.s_force &&
                   fa.moment == fb.moment && fa.flags == fb.flags && fa.break_mode == fb.break_mode;
            for (int k = 0; k < kEnergyCount; ++k) same = same && fa.energy[k] == fb.energy[k];
            if (fa.flags & kFdBroken) ++breaks;
            if (fa.flags & kFdSliding) ++sliding;
        }
        CHECK(same);
        for (int32_t i = 0; i < a.c->PropCount(); ++i) {
            const double x = a.c->ReturnProp(i), y = b.c->ReturnProp(i);
            CHECK((x == y || (std::isnan(x) && std::isnan(y))));
        }
        if (split == 10) {
            CHECK(breaks >= 2);
            CHECK(sliding > 0);
        }
    }
}

// ============================================================================ engine

namespace {

constexpr double kR = 0.01, kEngineDt = 1e-8;

/// Two balls on the x axis overlapping by 1e-9 m, bonded on the first cycle (a rule with
/// bonded = 1), then held at constant velocities by fixity.
struct Pair {
    Model m;
    BallId a, b;
    std::vector<Event> events;
    explicit Pair(int n) {
        m.setDefaultContactModel("fjoint", props(n));
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
};

}  // namespace

TEST_CASE("fjoint on the engine: pure tension and pure bending raise bond_break events",
          "[fjoint]") {
    {
        const double v = 0.3;  // opening at break fj_ten / kn = 1e-6 m = v k dt -> k = 334
        Pair p(4);
        CHECK(p.prop("fj_nbond") == 4.0);
        CHECK(p.prop("fj_radius") == Approx(kR));
        p.m.setBallVel(p.a, Vec2(-0.5 * v, 0.0));
        p.m.setBallVel(p.b, Vec2(0.5 * v, 0.0));
        const int k_break = int(std::ceil(kTen / (kKn * v * kEngineDt) * (1 + 1e-12)));
        p.m.cycle(k_break - 2);
        CHECK(p.prop("fj_fn") ==
              Approx(-kKn * 2.0 * kR * v * (k_break - 2) * kEngineDt).epsilon(1e-6));
        CHECK(p.events.empty());
        p.m.cycle(3);
        REQUIRE(p.events.size() == 1);  // one event per contact and step: all four at once
        CHECK(p.events[0].kind == EventKind::BondBreak);
        CHECK(p.events[0].mode == kBreakTension);
        CHECK(p.events[0].model == "fjoint");
        CHECK(p.events[0].sigma == Approx(kTen).epsilon(1e-9));
        CHECK(p.m.contactCount() == 0);  // separated and broken: gone
    }
    {
        // Opposite spins: no slip at the contact point; theta grows at w. N = 4: the two
        // elements on the opening side break at theta = ten / (kn |x_e|), |x_e| = 3R/4, R/4.
        const double w = 2.0;
        Pair p(4);
        p.m.setBallSpin(p.a, -0.5 * w);
        p.m.setBallSpin(p.b, 0.5 * w);
        const double th1 = kTen / (kKn * 0.75 * kR), th2 = kTen / (kKn * 0.25 * kR);
        const int k1 = int(std::ceil(th1 / (w * kEngineDt))),
                  k2 = int(std::ceil(th2 / (w * kEngineDt)));
        p.m.cycle(k1 - 2);
        CHECK(p.events.empty());
        CHECK(p.prop("fj_m") ==
              Approx(-kKn * 2.0 * kR * kR * kR / 3.0 * w * (k1 - 2) * kEngineDt).epsilon(1e-6));
        p.m.cycle(k2 + 2 - (k1 - 2));
        REQUIRE(p.events.size() == 2);
        for (const Event& e : p.events) {
            CHECK(e.mode == kBreakTension);
            CHECK(e.sigma == Approx(kTen).epsilon(1e-9));
        }
        CHECK(p.events[0].time == Approx((k1 + 1) * kEngineDt).margin(2.5 * kEngineDt));
        CHECK(p.events[1].time == Approx((k2 + 1) * kEngineDt).margin(2.5 * kEngineDt));
        CHECK(p.prop("fj_nbond") == 2.0);
        CHECK(p.m.contactCount() == 1);  // still bonded on the closing side
    }
}
