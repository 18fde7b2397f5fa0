// SPDX-License-Identifier: MIT
//
// `hysdamp`: linear contact with different loading and unloading stiffness (hysteretic
// damping; Shimizu & Cundall 2001 as cited by An 2006, Walton & Braun 1986;
// docs/models/hysdamp.md).
//
//   k_load = 2 d kn_m / (1 + d),  k_unload = 2 kn_m / (1 + d)   (kn_m their mean, d = ratio)
//   loading line    F = k_load u                      (anchored at the origin)
//   unloading line  F = k_unload (u - u0),  u0 = (1 - d) u_max  (the residual overlap)
//   F_n = min(k_load u, k_unload (u - u0)): unloading and reloading run along the unloading
//   line, and reloading meets the loading line at u_max and carries on along it (u_max grows).
//   Below u0:  tension = 0: F_n = 0;   tension = 1: F_n = k_load (u - u0) < 0 (elastic tension
//   branch with the loading stiffness, released when the contact separates).
//   shear: linear ks with a Coulomb slider, as the linear model.
//
// Restitution of a free impact: e = sqrt(d) without tension; with tension the bodies also
// climb out of the tension branch, e = sqrt(d - (1 - d)^2), which is real only for
// d > (3 - sqrt 5)/2 = 0.382: the origin of An's (2006) 0.4 <= d rule with tension.
//
// Why the state is u_max and not the last turning point: an incremental law (dF = k_load du
// while loading, k_unload du while unloading, reloading from the zero-force point) moves the
// zero-force overlap inward on every cycle, so that it creeps towards the largest overlap
// and the contact "loses" its radius (the defect in Shimizu & Cundall 2001 as cited by An 2006).
// Anchoring the loading line at the origin makes u0 a function of the largest overlap of this
// contact only: 0 <= u0 = (1 - d) u_max < u_max, constant under repeated cycles of the same
// amplitude, and reset to 0 when the contact separates (the engine clones a fresh object for the
// next touch).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "talus/contact_model.hpp"
#include "talus/sdk/dashpot.hpp"  // onsetFraction
#include "talus/sdk/model_base.hpp"
#include "talus/sdk/plastic_work.hpp"
#include "talus/sdk/shear_spring.hpp"

namespace {

using namespace talus;
using namespace talus::sdk;

const char* const kTensionModes[] = {"off", "on", nullptr};

/// Impulse that central differences miss when the force passes a corner within a step.
/// Central differences apply F(t_n) dt for the window [t_n - dt/2, t_n + dt/2], which is exact
/// while F is linear in time across the window. If the slope dF/dt changes by `slope_jump` at a
/// time `tau` after the previous step (0 <= tau <= dt), the windows of the previous and this
/// step together miss slope_jump (tau - dt/2)^2 / 2, whichever window holds the corner
/// (integrate the two linear pieces). Paid on the step that detects the corner.
double cornerImpulse(double slope_jump, double tau, double dt) {
    const double lag = tau - 0.5 * dt;
    return 0.5 * slope_jump * lag * lag;
}

class HysDamp final : public ModelBase<HysDamp> {
public:
    static constexpr const char* kName = "hysdamp";

    // properties
    double kn_m = 0.0;     // mean normal stiffness (k_load + k_unload)/2 [N/m]
    double d = 1.0;        // stiffness ratio k_load / k_unload [-]
    double ks = 0.0;       // shear stiffness [N/m]
    double fric = 0.0;     // [-]
    double tension = 0.0;  // 0: no tension, 1: tension branch
    // state (read-only)
    double hd_fn = 0.0;    // normal force [N]
    double hd_fs = 0.0;    // shear force [N]
    double hd_umax = 0.0;  // largest overlap of this contact [m]
    double hd_u0 = 0.0;    // residual (zero-force) overlap of the unloading line [m]
    double hd_slip = 0.0;  // 1 while sliding
    // per-contact values (not properties)
    double last_overlap_ = 0.0;
    double last_strain_ = 0.0;     // normal strain energy at the last step [J]
    double last_rate_ = 0.0;       // overlap rate of the last step [m/s]
    double last_applied_ = 0.0;    // normal force applied at the last step, with corrections [N]
    bool last_was_first_ = false;  // the last step was this contact's first
    bool touching_ = false;
    PlasticWork plastic_;  // this contact's plastic work, kept >= 0 (sdk/plastic_work.hpp)

