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
//     For one contact with effective mass m, v^(n+1/2) = v^(n-1/2) - dt (F_e + F_d) / m, which
//     gives the closed form below (other contacts and gravity are left out of the prediction;
//     their effect is second order in dt).
//  2. Exact impulse at both ends of a contact. The dashpot impulse over a time window is exactly
//     c times the displacement over that window. On the first step the window starts at the
//     moment of touch, a fraction `frac` of a step before now (from the overlap, by linear
//     interpolation); on the step after separation the remaining impulse c v (tau'/dt - 1/2) is
//     applied, with tau' the time from the last contact step to separation. For a normal dashpot
//     that lets the contact pull (mode 0) the total dashpot impulse is then zero, as it is for
//     the continuous law (accuracy-reference 1.1, sliding-impulse identity).
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

/// Dashpot coefficient for a critical damping ratio `beta` [-] (accuracy-reference 1.1):
/// c = 2 beta sqrt(m k) [N s/m].
inline double dashpotCoefficient(double beta, double mass_eff, double stiffness) {
    return 2.0 * beta * std::sqrt(mass_eff * stiffness);
}

/// Factor by which a stiffness is raised for the time step when a dashpot of ratio beta acts on
/// it: central differences with viscous damping are stable for dt < (sqrt(1+b^2) - b) 2/omega
/// (accuracy-reference 3.5, as PFC does).
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
///   contact that already existed, onsetFraction() on its first step.
inline double dashpotForce(double c, double m, double rate, double elastic, double dt,
                           double lead = 0.5) {
    if (c <= 0.0) return 0.0;
    const double a = c * dt / (2.0 * m);
    return c * ((lead + 0.5) * rate - 0.5 * dt * elastic / m) / (1.0 + a);
}

/// dashpotForce with the effective mass given as its inverse (one division instead of two):
/// the form the force loop of a model uses.
inline double dashpotForceInv(double c, double inv_mass, double rate, double elastic, double dt,
                              double lead = 0.5) {
    if (c <= 0.0) return 0.0;
    const double lag = 0.5 * dt * inv_mass;
    return c * ((lead + 0.5) * rate - lag * elastic) / (1.0 + c * lag);
}

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
