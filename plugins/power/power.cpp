// SPDX-License-Identifier: MIT
//
// `power`: An's elastic-perfectly plastic power-function contact model (An's 2006 UDM;
// An 2006, An & Tannant 2007; docs/models/power.md).
//
//   virgin loading   F = min(kn u, T)                    (elastic to the transition force T,
//                                                         then perfectly plastic)
//   off the virgin   F = F_B (u / u_B)^b   for u < u_B   (the power curve through the origin
//   curve                                                  and the turning point (u_B, F_B);
//                                                          a = F_B / u_B^b, never formed)
//   shear            F_s <- F_s - ks dU_s,  |F_s| <= fric F_n   (linear with slip)
//
// The turning point is the largest overlap reached so far (u_B = u_max, F_B = f_max). That one
// rule gives both the unloading after the maximum (u_dot_n changes sign) and the documented
// reloading before separation: back up the *same* power curve (elastically, no loss) to
// (u_B, F_B), then on along the virgin curve (plastic again at T). No tension: F >= 0, and the
// contact ends when u <= 0 (activity distance 0).
//
// Why the state is per contact. An's (2006) UDM kept (u_B, F_B) in function-level statics, so all
// contacts shared the first contact's turning point (An 2006). Here every datum
// lives in the per-contact object and nothing is static except the property table.
//
// A ball passing through: with too low a T the plastic overlap m* (v0^2 - v_y^2)/(2T) reaches
// the radius (Nejati 2008); the model then stops the run with an error
// naming the fix instead of pushing the ball on through the wall.
//
// Exponent modes (`exp_mode`), chosen once per impact from the approach speed v of the first
// FDlaw (kFdFirstCall):
//   fixed        b = exponent
//   velocity     b = 0.0429 v^3 - 0.4744 v^2 + 2.5508 v + 1.1489       (An 2006, appendix C)
//   velocity_b   b = 7 + (v/8)^3 for v > 4 m/s, else 7                   (Nejati 2008)
//   restitution  b = (1 + r) / e_t^2 - 1, r = min(1, v_y^2 / v^2), v_y = T / sqrt(kn m*)
//                (eq. 5.1 inverted: e^2 = (1 + v_y^2/v0^2)/(b + 1), An & Tannant 2007;
//                below yield r = 1, the elastic-power case e^2 = 2/(b+1)); b >= 1 enforced.
//
// Time-step contract: knest = max(kn, b F/u), F/u the current secant. b F/u is the tangent of
// the power curve at the current point, i.e. the stiffness the contact has (unloading) or will
// have the moment it turns (loading). The step is chosen a cycle ahead of the FDlaw that uses
// it, so the unloading stiffness must be in the estimate *before* the turn; An's (2006)
// instability was a step that did not follow the stiffness actually used.
// ContactDuration = t1 + t2 + t3 of An & Tannant 2007 for the approach speed given.
//
// Energies: strain = the recoverable energy on the current power curve,
// int_0^u a x^b dx = F u / (b+1), plus F_s^2/(2 ks); plastic (per step) = <F_n> du -
// d(recoverable) with <F_n> the mean of the old and new force and du the change of the overlap,
// PFC's energy tracing. du is not clipped at touch and separation: the force of the first
// contact step acts for the whole step, so the bodies lose (1/2) F_1 (u_1 - u_0) although the
// contact began part-way; booking that keeps the energy balance closed. Over an impact the
// plastic work is W_L - W_U (1.4) up to the discretisation error of the restitution.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "talus/contact_model.hpp"
#include "talus/sdk/dashpot.hpp"
#include "talus/sdk/model_base.hpp"
#include "talus/sdk/plastic_work.hpp"
#include "talus/sdk/shear_spring.hpp"

namespace {

using namespace talus;
using namespace talus::sdk;

constexpr double kInf = std::numeric_limits<double>::infinity();

const char* const kExpModes[] = {"fixed", "velocity", "velocity_b", "restitution", nullptr};
enum ExpMode { kFixed = 0, kVelocity = 1, kVelocityB = 2, kRestitution = 3 };

/// sqrt(pi) Gamma(1 + 1/n) / Gamma(1/2 + 1/n) = int_0^1 ds / sqrt(1 - s^n), n = b + 1:
/// the unloading time in units of u_B / (peak unloading speed) (An & Tannant 2007, t3).
double unloadFactor(double b) {
    const double n = b + 1.0;
    return std::sqrt(M_PI) * std::exp(std::lgamma(1.0 + 1.0 / n) - std::lgamma(0.5 + 1.0 / n));
}

class Power final : public ModelBase<Power> {
public:
    static constexpr const char* kName = "power";