    static const PropTable<HysDamp>& Table() {
        static const PropTable<HysDamp> t = {
            {{"kn_m", "N/m", kPropInheritable, 0.0, "mean normal stiffness (k_load + k_unload)/2",
              nullptr},
             &HysDamp::kn_m,
             0.0,
             kStiffnessMax},
            // The range depends on `tension`; the combination is checked in PreCycle.
            {{"d", "-", 0, 1.0, "ratio k_load / k_unload", nullptr},
             &HysDamp::d,
             0.05,
             1.0,
             false,
             "(Shimizu-Cundall hysteretic damping as An (2006) gives it: 0.05 <= d <= 1 without "
             "tension, 0.4 <= d <= 1 with tension) "},
            {{"ks", "N/m", kPropInheritable, 0.0, "shear stiffness", nullptr},
             &HysDamp::ks,
             0.0,
             kStiffnessMax},
            {{"fric", "-", kPropInheritable, 0.0, "friction coefficient", nullptr},
             &HysDamp::fric,
             0.0},
            {{"tension", "-", kPropInteger, 0.0, "tension branch below the residual overlap",
              kTensionModes},
             &HysDamp::tension,
             0.0,
             1.0},
            {{"hd_fn", "N", kPropReadOnly | kPropState, 0.0, "normal force", nullptr},
             &HysDamp::hd_fn},
            {{"hd_fs", "N", kPropReadOnly | kPropState, 0.0, "shear force", nullptr},
             &HysDamp::hd_fs},
            {{"hd_umax", "m", kPropReadOnly | kPropState, 0.0, "largest overlap of this contact",
              nullptr},
             &HysDamp::hd_umax},
            {{"hd_u0", "m", kPropReadOnly | kPropState, 0.0,
              "residual (zero-force) overlap of the unloading line", nullptr},
             &HysDamp::hd_u0},
            {{"hd_slip", "-", kPropReadOnly | kPropState, 0.0, "1 while sliding", nullptr},
             &HysDamp::hd_slip},
        };
        return t;
    }

    /// Lower limit of d for the tension mode (An 2006).
    double minRatio() const { return tension == 1.0 ? 0.4 : 0.05; }

    const char* PreCycle(const PropBlock& pb) override {
        if (const char* why = ModelBase<HysDamp>::PreCycle(pb)) return why;
        if (d < minRatio()) {
            char buf[320];
            std::snprintf(buf, sizeof buf,
                          "hysdamp: 'd' must be in [%g, 1] when tension = %d (Shimizu-Cundall "
                          "hysteretic damping as An (2006) gives it: 0.4 <= d <= 1 with tension, "
                          "0.05 <= d <= 1 without; with tension a free impact cannot separate for "
                          "d < 0.382) (got %g)",
                          minRatio(), static_cast<int>(tension), d);
            errorText() = buf;
            return errorText().c_str();
        }
        return nullptr;
    }

    bool inherit(const PropBlock& pb) {
        kn_m = inheritSeries(kn_m, pb.kn);
        ks = inheritSeries(ks, pb.ks);
        fric = inheritMin(fric, pb.fric);
        return true;
    }

    double loadStiffness() const { return 2.0 * d * kn_m / (1.0 + d); }
    double unloadStiffness() const { return 2.0 * kn_m / (1.0 + d); }

    /// Normal force at overlap u for the current u_max (Walton & Braun 1986).
    double normalForce(double u) const {
        const double k1 = loadStiffness(), k2 = unloadStiffness();
        const double f = std::min(k1 * u, k2 * (u - hd_u0));
        if (f >= 0.0) return f;
        return tension == 1.0 ? k1 * (u - hd_u0) : 0.0;
    }

    /// Recoverable energy of the normal spring at force f: unloading runs along the unloading
    /// line (slope k_unload), the tension branch is elastic with slope k_load.
    double normalStrain(double f) const {
        return f >= 0.0 ? springEnergy(f, unloadStiffness()) : springEnergy(f, loadStiffness());
    }

