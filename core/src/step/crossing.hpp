// SPDX-License-Identifier: MIT
//
// A body's state where its centre crosses a line within a step (the trackers' lines, the
// barriers). Not installed.
#pragma once

#include "talus/vec.hpp"

namespace talus {

/// Position, velocity and spin at fraction s of the interval dt between two samples (p0, v0, w0)
/// and (p1, v1, w1) taken at whole steps with half-step velocities. Between two samples the
/// exact path of a body under a constant acceleration a is the parabola p(t0 + tau) = p0 + v_c
/// tau + a tau (tau - dt) / 2 through both (v_c the chord's velocity), with v(t0 + tau) = v_c +
/// a (tau - dt / 2); in free flight (a = gravity) this is the ballistic state, exactly. The spin
/// is interpolated linearly.
struct CrossingState {
    Vec2 pos, vel;
    double spin;
};
inline CrossingState crossingAt(const Vec2& p0, double w0, const Vec2& p1, double w1, double s,
                                double dt, double ax, double ay) {
    const double tau = s * dt;
    const double cx = (p1.x() - p0.x()) / dt;
    const double cy = (p1.y() - p0.y()) / dt;
    CrossingState c;
    c.pos = Vec2(p0.x() + cx * tau + 0.5 * ax * tau * (tau - dt),
                 p0.y() + cy * tau + 0.5 * ay * tau * (tau - dt));
    c.vel = Vec2(cx + ax * (tau - 0.5 * dt), cy + ay * (tau - 0.5 * dt));
    c.spin = w0 + s * (w1 - w0);
    return c;
}

/// Translational plus rotational kinetic energy, written as the trackers write them (0.5 m v^2,
/// 0.5 I w^2), so that a barrier and a tracker give the same bits for the same state.
inline double translationalEnergy(double mass, const Vec2& v) {
    return 0.5 * mass * (v.x() * v.x() + v.y() * v.y());
}
inline double rotationalEnergy(double inertia, double w) { return 0.5 * inertia * w * w; }

}  // namespace talus