    // properties
    double kn = 0.0;           // [N/m]
    double ks = 0.0;           // [N/m]
    double fric = 0.0;         // [-]
    double transition = kInf;  // T [N]
    double exponent = 1.0;     // b [-]
    double exp_mode = 0.0;     // ExpMode
    double target_e = 0.5;     // [-], restitution mode
    // state (read-only)
    double u_max = 0.0;     // turning point overlap u_B [m]
    double f_max = 0.0;     // turning point force F_B [N]
    double plastic = 0.0;   // 1 once the force reached T
    double b_used = 0.0;    // exponent of this impact [-]
    double v_impact = 0.0;  // approach speed at the first FDlaw [m/s]
    double fn = 0.0;        // normal force [N]
    double fs = 0.0;        // shear force [N]
    // per-contact bookkeeping (not properties)
    double u_prev_ = 0.0;   // overlap at the last FDlaw [m]
    double e_rec_ = 0.0;    // recoverable energy at the last FDlaw [J]
    double u_limit_ = 0.0;  // overlap at which the contact geometry fails [m] (0: unknown)
    bool wall_ = false;     // end 2 is a wall
    bool started_ = false;
    bool touching_ = false;
    PlasticWork plastic_work_;  // this contact's plastic work, kept >= 0 (sdk/plastic_work.hpp)

    // One property per entry (clang-format would put every value on its own line).
    // clang-format off
    static const PropTable<Power>& Table() {
        static const PropTable<Power> t = {
            {{"kn", "N/m", kPropInheritable, 0.0, "loading (elastic) normal stiffness", nullptr},
             &Power::kn, 0.0, kStiffnessMax},
            {{"ks", "N/m", kPropInheritable, 0.0, "shear stiffness", nullptr}, &Power::ks, 0.0, kStiffnessMax},
            {{"fric", "-", kPropInheritable, 0.0, "friction coefficient", nullptr},
             &Power::fric, 0.0},
            {{"transition", "N", 0, kInf, "transition force T (inf: elastic-power model)", nullptr},
             &Power::transition, 0.0, kInf, true},
            {{"exponent", "-", 0, 1.0, "unloading exponent b (exp_mode fixed)", nullptr},
             &Power::exponent, 1.0, kInf, false,
             "(An & Tannant 2007: b >= 1 keeps the model dissipative)"},
            {{"exp_mode", "-", kPropInteger, 0.0, "how b is chosen per impact", kExpModes},
             &Power::exp_mode, 0.0, 3.0},
            {{"target_e", "-", 0, 0.5, "target restitution (exp_mode restitution)", nullptr},
             &Power::target_e, 0.0, 1.0, true},
            {{"u_max", "m", kPropReadOnly | kPropState, 0.0, "turning-point overlap u_B", nullptr},
             &Power::u_max},
            {{"f_max", "N", kPropReadOnly | kPropState, 0.0, "turning-point force F_B", nullptr},
             &Power::f_max},
            {{"plastic", "-", kPropReadOnly | kPropState, 0.0, "1 once the force reached T",
              nullptr},
             &Power::plastic},
            {{"b_used", "-", kPropReadOnly | kPropState, 0.0, "exponent of this impact", nullptr},
             &Power::b_used},
            {{"v_impact", "m/s", kPropReadOnly | kPropState, 0.0, "approach speed at first touch",
              nullptr},
             &Power::v_impact},
            {{"pw_fn", "N", kPropReadOnly | kPropState, 0.0, "normal force", nullptr}, &Power::fn},
            {{"pw_fs", "N", kPropReadOnly | kPropState, 0.0, "shear force", nullptr}, &Power::fs},
        };
        return t;
    }
    // clang-format on

    int32_t AcceptProp(int32_t index, double value) override {
        // The table allows +inf for open-ended ranges; only `transition` may be infinite.
        const auto& t = Table();
        if (index >= 0 && index < PropCount() && std::isinf(value) &&
            t[static_cast<std::size_t>(index)].member != &Power::transition)
            return fail(std::string("power: '") + t[static_cast<std::size_t>(index)].info.name +
                        "' must be finite");
        return ModelBase<Power>::AcceptProp(index, value);
    }

    bool inherit(const PropBlock& pb) {
        kn = inheritSeries(kn, pb.kn);
        ks = inheritSeries(ks, pb.ks);
        fric = inheritMin(fric, pb.fric);
        // Past R the centre crosses the wall line and the normal flips; past r1 + r2 the
        // centres cross. Either way the ball is going through (Nejati 2008: too low a T).
        wall_ = pb.end2_type == kEndWall;
        u_limit_ = wall_ ? pb.radius[0] : pb.radius[0] + pb.radius[1];
        if (!(kn > 0.0) || !std::isfinite(kn)) {
            fail(
                "power: 'kn' must be > 0 (set it on the model or inherit it from the balls and "
                "walls)");
            return false;
        }
        return true;
    }