    void fdlaw(FdBlock& fd) {
        const bool energy = (fd.flags & kFdEnergyOn) != 0;
        const double u = fd.u_n;

        if (u <= 0.0) {
            // Separated. The last contact step's force was applied for the half step after it;
            // the force really acted until separation, along the law, possibly past the corner
            // at u0, and (with tension) it then jumps to zero. Pay the difference now.
            const double closing = touching_ ? closingImpulse(u, fd) / fd.tdel : 0.0;
            if (energy) {
                fd.energy[kEnergyStrain] = 0.0;
                // Trapezoidal work of the step, minus the strain given back; with tension this
                // includes the energy left in the tension branch, lost with the contact. The
                // closing force C also works over the next step (the engine pairs it with a zero
                // force there), whose displacement is du_n - C dt^2/m*, C itself included.
                const double du_next = fd.mass_eff > 0.0
                                           ? fd.du_n - closing * fd.tdel * fd.tdel / fd.mass_eff
                                           : fd.du_n;
                fd.energy[kEnergyPlastic] =
                    touching_ ? plastic_.book(0.5 * (last_applied_ + closing) * fd.du_n +
                                              0.5 * closing * du_next + last_strain_)
                              : 0.0;
            }
            touching_ = false;
            hd_fn = hd_fs = hd_slip = 0.0;
            fd.n_force = closing;
            fd.s_force = fd.moment = 0.0;
            writeEstimates(fd);
            last_overlap_ = u;
            last_strain_ = 0.0;
            last_rate_ = fd.u_dot_n;
            last_applied_ = 0.0;
            return;
        }

        const bool first = !touching_;
        const double frac = first ? onsetFraction(u, fd.du_n) : 1.0;
        double fn_old = first ? 0.0 : last_applied_;
        const double u_old = first ? 0.0 : last_overlap_;
        // Born overlapping (bodies created or moved into each other): the overlap before this
        // step, u - du_n > 0, was placed, not loaded by any traced work. The engine books what
        // the contact holds there as `placement` (docs/physics/energy.md; at u itself for a
        // contact already opening), so the contact starts as if loaded along the loading line to
        // that overlap: its largest overlap, and its strain there the baseline of the step's
        // plastic work. The step's path from there is the model's own (its work the mean of the
        // forces at both ends: exact on the lines), so the plastic work is the hysteresis of
        // that path alone, >= 0, and 0 for a contact placed at rest. (Counted from zero it was
        // -strain: the whole placement off the books.)
        double strain_before = first ? 0.0 : last_strain_;
        const double placed = first ? std::min(u - fd.du_n, u) : 0.0;
        double du = fd.du_n;
        if (placed > 0.0) {
            du = u - placed;
            hd_umax = std::max(hd_umax, placed);
            hd_u0 = (1.0 - d) * hd_umax;
            fn_old = normalForce(placed);
            strain_before = normalStrain(fn_old);
        }

        const double umax_old = hd_umax, u0_old = hd_u0;
        if (u > hd_umax) {
            hd_umax = u;
        } else if (!first && !last_was_first_ && last_rate_ > 0.0 && fd.u_dot_n < 0.0) {
            // The overlap turned between the last two steps. The largest overlap lies between
            // the samples: with the acceleration constant over the two half steps, the vertex
            // of the parabola through them is v_mid^2 / (2 |a|) above the last sample, v_mid
            // the mean of the two half-step rates. It exceeds the sampled maximum by at most
            // an eighth of one step's relative travel, (v_before - v_after) dt / 8. Without it
            // the unloading line would start from the sampled maximum: the restitution error
            // at 30 steps per contact is then 1e-3 instead of 7e-6. (Not after the first step,
            // whose rate includes the closing of the gap before touch. A prescribed overlap
            // history that reverses abruptly is not a motion with bounded acceleration: there
            // the estimate can raise u_max by up to that eighth of a step.)
            const double v_mid = 0.5 * (last_rate_ + fd.u_dot_n);
            const double decel = (last_rate_ - fd.u_dot_n) / fd.tdel;
            hd_umax = std::max(hd_umax, last_overlap_ + 0.5 * v_mid * v_mid / decel);
        }
        hd_u0 = (1.0 - d) * hd_umax;  // 0 <= u0 < u_max
        hd_fn = normalForce(u);
        const double corner = first ? onsetImpulse(u, fd.du_n, fd.tdel)
                                    : cornersPassed(u_old, u, umax_old, u0_old, fd.tdel);
        const double fn_applied = hd_fn + corner / fd.tdel;

        const ShearResult sr =
            updateShearSpring(hd_fs, ks, fd.du_s * frac, fric * std::max(hd_fn, 0.0));
        hd_slip = sr.sliding ? 1.0 : 0.0;

        fd.n_force = fn_applied;
        fd.s_force = hd_fs;
        fd.moment = 0.0;
        if (sr.sliding) fd.flags |= kFdSliding;
        writeEstimates(fd);
        const double strain = normalStrain(hd_fn);
        if (energy) {
            fd.energy[kEnergyStrain] = strain + springEnergy(hd_fs, ks);
            fd.energy[kEnergySlip] = sr.slip_work;
            // Hysteretic loss: trapezoidal work of the applied force over the step's
            // displacement (the work the engine's leapfrog kinetic energy sees, so the books
            // close) minus the change of recoverable energy (PFC's energy tracing). A step
            // across a corner may give a small negative increment, which later steps make up.
            fd.energy[kEnergyPlastic] =
                plastic_.book(0.5 * (fn_old + fn_applied) * du - (strain - strain_before));
        }
        touching_ = true;
        last_overlap_ = u;
        last_strain_ = strain;
        last_rate_ = fd.u_dot_n;
        last_applied_ = fn_applied;
        last_was_first_ = first;
    }

    /// Slope dF/du of the law just below (`above` false) or above a point, for the state
    /// (u_max, u0) in force before this step.
    double slopeAt(double u, bool above, double umax, double u0) const {
        const double k1 = loadStiffness(), k2 = unloadStiffness();
        if (above ? u >= umax : u > umax) return k1;  // loading line
        if (above ? u >= u0 : u > u0) return k2;      // unloading line
        return tension == 1.0 ? k1 : 0.0;             // tension branch or no force
    }

    /// Touch is a corner of the law (F = 0 before it, slope k_load after): the first step's
    /// correction, with the touch a fraction `frac` of the step before now.
    double onsetImpulse(double u, double du, double dt) const {
        const double frac = onsetFraction(u, du);
        if (!(du > 0.0) || frac >= 1.0) return 0.0;
        const double rate = du / dt;
        return cornerImpulse(loadStiffness() * rate, (1.0 - frac) * dt, dt);
    }

    /// Corners of the law the overlap passed between the last step (u_old) and now (u): the
    /// residual overlap u0 (unloading line to zero force or to the tension branch) and u_max
    /// (unloading line to loading line on reloading). At the turning point itself the rate is
    /// zero and so is the slope jump in time. Uses the law as it was before this step.
    double cornersPassed(double u_old, double u, double umax, double u0, double dt) const {
        if (u == u_old) return 0.0;
        const double rate = (u - u_old) / dt;
        double impulse = 0.0;
        for (const double corner : {u0, umax}) {
            const bool crossed = (u_old < corner && corner <= u) || (u <= corner && corner < u_old);
            if (!crossed || (corner == umax && u < u_old)) continue;  // u_max only on reloading
            const double tau = (corner - u_old) / rate;               // in [0, dt]
            const bool up = u > u_old;
            const double before = slopeAt(corner, !up, umax, u0);
            const double after = slopeAt(corner, up, umax, u0);
            impulse += cornerImpulse((after - before) * rate, tau, dt);
        }
        return impulse;
    }

    /// Impulse owed at separation [N s]. With F_n the force and s_n = k v its rate along the
    /// law at the last contact step, corners at times tau_i (slope jumps ds_i) and separation
    /// at tau_sep after that step, the force acted for
    ///   int_{-dt/2}^{tau_sep} F = F_n (tau_sep + dt/2) + s_n (tau_sep^2 - dt^2/4)/2
    ///                             + sum_i ds_i (tau_sep - tau_i)^2 / 2,
    /// of which central differences applied F_n dt. This covers a force that reaches zero at
    /// separation (a corner, no tension, d = 1), one that reached zero at u0 on the way out,
    /// and the jump from the tension branch to zero.
    double closingImpulse(double u, const FdBlock& fd) const {
        const double dt = fd.tdel;
        if (!(last_overlap_ > u)) return 0.0;
        const double rate = (u - last_overlap_) / dt;  // < 0
        const double tau_sep = separationFraction(u, fd) * dt;
        const double k_last = slopeAt(last_overlap_, false, hd_umax, hd_u0);
        double impulse = hd_fn * (tau_sep - 0.5 * dt) +
                         0.5 * k_last * rate * (tau_sep * tau_sep - 0.25 * dt * dt);
        if (last_overlap_ > hd_u0 && hd_u0 > 0.0) {
            const double tau0 = (hd_u0 - last_overlap_) / rate;
            if (tau0 < tau_sep) {
                const double k_after = tension == 1.0 ? loadStiffness() : 0.0;
                impulse += 0.5 * (k_after - unloadStiffness()) * rate * (tau_sep - tau0) *
                           (tau_sep - tau0);
            }
        }
        return impulse;
    }

    /// Time from the last contact step to separation, in steps. The tension force decelerates
    /// the separation strongly, so the overlap is taken as a parabola over the step,
    /// u(s) = u_n + (v - a dt/2) s + a s^2/2 with v the half-step rate and a = -F_n/m*, rather
    /// than a straight line (which would leave an O(dt^2) error in the closing impulse).
    double separationFraction(double u, const FdBlock& fd) const {
        const double dt = fd.tdel;
        const double linear = last_overlap_ / (last_overlap_ - u);
        if (!(fd.mass_eff > 0.0)) return linear;
        const double a = -hd_fn / fd.mass_eff;
        const double v0 = fd.u_dot_n - 0.5 * a * dt;  // rate at the last contact step
        // Root of u_n + v0 s + a s^2 / 2 = 0 in [0, dt], in the cancellation-free form.
        const double disc = v0 * v0 - 2.0 * a * last_overlap_;
        if (!(disc >= 0.0) || !(v0 < 0.0)) return linear;
        const double s = 2.0 * last_overlap_ / (-v0 + std::sqrt(disc));
        return s >= 0.0 && s <= dt ? s / dt : linear;
    }

    void writeEstimates(FdBlock& fd) const {
        // The unloading stiffness is the larger one: the step must follow it.
        fd.knest = unloadStiffness();
        fd.ksest = ks;
        fd.krest = 0.0;
    }

    void saveRestoreState(ModelSaveObject& so) {
        so.Double(hd_fn);
        so.Double(hd_fs);
        so.Double(hd_umax);
        so.Double(hd_u0);
        so.Double(hd_slip);
        so.Double(last_overlap_);
        so.Double(last_strain_);
        so.Double(last_rate_);
        so.Double(last_applied_);
        so.Bool(last_was_first_);
        so.Bool(touching_);
        // Version 2 added the contact's plastic work to date; a contact of version 1 restores
        // with it unknown (+inf: its increments are booked as found, as before).
        if (so.IsSaving() || so.DataVersion() >= 2)
            so.Double(plastic_.total);
        else
            plastic_.total = HUGE_VAL;
    }

    int32_t Version() const override { return 2; }
    double KnEstimate() const override { return unloadStiffness(); }
    double KsEstimate() const override { return ks; }
    double ContactDuration(double mass_eff, double) const override {
        // Time the force acts in a free impact (Walton & Braun 1986): a quarter period on
        // each line, (pi/2)(sqrt(m/k_load) + sqrt(m/k_unload)); with tension, plus the climb
        // out of the tension branch, asin((1-d)/sqrt(d)) / omega_load. Speed-independent.
        const double k1 = loadStiffness(), k2 = unloadStiffness();
        if (!(k1 > 0.0)) return HUGE_VAL;
        double t = 0.5 * M_PI * (std::sqrt(mass_eff / k1) + std::sqrt(mass_eff / k2));
        if (tension == 1.0)
            t += std::asin(std::min(1.0, (1.0 - d) / std::sqrt(d))) * std::sqrt(mass_eff / k1);
        return t;
    }
};

ContactModel* createPrototype(int32_t index) { return index == 0 ? new HysDamp() : nullptr; }
void destroyPrototype(ContactModel* p) { delete static_cast<HysDamp*>(p); }

const PluginInfo kInfo = TALUS_PLUGIN_INFO_INIT("1.0.0", 1, createPrototype, destroyPrototype);

}  // namespace

TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }
