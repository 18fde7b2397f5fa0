// SPDX-License-Identifier: MIT
//
// The corners of a contact: touch and separation inside a step.
//
// Central differences apply the force of step n for a whole step (its impulse window runs from
// half a step before to half a step after). A force that starts from zero at touch, or stops at
// separation, somewhere inside a window is then paid the wrong impulse:
//  - a spring force growing from zero at `rate` (k rate tau at the step, tau the time since
//    touch) is owed (k rate / 2)(tau - dt/2)^2 over the first window -- the exact impulse is
//    (k rate / 2)(tau + dt/2)^2, the scheme pays k rate tau dt;
//  - symmetrically at separation, tau' after the last contact step;
//  - a force that stays finite up to separation (a sticking shear spring, a dashpot) is owed
//    its integral from the end of the last window to separation, positive or negative, on the
//    step after: F (tau' - dt/2) + F' (tau'^2 - dt^2/4) / 2 with F' its rate of change.
// Paying these makes the impulses exact for motion that is linear across the corner, and the
// restitution of a resolved impact correspondingly accurate (docs/physics/integration.md).
#pragma once

#include <algorithm>
#include <cmath>

#include "talus/contact_model.hpp"

namespace talus::sdk {

/// Time from the last contact step to separation, in steps (tau'/dt in [0, 1]), by linear
/// interpolation of the overlap: `last_overlap` > 0 then, `overlap` <= 0 now.
inline double closingFraction(double last_overlap, double overlap) {
    if (last_overlap <= overlap) return 0.5;
    return std::clamp(last_overlap / (last_overlap - overlap), 0.0, 1.0);
}

/// Onset: the correction on the first contact step, as a force over the step [N] (adds to the
/// spring's force). `lead` = onsetFraction(), `rate` = the rate the spring is loaded at.
inline double springOnsetCorrection(double k, double rate, double dt, double lead) {
    const double x = lead - 0.5;
    return 0.5 * k * std::fabs(rate) * dt * x * x;
}

/// Separation: the correction on the step after the last contact step [N] (repulsive for a
/// normal spring). `frac` = closingFraction().
inline double springClosingCorrection(double k, double rate, double dt, double frac) {
    const double x = frac - 0.5;
    return 0.5 * k * std::fabs(rate) * dt * x * x;
}

/// Separation of a spring whose force is updated incrementally (F <- max(0, F + k du)): from its
/// value `force` at the last contact step it runs on at k `rate` (`rate` the overlap rate, < 0
/// while separating) up to separation, a fraction `frac` of a step later (closingFraction), or
/// to zero before that. Such a force need not reach zero where the overlap does (a normal that
/// turned, a clip at zero on the way); where it does, this is the absolute spring's corner.
struct IncrementalClosing {
    double corner = 0.0;  ///< its integral from the end of the last window on, as a force over
                          ///< the step after the last contact step [N] (a finite force's corner)
    double left = 0.0;    ///< energy of the force still there at separation, F^2 / (2k) [J]
};
inline IncrementalClosing incrementalClosing(double force, double k, double rate, double dt,
                                             double frac) {
    IncrementalClosing c;
    if (!(k > 0.0) || !(force > 0.0)) return c;
    const double slope = k * rate * dt;  // the force's change over a step
    const double end = force + slope * frac < 0.0 ? -force / slope : frac;  // zero before?
    c.corner = force * (end - 0.5) + 0.5 * slope * (end * end - 0.25);
    const double at_end = std::max(0.0, force + slope * end);
    c.left = 0.5 * at_end * at_end / k;
    return c;
}

/// Forces to add at a corner of the linear law's elastic part (normal spring, shear spring
/// with a Coulomb slider), along n and t.
struct Corners {
    double normal = 0.0;
    double shear = 0.0;
};

/// First contact step. A sliding shear force follows the normal spring's corner (Coulomb: it is
/// fric times the normal spring force); a sticking shear spring has a corner of its own.
/// (Fd: FdBlock, or anything with its fields u_dot_n, u_dot_s, tdel, such as sdk::LaneFd.)
template <class Fd>
inline Corners linearOnsetCorners(double kn, double ks, double fric, double shear_force,
                                  bool sliding, const Fd& fd, double lead) {
    Corners c;
    c.normal = springOnsetCorrection(kn, fd.u_dot_n, fd.tdel, lead);
    c.shear =
        sliding ? std::copysign(fric * c.normal, shear_force)
                : -std::copysign(springOnsetCorrection(ks, fd.u_dot_s, fd.tdel, lead), fd.u_dot_s);
    return c;
}

/// Step after separation. `normal_corner`: the normal spring's force fell to zero at the
/// separation (false when a no-tension dashpot had already brought the total force to zero).
/// A sticking shear spring keeps changing at -ks u_dot_s until separation.
template <class Fd>
inline Corners linearClosingCorners(double kn, double ks, double fric, double shear_force,
                                    bool sliding, const Fd& fd, double frac, bool normal_corner) {
    Corners c;
    const double spring_n = springClosingCorrection(kn, fd.u_dot_n, fd.tdel, frac);
    if (normal_corner) c.normal = spring_n;
    c.shear = sliding ? std::copysign(fric * spring_n, shear_force)
                      : shear_force * (frac - 0.5) -
                            0.5 * ks * fd.u_dot_s * fd.tdel * (frac * frac - 0.25);
    return c;
}

}  // namespace talus::sdk
