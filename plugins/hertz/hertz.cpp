// SPDX-License-Identifier: MIT
//
// `hertz`: Hertz-Mindlin contact as PFC defines it, in shear-modulus form (docs/models/hertz.md).
//
//   normal:  F_n^h = (4/3) E* sqrt(R*) u_n^(3/2)                  (Johnson 1985)
//            E* = G/(1-nu) ball-ball (equal materials), 2G/(1-nu) ball-wall (rigid wall)
//   shear:   F_s^h <- F_s^h - k_t dU_s,  k_t = 8 G* sqrt(R* u_n)  (Mindlin no-slip stiffness)
//            1/G* = (2-nu)/G + (2-nu)/G ball-ball, (2-nu)/G ball-wall
//            |F_s^h| <= fric F_n^h  (Coulomb limit on the elastic part, as PFC)
//            normal unloading scales F_s^h by k_t(new)/k_t(old)  (Mindlin-Deresiewicz
//            simplification: the elastic shear displacement F_s/k_t is kept)
//   dashpot: c = 2 beta sqrt(m* k), k the current tangent stiffness, so c ~ u_n^(1/4) and the
//            restitution does not depend on the impact speed (Tsuji, Tanaka & Ishida 1992);
//            hz_e sets beta for a target restitution by inverting the scaled impact equation
//
// Numerics beyond the SDK's dashpot: the coefficient is averaged over each step's impulse
// window with its exact antiderivative (c varies steeply near touch), the no-tension clip pays
// the impulse central differences miss at that corner, and the works are booked trapezoidally,
// as the engine's leapfrog kinetic energy sees them (docs/models/hertz.md, "Numerics").
//
// The sphere law is applied to disks: a modelling choice (a line contact between cylinders has
// no pure power law); it makes the 3D benchmarks of Chung & Ooi 2011 checkable with
// the sphere mass mode.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "talus/contact_model.hpp"
#include "talus/sdk/dashpot.hpp"
#include "talus/sdk/model_base.hpp"
#include "talus/sdk/shear_spring.hpp"

namespace {

using namespace talus;
using namespace talus::sdk;

const char* const kDpModes[] = {"full", "no_tension", "no_shear_slip", "no_tension_no_shear_slip",
                                nullptr};

/// Factor of the Hertz contact duration: t_c = durationFactor() (m*^2 / (R* E*^2 v))^(1/5),
/// i.e. 2.9432 delta_max / v with 2.9432 = 2 sqrt(pi) Gamma(7/5)/Gamma(9/10) and
/// delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5), so the factor is 2.9432 (15/16)^(2/5)
/// = 2.8683 (Johnson 1985). Computed to full precision rather than from the rounded
/// constants, which differ from it by 2e-5.
double durationFactor() {
    static const double f =
        2.0 * std::sqrt(M_PI) * std::tgamma(1.4) / std::tgamma(0.9) * std::pow(15.0 / 16.0, 0.4);
    return f;
}

class Hertz final : public ModelBase<Hertz> {
public:
    static constexpr const char* kName = "hertz";

    // properties (PFC names)
    double hz_shear = 0.0;   // shear modulus G [Pa]
    double hz_poiss = 0.0;   // Poisson ratio [-]
    double hz_alpha = 1.5;   // exponent of the normal force [-] (only 1.5)
    double fric = 0.0;       // [-]
    double dp_nratio = 0.0;  // [-]
    double dp_sratio = 0.0;  // [-]
    double dp_mode = 0.0;    // 0..3, as linear
    double hz_e = 0.0;       // target normal restitution (0: not used) [-]
    // state (read-only)
    double hz_fn = 0.0;    // Hertz normal force [N]
    double hz_fs = 0.0;    // Mindlin shear force [N]
    double dp_fn = 0.0;    // normal dashpot force [N]
    double dp_fs = 0.0;    // shear dashpot force [N]
    double hz_slip = 0.0;  // 1 while sliding
    // derived values (not properties)
    double hz_e_done_ = 0.0;  // the hz_e that dp_nratio was derived from (0: none)
    double e_star_ = 0.0;     // effective modulus E* [Pa]
    double g_star_ = 0.0;     // effective shear modulus G* [Pa]
    double r_star_ = 0.0;     // effective radius R* [m]
    double mass_eff_ = 0.0;
    double last_overlap_ = 0.0;
    double window_end_ = 0.0;  // overlap at which the last step's dashpot window ended [m]
    double last_total_ = 0.0;  // the law's normal force at the last step (no corrections) [N]
    bool touching_ = false;
    DashpotHistory history_;  // the rest of the model's push on the dashpots' rates