    /// Exponent for an impact at approach speed v [m/s] with effective mass m [kg].
    double exponentFor(double v, double m) const {
        v = std::max(v, 0.0);
        double b = exponent;
        switch (static_cast<int>(exp_mode)) {
            case kVelocity:  // An 2006, appendix C (v in m/s)
                b = ((0.0429 * v - 0.4744) * v + 2.5508) * v + 1.1489;
                break;
            case kVelocityB:  // Nejati (2008); 7 below 4 m/s (a 0.125 step at 4 m/s, documented)
                b = v > 4.0 ? 7.0 + std::pow(v / 8.0, 3.0) : 7.0;
                break;
            case kRestitution: {
                // eq. 5.1 inverted with g from the impact (An & Tannant 2007).
                const double vy = yieldSpeed(m);
                const double r = (v > vy) ? (vy / v) * (vy / v) : 1.0;
                b = (1.0 + r) / (target_e * target_e) - 1.0;
                break;
            }
            default:
                break;
        }
        return std::max(b, 1.0);  // b >= 1 keeps the model dissipative (An & Tannant 2007)
    }

    /// v_y = T / sqrt(kn m*): the approach speed at which the force just reaches T.
    double yieldSpeed(double m) const {
        if (!std::isfinite(transition)) return kInf;
        return (m > 0.0 && kn > 0.0) ? transition / std::sqrt(kn * m) : kInf;
    }

    void fdlaw(FdBlock& fd) {
        if (!started_) {
            // The first FDlaw of the contact (kFdFirstCall): the impact's exponent, once. The
            // sample before it was outside the contact, at u - du_n with zero force.
            started_ = true;
            v_impact = std::max(0.0, fd.u_dot_n);
            b_used = exponentFor(v_impact, fd.mass_eff);
            u_prev_ = fd.u_n - fd.du_n;
            // (a contact already opening is placed where it is, as the engine books it)
            if (u_prev_ > 0.0) u_prev_ = placeOnVirginCurve(std::min(u_prev_, fd.u_n));
        }
        const double b = b_used;
        const double u = fd.u_n;
        // The overlap itself never reaches R: as the centre crosses the wall line the normal
        // flips and the overlap falls again. Stop while the crossing is within one step.
        if (u_limit_ > 0.0 && u + std::fabs(fd.du_n) >= u_limit_) throwPassingThrough(u);
        const double fn_old = fn, u_old = u_prev_, e_old = e_rec_;
        double e_rec = 0.0, slip_work = 0.0;

        if (u > 0.0) {
            if (u >= u_max) {
                // Virgin curve: elastic, then perfectly plastic at T.
                const double elastic = kn * u;
                fn = std::min(elastic, transition);
                if (elastic >= transition) plastic = 1.0;
                u_max = u;
                f_max = fn;
            } else {
                // The power curve through (u_B, F_B); (u/u_B)^b instead of a u^b because
                // u_B^b underflows for the large b of An (2006) (u_B ~ 1e-4 m, b ~ 80).
                fn = f_max * std::pow(u / u_max, b);
            }
            e_rec = fn * u / (b + 1.0);
            // Only the part of the first step after touch loads the shear spring.
            const double du_s = touching_ ? fd.du_s : fd.du_s * onsetFraction(u, fd.du_n);
            const ShearResult sr = updateShearSpring(fs, ks, du_s, fric * fn);
            slip_work = sr.slip_work;
            if (sr.sliding) fd.flags |= kFdSliding;
            touching_ = true;
        } else {
            // Separated: no tension. The shear spring lets go as the Coulomb limit vanishes.
            fn = 0.0;
            slip_work = springEnergy(fs, ks);
            fs = 0.0;
            touching_ = false;
        }

        fd.n_force = fn;
        fd.s_force = fs;
        fd.moment = 0.0;
        writeEstimates(fd, u);
        if (fd.flags & kFdEnergyOn) {
            // <F_n> du over the whole step, including the part of the first and last steps
            // outside the contact: that is the work the central-difference update does with
            // these forces (summation by parts), so the energy balance closes.
            const double work = 0.5 * (fn_old + fn) * (u - u_old);
            fd.energy[kEnergyStrain] = e_rec + springEnergy(fs, ks);
            fd.energy[kEnergySlip] = slip_work;
            fd.energy[kEnergyPlastic] = plastic_work_.book(work - (e_rec - e_old));
        }
        u_prev_ = u;
        e_rec_ = e_rec;
    }

    /// Born overlapping (bodies created or moved into each other): the overlap before the
    /// first step, u_p > 0, was placed, not loaded by any traced work, and the engine books what
    /// the contact holds there as `placement` (docs/physics/energy.md). The contact starts as if
    /// loaded along the virgin curve to u_p: the turning point, the force there and its
    /// recoverable energy the baseline of the first step's plastic work (returns u_p), so that a
    /// contact placed at rest books none and one placed while approaching books only the loss of
    /// its own path (kn (u^2 - u_p^2) (1/2 - 1/(b+1)) >= 0 while elastic). Counted from zero force
    /// and energy, the first step booked -F u/(b+1): the whole placement off the books.
    double placeOnVirginCurve(double placed) {
        fn = std::min(kn * placed, transition);
        if (kn * placed >= transition) plastic = 1.0;
        u_max = placed;
        f_max = fn;
        e_rec_ = fn * placed / (b_used + 1.0);
        return placed;
    }

    [[noreturn]] void throwPassingThrough(double u) const {
        char msg[400];
        std::snprintf(msg, sizeof msg,
                      "power: the overlap %.4g m is within a step of %s (%.4g m): the ball is "
                      "passing through; the plastic overlap m* (v0^2 - v_y^2) / (2T) at "
                      "v0 = %.4g m/s is too large: raise 'transition' (T = %.4g N)",
                      u, wall_ ? "the ball radius" : "the sum of the radii", u_limit_, v_impact,
                      transition);
        throw std::runtime_error(msg);
    }

    /// Current tangent stiffness of the normal law, raised to the power curve's tangent b F/u.
    double normalStiffness(double u) const {
        if (u > 0.0 && fn > 0.0) return std::max(kn, b_used * fn / u);
        return kn;
    }

    void writeEstimates(FdBlock& fd, double u) const {
        fd.knest = normalStiffness(u);
        fd.ksest = ks;
        fd.krest = 0.0;
    }

    void saveRestoreState(ModelSaveObject& so) {
        so.Double(u_max);
        so.Double(f_max);
        so.Double(plastic);
        so.Double(b_used);
        so.Double(v_impact);
        so.Double(fn);
        so.Double(fs);
        so.Double(u_prev_);
        so.Double(e_rec_);
        so.Double(u_limit_);
        so.Bool(wall_);
        so.Bool(started_);
        so.Bool(touching_);
        // Version 2 added the contact's plastic work to date; a contact of version 1 restores
        // with it unknown (+inf: its increments are booked as found, as before).
        if (so.IsSaving() || so.DataVersion() >= 2)
            so.Double(plastic_work_.total);
        else
            plastic_work_.total = HUGE_VAL;
    }

    int32_t Version() const override { return 2; }

    double KnEstimate() const override {
        if (started_) return normalStiffness(std::max(u_prev_, 0.0));
        // Before touch: the stiffness at the first turning point of an elastic impact, b kn.
        // In the speed-dependent modes b is not known yet; the first FDlaw reports it.
        return kn * (static_cast<int>(exp_mode) == kFixed ? std::max(1.0, exponent) : 1.0);
    }
    double KsEstimate() const override { return ks; }

    /// t1 + t2 + t3 of An & Tannant 2007 for an impact at approach speed v.
    double ContactDuration(double m, double v) const override {
        if (!(kn > 0.0) || !(m > 0.0)) return HUGE_VAL;
        v = std::max(v, 0.0);
        const double b = exponentFor(v, m);
        const double omega = std::sqrt(kn / m);
        const double vy = yieldSpeed(m);
        double t12, secant_ratio;  // elastic + plastic time, u_B / F_B
        if (v <= vy) {
            t12 = 0.5 * M_PI / omega;  // quarter period of the elastic spring
            secant_ratio = 1.0 / kn;
        } else {
            const double t1 = std::asin(vy / v) / omega;
            const double t2 = m * std::sqrt(v * v - vy * vy) / transition;
            const double u_b = transition / kn + 0.5 * m * (v * v - vy * vy) / transition;
            t12 = t1 + t2;
            secant_ratio = u_b / transition;
        }
        // t3 = sqrt((b+1) m u_B / (2 F_B)) * sqrt(pi) Gamma(1+1/(b+1)) / Gamma(1/2+1/(b+1))
        const double t3 = std::sqrt((b + 1.0) * m * secant_ratio / 2.0) * unloadFactor(b);
        return t12 + t3;
    }
};

ContactModel* createPrototype(int32_t index) { return index == 0 ? new Power() : nullptr; }
void destroyPrototype(ContactModel* p) { delete static_cast<Power*>(p); }

const PluginInfo kInfo = TALUS_PLUGIN_INFO_INIT("1.0.0", 1, createPrototype, destroyPrototype);

}  // namespace

TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }
