// SPDX-License-Identifier: MIT
//
// Viscous dashpot, integrated at the time level of the spring force.
//
// Why not the PFC form. PFC evaluates a dashpot on the relative velocity of the half step before
// the force, F_d = c v^(n-1/2). That lags the spring force by half a step and makes the scheme
// first order: an isolated linear impact with damping ratio 0.5 resolved in 30 steps misses the
// restitution by about 6% (../docs/physics/integration.md has the table). Two things fix it:
//
//  1. Implicit midpoint. Central differences apply the impulse F^n dt at step n. The dashpot force
//     consistent with it uses the rate at the *whole* step, v^n = (v^(n-1/2) + v^(n+1/2)) / 2.
//     The rate ahead is predicted as
//         v^(n+1/2) = v^(n-1/2) + dt (a_o - (F_e + F_d) / m),
//     m the effective mass and a_o the acceleration of the rate caused by everything but this
//     contact (gravity, applied forces, the other contacts, damping, a turning normal), which
//     gives the closed form of dashpotForce below.
//  2. Exact impulse at both ends of a contact. The dashpot impulse over a time window is exactly
//     c times the displacement over that window. On the first step the window starts at the
//     moment of touch, a fraction `frac` of a step before now (from the overlap, by linear
//     interpolation); on the step after separation the remaining impulse c v (tau'/dt - 1/2) is
//     applied, with tau' the time from the last contact step to separation. For a normal dashpot
//     that lets the contact pull (mode 0) the total dashpot impulse is then zero, as it is for
//     the continuous law (the closed form of a linear spring-dashpot).
//
// The rest of the model (a_o). Leaving it out (a_o = 0, as this header did until 2026-11) is
// harmless in a short impact but wrong in every persistent contact: a ball resting on a floor has
// v^(n-1/2) = 0 and F_e = m g, so the predicted rate is -dt g / 2, the dashpot pulls by
// c dt g / 2 / (1 + c dt / 2m), the spring carries that much more than the weight, and the work
// of that force is booked as dissipation for ever. DashpotHistory estimates a_o from what the
// law of motion did with this contact's own force over the last window w = (dt_prev + dt) / 2:
//         a_o = (v^(n-1/2) - v^(n-3/2)) / w + F^(n-1) / m,
// exact for leapfrog whatever a_o is made of. In equilibrium v is constant, a_o = F^(n-1)/m and
// the only fixed point is F_d = 0 (reaction = load to round-off); in steady sliding F_d = c v;
// in an isolated impact a_o = 0 to round-off, so the impact accuracy below is unchanged. The
// estimate lags one step; used raw, that lag shifts the stability limit of a damped packing
// (a 1D chain at beta 0.7 went unstable at 1.2 x the stability rule's step instead of 1.8 x),
// because the fastest mode flips sign every step. The average of the last two estimates has no
// gain at that frequency and restores the old limit (docs/physics/integration.md).
//
// Measured with the engine (tests/core/test_restitution.cpp): worst restitution error over
// random phases of first touch 0.3% for damping ratio 0.7 at 30 steps per sqrt(m/k) pi.
//
// Sign convention: all quantities are "resisting": `rate` is the rate of the displacement the
// dashpot resists, `elastic` the elastic force resisting the same displacement, and the
// returned force resists it too (normal: overlap rate and compression; shear: -s_force).
#pragma once

#include <algorithm>
#include <cmath>

#include "talus/sdk/corners.hpp"

namespace talus::sdk {

/// Dashpot coefficient for a critical damping ratio `beta` [-] (the closed form of a linear
/// spring-dashpot): c = 2 beta sqrt(m k) [N s/m].
inline double dashpotCoefficient(double beta, double mass_eff, double stiffness) {
    return 2.0 * beta * std::sqrt(mass_eff * stiffness);
}

/// Factor by which a stiffness is raised for the time step when a dashpot of ratio beta acts on
/// it: central differences with viscous damping are stable for dt < (sqrt(1+b^2) - b) 2/omega
/// (as PFC's time step does).
inline double dashpotStiffnessFactor(double beta) {
    const double f = std::sqrt(1.0 + beta * beta) - beta;
    return 1.0 / (f * f);
}

/// Fraction of the last step spent in contact, from the overlap now and its increment over the
/// step (linear interpolation of the touch time). 1 when the contact already existed.
inline double onsetFraction(double overlap, double overlap_increment) {
    if (overlap_increment <= overlap || overlap_increment <= 0.0) return 1.0;
    return std::clamp(overlap / overlap_increment, 0.0, 1.0);
}

/// Dashpot force at the time level of the elastic force.
///   c: coefficient [N s/m]; m: effective mass [kg]; rate: half-step rate [m/s];
///   elastic: elastic force resisting the same motion [N]; dt: step [s];
///   lead: time from the start of this step's impulse window to now, in steps: 0.5 for a
///   contact that already existed, onsetFraction() on its first step;
///   other: acceleration of `rate` from everything but this contact [m/s^2]
///   (DashpotHistory; 0 leaves it out).
/// F_d = c ((lead + 1/2) v + (dt/2) (a_o - F_e/m)) / (1 + c dt / 2m).
inline double dashpotForce(double c, double m, double rate, double elastic, double dt,
                           double lead = 0.5, double other = 0.0) {
    if (c <= 0.0) return 0.0;
    const double a = c * dt / (2.0 * m);
    return c * ((lead + 0.5) * rate + 0.5 * dt * (other - elastic / m)) / (1.0 + a);
}

/// dashpotForce with the effective mass given as its inverse (one division instead of two):
/// the form the force loop of a model uses.
inline double dashpotForceInv(double c, double inv_mass, double rate, double elastic, double dt,
                              double lead = 0.5, double other = 0.0) {
    if (c <= 0.0) return 0.0;
    const double lag = 0.5 * dt * inv_mass;
    return c * ((lead + 0.5) * rate + 0.5 * dt * other - lag * elastic) / (1.0 + c * lag);
}

/// Accelerations of a contact's two dashpot rates caused by the rest of the model [m/s^2]:
/// the `other` argument of dashpotForce for the normal and the shear dashpot.
struct DashpotLoad {
    double normal = 0.0;
    double shear = 0.0;
};

/// The load `other` (DashpotHistory::observe) less what springs in parallel with the dashpot's
/// own spring do to the same rates: `normal` and `shear` their forces this step in the resisting
/// sign (compression; -s_force), the inverse masses those observe took. Why: observe learns
/// the contact's whole force (a bond's included) as its own, and dashpotForce subtracts only the
/// `elastic` force it is given; handed the linear spring alone, a parallel bond carrying F_b in
/// equilibrium leaves F_d = F_b c dt / 2m for ever (rate 0, yet booked as dissipation: a resting
/// bonded fragment under 166 kN of locked-in bond force "dissipated" 0.13 J a step per contact).
inline DashpotLoad lessParallelSprings(DashpotLoad other, double normal, double shear,
                                       double inv_mass_n, double inv_mass_s) {
    other.normal -= normal * inv_mass_n;
    other.shear -= shear * inv_mass_s;
    return other;
}

/// What the rest of the model does to a contact's rates, learnt from the rates the host hands
/// in and the forces the contact applied (header comment, "The rest of the model"). One per
/// contact; call observe() at every FDlaw, touching or not, before the dashpot forces. Five
/// doubles of state and about 20 flops a call.
class DashpotHistory {
public:
    /// Estimates for this step from `fd` as it enters FDlaw (its n_force and s_force are the
    /// forces the contact applied at the last step, ABI "previous values on entry"). inv_mass_n
    /// and inv_mass_s are the inverse masses the normal and shear dashpots are solved with (the
    /// same ones, or equilibrium would not be exact); 0 for a direction without a dashpot, which
    /// then costs nothing and gets 0. Zero on the first call of a contact.
    /// (Fd: FdBlock, or anything with its fields flags, tdel, u_dot_n, u_dot_s, n_force,
    /// s_force, such as sdk::LaneFd.)
    template <class Fd>
    DashpotLoad observe(const Fd& fd, double inv_mass_n, double inv_mass_s) {
        DashpotLoad out;
        if (dt_prev_ > 0.0 && !(fd.flags & kFdFirstCall)) {
            // Leapfrog moved the rates by w (a_o - F inv_mass) since the last call, w = (dt_prev
            // + dt)/2 the law of motion's window and F the force applied then (resisting sign:
            // n_force, -s_force). The mean of the last two estimates (the one before a
            // contact's first counting as 0) has no gain at the frequency of a packing's
            // fastest mode, which flips sign every step, so the one-step lag cannot
            // destabilize it.
            const double inv_w = 2.0 / (dt_prev_ + fd.tdel);
            if (inv_mass_n > 0.0) {
                const double est = (fd.u_dot_n - rate_n_) * inv_w + fd.n_force * inv_mass_n;
                out.normal = 0.5 * (est + est_prev_n_);
                est_prev_n_ = est;
            }
            if (inv_mass_s > 0.0) {
                const double est = (fd.u_dot_s - rate_s_) * inv_w - fd.s_force * inv_mass_s;
                out.shear = 0.5 * (est + est_prev_s_);
                est_prev_s_ = est;
            }
        } else {
            est_prev_n_ = est_prev_s_ = 0.0;
        }
        rate_n_ = fd.u_dot_n;
        rate_s_ = fd.u_dot_s;
        dt_prev_ = fd.tdel;
        return out;
    }

    /// Forget the past (the calls were interrupted): the next call estimates nothing.
    void reset() { dt_prev_ = 0.0; }

    /// The five doubles of state, as a lane row's first .. first + 4 (sdk/lanes.hpp).
    static constexpr int kLaneStateSize = 5;
    void toLane(double* row, int first) const {
        row[first] = dt_prev_, row[first + 1] = rate_n_, row[first + 2] = rate_s_;
        row[first + 3] = est_prev_n_, row[first + 4] = est_prev_s_;
    }
    void fromLane(const double* row, int first) {
        dt_prev_ = row[first], rate_n_ = row[first + 1], rate_s_ = row[first + 2];
        est_prev_n_ = row[first + 3], est_prev_s_ = row[first + 4];
    }

    /// Part of a model's saveRestoreState (five doubles).
    void saveRestore(ModelSaveObject& so) {
        so.Double(dt_prev_);
        so.Double(rate_n_);
        so.Double(rate_s_);
        so.Double(est_prev_n_);
        so.Double(est_prev_s_);
    }

private:
    double dt_prev_ = 0.0;                        // the step of the last call (0: none yet) [s]
    double rate_n_ = 0.0, rate_s_ = 0.0;          // the rates at the last call [m/s]
    double est_prev_n_ = 0.0, est_prev_s_ = 0.0;  // the last one-step estimates [m/s^2]
};

/// Energy dissipated by a dashpot force over this step [J]. The dissipation is the impulse times
/// the rate at the force's time level, and that rate is unclipped / (c (lead + 1/2)) by
/// construction of dashpotForce; `applied` may differ from `unclipped` when a no-tension limit
/// cut the force.
inline double dashpotEnergy(double c, double applied, double unclipped, double dt,
                            double lead = 0.5) {
    if (c <= 0.0) return 0.0;
    return applied * unclipped * dt / (c * (lead + 0.5));
}

/// Impulse still owed after separation, as a force over this step [N]. `last_overlap` and
/// `overlap` are the overlaps at the last contact step and now (<= 0); `rate` the rate over
/// the step between them.
inline double dashpotClosingForce(double c, double rate, double last_overlap, double overlap) {
    if (c <= 0.0) return 0.0;
    return c * rate * (closingFraction(last_overlap, overlap) - 0.5);
}

}  // namespace talus::sdk
