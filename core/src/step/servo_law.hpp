// SPDX-License-Identifier: MIT
//
// PFC's servo law, shared by the wall servo (wall_servo.cpp) and the servos over sets of walls
// (servo.cpp). Not installed.
//
// With e = target - measured (a stress or a force, compression positive),
//
//     v = G e,   G = alpha L / (K dt)   (stress form; force form: L = 1),
//
// K the sum of the stiffnesses (knest) of the walls' contacts (PFC2D 3.1 "Servo-control" in the
// biaxial test; Potyondy & Cundall 2004, section 3.1). Moving the walls by v dt changes their
// force by about K v dt = alpha L e, so each step closes the fraction alpha of the gap in the
// quasi-static limit: e' = (1 - alpha) e, stable for 0 < alpha < 2 and without overshoot for
// alpha <= 1. The speed is capped at vmax; walls with no contact stiffness (nothing touches
// them) move at vmax toward the target.
#pragma once

#include <algorithm>
#include <limits>

namespace talus {

/// The speed along the servo direction for the error `error`; `gain` receives G (infinite when
/// nothing touches the walls). `length` is 1 for the force form.
inline double servoLawSpeed(double error, double length, double knest, double dt, double alpha,
                            double vmax, double& gain) {
    double v;
    if (knest > 0.0 && dt > 0.0) {
        gain = alpha * length / (knest * dt);
        v = gain * error;
    } else {
        gain = std::numeric_limits<double>::infinity();
        v = error > 0.0 ? vmax : (error < 0.0 ? -vmax : 0.0);
    }
    return std::max(-vmax, std::min(vmax, v));
}

}  // namespace talus