    static const PropTable<Hertz>& Table() {
        static const PropTable<Hertz> t = {
            {{"hz_shear", "Pa", 0, 0.0, "shear modulus G", nullptr},
             &Hertz::hz_shear,
             0.0,
             kStiffnessMax},
            // range [0, 0.5) checked in AcceptProp and PreCycle (the table's ranges are closed)
            {{"hz_poiss", "-", 0, 0.0, "Poisson ratio", nullptr}, &Hertz::hz_poiss},
            {{"hz_alpha", "-", 0, 1.5, "exponent of the normal force", nullptr},
             &Hertz::hz_alpha,
             1.5,
             1.5,
             false,
             "(only the Hertz exponent 1.5 is implemented) "},
            {{"fric", "-", kPropInheritable, 0.0, "friction coefficient", nullptr},
             &Hertz::fric,
             0.0},
            {{"dp_nratio", "-", 0, 0.0, "normal critical damping ratio", nullptr},
             &Hertz::dp_nratio,
             0.0,
             1.0,
             false,
             "(1 = critical) "},
            {{"dp_sratio", "-", 0, 0.0, "shear critical damping ratio", nullptr},
             &Hertz::dp_sratio,
             0.0,
             1.0,
             false,
             "(1 = critical) "},
            {{"dp_mode", "-", kPropInteger, 0.0, "dashpot mode", kDpModes},
             &Hertz::dp_mode,
             0.0,
             3.0},
            {{"hz_e", "-", 0, 0.0, "target normal restitution; sets dp_nratio (0 = not used)",
              nullptr},
             &Hertz::hz_e,
             0.0,
             1.0,
             false,
             "(0 = not used) "},
            {{"hz_fn", "N", kPropReadOnly | kPropState, 0.0, "Hertz normal force", nullptr},
             &Hertz::hz_fn},
            {{"hz_fs", "N", kPropReadOnly | kPropState, 0.0, "Mindlin shear force", nullptr},
             &Hertz::hz_fs},
            {{"dp_fn", "N", kPropReadOnly | kPropState, 0.0, "normal dashpot force", nullptr},
             &Hertz::dp_fn},
            {{"dp_fs", "N", kPropReadOnly | kPropState, 0.0, "shear dashpot force", nullptr},
             &Hertz::dp_fs},
            {{"hz_slip", "-", kPropReadOnly | kPropState, 0.0, "1 while sliding", nullptr},
             &Hertz::hz_slip},
        };
        return t;
    }

    // Poisson's ratio must stay below 0.5; the table's range is closed, so the open end is
    // checked here (AcceptProp) and again before cycling (PreCycle).
    int32_t AcceptProp(int32_t index, double value) override {
        if (const PropInfo* info = PropInfoAt(index))
            if (std::string(info->name) == "hz_poiss" && !(value >= 0.0 && value < 0.5))
                return fail(poissonError(value));
        return ModelBase<Hertz>::AcceptProp(index, value);
    }

    const char* PreCycle(const PropBlock& pb) override {
        if (!(hz_poiss >= 0.0 && hz_poiss < 0.5)) {
            errorText() = poissonError(hz_poiss);
            return errorText().c_str();
        }
        if (const char* why = ModelBase<Hertz>::PreCycle(pb)) return why;
        if (hz_e > 0.0 && hz_e != hz_e_done_) {
            // A restitution instead of a damping ratio. With the dashpot on the tangent
            // stiffness the impact in units where K = (4/3) E* sqrt(R*), m* and v0 are 1 reads
            // u'' = -(u^1.5 + c u^0.25 u') with c = 2 beta sqrt(3/2): e depends on beta and the
            // mode only (Tsuji, Tanaka & Ishida 1992: the speed-independent variant). Invert it
            // once per setting (about 10 ms).
            char buf[256];
            buf[0] = '\0';
            const double e_min = restitutionForRatio(1.0, noTension());
            if (dp_nratio > 0.0 && hz_e_done_ == 0.0)
                std::snprintf(buf, sizeof buf,
                              "hertz: set either 'hz_e' or 'dp_nratio', not both (got hz_e = %g, "
                              "dp_nratio = %g)",
                              hz_e, dp_nratio);
            else if (hz_e < e_min)
                std::snprintf(buf, sizeof buf,
                              "hertz: 'hz_e' = %g needs a damping ratio above 1; with dp_mode %g "
                              "the smallest restitution is %.4f",
                              hz_e, dp_mode, e_min);
            if (buf[0]) {
                errorText() = buf;
                return errorText().c_str();
            }
            dp_nratio = ratioForRestitution(hz_e, noTension());
            hz_e_done_ = hz_e;
        }
        return nullptr;
    }

    /// Restitution of the scaled damped Hertz impact u'' = -(u^1.5 + c u^0.25 u'), u(0) = 0,
    /// u'(0) = 1, c = 2 beta sqrt(3/2) (K = m = v0 = 1, so c0 = 2 beta sqrt(m 2 E* sqrt(R*))
    /// = 2 beta sqrt(3/2 K m)); classical RK4, 2000 steps per unit time (the elastic contact
    /// lasts 3.2 units), separation interpolated: e to 3e-6 (checked against 64000 steps).
    static double restitutionForRatio(double beta, bool no_tension) {
        const double c = 2.0 * beta * std::sqrt(1.5), h = 1.0 / 2000.0;
        auto acc = [&](double x, double v) {
            if (x <= 0.0) return 0.0;
            const double f = x * std::sqrt(x) + c * std::sqrt(std::sqrt(x)) * v;
            return no_tension ? -std::max(0.0, f) : -f;
        };
        double x = 0.0, v = 1.0;
        for (int i = 0; i < 12 * 2000; ++i) {
            const double k1x = v, k1v = acc(x, v);
            const double k2x = v + 0.5 * h * k1v, k2v = acc(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
            const double k3x = v + 0.5 * h * k2v, k3v = acc(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
            const double k4x = v + h * k3v, k4v = acc(x + h * k3x, v + h * k3v);
            const double xn = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            const double vn = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            if (xn <= 0.0 && x > 0.0) return -(v + x / (x - xn) * (vn - v));
            x = xn, v = vn;
        }
        return 0.0;  // not separated within 12 units (the elastic contact lasts 3.2): captured
    }

    /// The damping ratio whose restitution is e (bisection on the decreasing e(beta), beta in
    /// [0, 1]).
    static double ratioForRestitution(double e, bool no_tension) {
        if (e >= 1.0) return 0.0;
        double lo = 0.0, hi = 1.0;
        for (int i = 0; i < 26; ++i) {  // beta to 1.5e-8
            const double mid = 0.5 * (lo + hi);
            (restitutionForRatio(mid, no_tension) > e ? lo : hi) = mid;
        }
        return 0.5 * (lo + hi);
    }

    static std::string poissonError(double value) {
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "hertz: 'hz_poiss' must be in [0, 0.5) (Poisson ratio; 0.5, incompressible, "
                      "is excluded) (got %g)",
                      value);
        return buf;
    }

    bool inherit(const PropBlock& pb) {
        fric = inheritMin(fric, pb.fric);
        const bool wall = pb.end2_type == kEndWall;
        // Equal materials: 1/E* = 2 (1-nu^2)/E = (1-nu)/G for two balls; a rigid wall
        // contributes nothing, so E* = E/(1-nu^2) = 2G/(1-nu) (Johnson 1985).
        const double one_side_compliance = (1.0 - hz_poiss) / (2.0 * hz_shear);  // (1-nu^2)/E
        e_star_ =
            hz_shear > 0.0 ? 1.0 / (wall ? one_side_compliance : 2.0 * one_side_compliance) : 0.0;
        // Mindlin: 1/G* = (2-nu_A)/G_A + (2-nu_B)/G_B; the rigid wall's term is zero.
        g_star_ = hz_shear > 0.0 ? hz_shear / ((wall ? 1.0 : 2.0) * (2.0 - hz_poiss)) : 0.0;
        const double r1 = pb.radius[0], r2 = pb.radius[1];
        r_star_ = wall || !(r2 > 0.0) ? r1 : r1 * r2 / (r1 + r2);
        mass_eff_ = pb.mass_eff;
        return true;
    }

    bool noTension() const { return dp_mode == 1.0 || dp_mode == 3.0; }
    bool noShearDashpotWhileSliding() const { return dp_mode >= 2.0; }

    // Tangent normal stiffness dF_n/du_n = 2 E* sqrt(R* u_n) and Mindlin shear stiffness.
    double normalTangent(double overlap) const {
        return overlap > 0.0 ? 2.0 * e_star_ * std::sqrt(r_star_ * overlap) : 0.0;
    }
    double shearTangent(double overlap) const {
        return overlap > 0.0 ? 8.0 * g_star_ * std::sqrt(r_star_ * overlap) : 0.0;
    }

    // Antiderivative of the normal dashpot coefficient c(u) = 2 beta sqrt(m* 2 E* sqrt(R* u)):
    // C(u) = (4/5) c(u) u for u > 0 and 0 otherwise. The dashpot impulse over a window in which
    // the overlap goes from a to b is C(b) - C(a) whatever the path, which is what makes the
    // total dashpot impulse of a full-mode contact exactly zero (the sliding-impulse identity of
    // a linear spring-dashpot, here for c ~ u^(1/4)).
    double dashpotPotential(double overlap) const {
        if (!(overlap > 0.0)) return 0.0;
        return 0.8 * dashpotCoefficient(dp_nratio, mass_eff_, normalTangent(overlap)) * overlap;
    }

    void fdlaw(FdBlock& fd) {
        mass_eff_ = fd.mass_eff;
        const double dt = fd.tdel;
        const bool energy = (fd.flags & kFdEnergyOn) != 0;
        const double u = fd.u_n;
        // Forces of the last step, for the energy increments (zero before the first step).
        const double dp_fn_old = dp_fn, dp_fs_old = dp_fs, fs_old = hz_fs;
        const double strain_s_old = springEnergy(hz_fs, shearTangent(last_overlap_));
        // Gravity, the other contacts and the rest, as seen in the rates (sdk/dashpot.hpp),
        // with the effective mass both dashpots are solved with. Followed on every call,
        // touching or not, dashpot or not (hz_e may set one later), so it is never stale.
        const double inv_mass = mass_eff_ > 0.0 ? 1.0 / mass_eff_ : 0.0;
        const DashpotLoad other = history_.observe(fd, dp_nratio > 0.0 ? inv_mass : 0.0,
                                                   dp_sratio > 0.0 ? inv_mass : 0.0);

        if (u <= 0.0) {
            // Separated. The dashpot impulse owed between the end of the last step's window
            // and the moment of separation is C(0) - C(window end) (full modes only).
            double closing = 0.0;
            if (touching_ && !noTension() && dp_nratio > 0.0)
                closing = -dashpotPotential(window_end_) / dt;
            if (energy) {
                fd.energy[kEnergyStrain] = 0.0;
                fd.energy[kEnergyDashpot] =
                    0.5 * (dp_fn_old + closing) * fd.du_n - 0.5 * dp_fs_old * fd.du_s;
                // The shear spring lets go of what it stored (the last force was at most
                // fric F_n, which vanishes at separation): micro-slip.
                fd.energy[kEnergySlip] = -0.5 * fs_old * fd.du_s + strain_s_old;
            }
            touching_ = false;
            hz_fn = hz_fs = dp_fs = hz_slip = 0.0;
            dp_fn = closing;
            fd.n_force = closing;
            fd.s_force = 0.0;
            fd.moment = 0.0;
            fd.knest = fd.ksest = fd.krest = 0.0;
            last_overlap_ = u;
            window_end_ = 0.0;
            return;
        }

        const bool first = !touching_;
        const double frac = first ? onsetFraction(u, fd.du_n) : 1.0;
        const double lead = first ? frac : 0.5;
        const double kn_t = normalTangent(u);
        const double kt = shearTangent(u);

        // Normal: Hertz, from the overlap (secant form, no memory).
        hz_fn = (2.0 / 3.0) * kn_t * u;  // = (4/3) E* sqrt(R*) u^(3/2)

        // Shear: on normal unloading keep the elastic shear displacement F_s/k_t, i.e. scale
        // the force with k_t (PFC's simplification of Mindlin-Deresiewicz).
        if (!first && u < last_overlap_ && hz_fs != 0.0) hz_fs *= kt / shearTangent(last_overlap_);
        // On the first step only the part of the shear increment after touch loads the spring.
        const ShearResult sr = updateShearSpring(hz_fs, kt, fd.du_s * frac, fric * hz_fn);
        hz_slip = sr.sliding ? 1.0 : 0.0;

        // Normal dashpot with the coefficient averaged over this step's impulse window, from
        // touch (first step) or half a step back, to half a step ahead (predicted with the
        // half-step rate): c_w = (C(b) - C(a)) / (b - a). The SDK's implicit, impulse-exact
        // dashpotForce then takes c_w as a constant coefficient for the step.
        double dn = 0.0;
        if (dp_nratio > 0.0) {
            const double a = first ? 0.0 : u - lead * fd.du_n;
            const double b = u + 0.5 * fd.du_n;
            const double cn = std::fabs(b - a) > 1e-12 * u
                                  ? (dashpotPotential(b) - dashpotPotential(a)) / (b - a)
                                  : dashpotCoefficient(dp_nratio, mass_eff_, kn_t);
            dn = dashpotForce(cn, mass_eff_, fd.u_dot_n, hz_fn, dt, lead, other.normal);
            window_end_ = b;
        }
        dp_fn = dn;
        double total_law = hz_fn + dn;  // the law's total, before the corner correction
        if (noTension() && hz_fn + dn < 0.0) {
            total_law = 0.0;
            dp_fn = -hz_fn;  // total normal force clipped at zero
            // The clip is a corner of the force history: the total fell linearly from the last
            // step's value to zero within this step and stays there. Central differences miss
            // the impulse slope (tau - dt/2)^2 / 2 around such a corner (see cornerImpulse in
            // plugins/hysdamp); pay it now, with the dashpot.
            const double total_old = last_total_;
            if (!first && total_old > 0.0) {
                const double slope = (hz_fn + dn - total_old) / dt;  // < 0
                const double tau = total_old / -slope;
                const double lag = tau - 0.5 * dt;
                dp_fn += 0.5 * -slope * lag * lag / dt;
            }
        }

        const double cs = dashpotCoefficient(dp_sratio, mass_eff_, kt);
        double ds = 0.0;  // resisting the shear motion
        if (!(sr.sliding && noShearDashpotWhileSliding()))
            ds = dashpotForce(cs, mass_eff_, fd.u_dot_s, -hz_fs, dt, lead, other.shear);
        dp_fs = -ds;

        fd.n_force = hz_fn + dp_fn;
        fd.s_force = hz_fs + dp_fs;
        fd.moment = 0.0;
        if (sr.sliding) fd.flags |= kFdSliding;
        fd.knest = kn_t * dashpotStiffnessFactor(dp_nratio);
        fd.ksest = kt * dashpotStiffnessFactor(dp_sratio);
        fd.krest = 0.0;
        if (energy) {
            // Stored energy from the law itself: int F_n du = (2/5) F_n u, plus the shear spring.
            const double strain_s = springEnergy(hz_fs, kt);
            fd.energy[kEnergyStrain] = 0.4 * hz_fn * u + strain_s;
            // Works are trapezoidal, force at the last and this step times this step's
            // displacement: the work the engine's leapfrog kinetic energy sees (docs/physics/
            // energy.md), so the books close whatever the dashpot's prediction assumed.
            fd.energy[kEnergyDashpot] =
                0.5 * (dp_fn_old + dp_fn) * fd.du_n - 0.5 * (dp_fs_old + dp_fs) * fd.du_s;
            // Shear spring: work in (the last step's applied force and this one's, as the
            // engine pairs them) minus the change of stored energy. This is Coulomb slip, plus
            // the energy a changing k_t removes at constant force (normal loading) or by the
            // scaling (unloading): micro-slip in Mindlin-Deresiewicz terms. It reduces to the
            // SDK's slip work when k_t is constant.
            fd.energy[kEnergySlip] = -0.5 * (fs_old + hz_fs) * fd.du_s - (strain_s - strain_s_old);
        }
        touching_ = true;
        last_overlap_ = u;
        last_total_ = total_law;
    }

    void saveRestoreState(ModelSaveObject& so) {
        so.Double(hz_fn);
        so.Double(hz_fs);
        so.Double(dp_fn);
        so.Double(dp_fs);
        so.Double(hz_slip);
        so.Double(e_star_);
        so.Double(g_star_);
        so.Double(r_star_);
        so.Double(mass_eff_);
        so.Double(last_overlap_);
        so.Double(window_end_);
        so.Double(last_total_);
        // Version 2 added the dashpots' history; data of version 1 restores without it (the
        // next call then estimates nothing, as on a first touch).
        if (so.IsSaving() || so.DataVersion() >= 2)
            history_.saveRestore(so);
        else
            history_.reset();
        so.Bool(touching_);
    }

    int32_t Version() const override { return 2; }
    double KnEstimate() const override {
        return touching_ ? normalTangent(last_overlap_) * dashpotStiffnessFactor(dp_nratio) : 0.0;
    }
    double KsEstimate() const override {
        return touching_ ? shearTangent(last_overlap_) * dashpotStiffnessFactor(dp_sratio) : 0.0;
    }
    double ContactDuration(double mass_eff, double approach_speed) const override {
        // Elastic Hertz impact (Johnson 1985); a dashpot changes it by a few percent.
        if (!(approach_speed > 0.0) || !(e_star_ > 0.0) || !(r_star_ > 0.0)) return HUGE_VAL;
        return durationFactor() *
               std::pow(mass_eff * mass_eff / (r_star_ * e_star_ * e_star_ * approach_speed), 0.2);
    }
};

ContactModel* createPrototype(int32_t index) { return index == 0 ? new Hertz() : nullptr; }
void destroyPrototype(ContactModel* p) { delete static_cast<Hertz*>(p); }

const PluginInfo kInfo = TALUS_PLUGIN_INFO_INIT("1.0.0", 1, createPrototype, destroyPrototype);

}  // namespace

TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }
