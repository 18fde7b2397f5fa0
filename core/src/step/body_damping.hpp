// SPDX-License-Identifier: MIT
//
// Body damping shared by the ball loop (law_of_motion.cpp) and the clump loop
// (clump_motion.cpp): PFC local damping's force and the work both dampings do in one step
// (docs/physics/damping.md). Not installed.
#pragma once

#include <cmath>

#include "talus/vec.hpp"

namespace talus {

/// PFC local damping of one degree of freedom: -alpha |F| sign(v), with sign(0) = 0
/// (the PFC2D manual, "local damping").
inline double localDamping(double alpha, double force, double vel) {
    if (vel == 0.0) return 0.0;
    return -alpha * std::fabs(force) * (vel > 0.0 ? 1.0 : -1.0);
}

/// The work the damping impulses remove over the window w around t (>= 0). Local damping
/// (force `local`, moment `local_moment`) is a force fixed at t, so its impulse works on the
/// velocity at t, the energy snapshot's (`v_now`, `om_now`): with it a damped body in free
/// flight balances to round-off for any step sequence, the first cycle included (there the
/// velocity at t is the given one). The mean of the half-step velocities, used before, equals it
/// only for a steady step after the first cycle; a changing step, or the first cycle's half
/// window against a load, left about D G dt^2/(8m) unbooked (stress seed 1440: local damping
/// 0.88 reversing a ball in its first 0.023 s step, 0.47 J = 1.6% of the throughput). Viscous
/// damping is implicit, F = -c m v_mid, and the scheme removes exactly w F . v_mid from the
/// half-step kinetic energy; booked on v_mid it stays closer for strong damping and changing
/// steps (c dt ~ 0.5: 2% against 5-11% on v_now; docs/physics/energy.md). It acts on
/// translation and spin alike (M = -c I w), per component coefficients (cx, cy, cw) being 0 for
/// a fixed component.
inline double dampingWork(double w, const Vec2& local, double local_moment, const Vec2& v_now,
                          double om_now, const Vec2& v_mid, double om_mid, double mass,
                          double inertia, double cx, double cy, double cw) {
    return -w * (local.dot(v_now) + local_moment * om_now -
                 mass * (cx * v_mid.x() * v_mid.x() + cy * v_mid.y() * v_mid.y()) -
                 cw * inertia * om_mid * om_mid);
}

}  // namespace talus
