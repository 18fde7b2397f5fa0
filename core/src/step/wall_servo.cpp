// SPDX-License-Identifier: MIT
//
// Wall servo (PFC "wall servo"): a wall whose velocity along a direction is set every step so
// that the force the balls exert on it (or that force over a length, a stress) tracks a target.
//
// The control law is PFC's (PFC2D 3.1 "Servo-control" in the biaxial test; Potyondy & Cundall
// 2004, section 3.1): with e = target - measured,
//
//     v = G e,   G = alpha L / (K dt)   (stress form; force form: G = alpha / (K dt)),
//
// K the sum of the stiffnesses (knest) of the wall's contacts. Moving the wall by v dt changes
// its force by about K v dt = alpha L e, so each step closes the fraction alpha of the gap in
// the quasi-static limit: the error follows e' = (1 - alpha) e, stable for 0 < alpha < 2 and
// without overshoot for alpha <= 1 (PFC's default 0.5 halves it each step). The speed is capped
// at vmax; a wall with no contact stiffness (nothing touches it) moves at vmax.
//
// The measured force is WallData::force, the same sum the force loop builds and wallForce()
// reports; the velocity is written into WallData::vel, so moveWalls books the wall's work as
// boundary work as for any moving wall. Runs only when a servo is on
// (BodyStore::servos_on).
#include <cmath>
#include <limits>

#include "step/step.hpp"
#include "talus/errors.hpp"
#include "world/body_store.hpp"
#include "world/types.hpp"

namespace talus {

void servoWalls(World& world, const StepContext& step) {
    const double dt = step.dt;
    for (WallData& w : world.bodies.walls) {
        if (!w.alive || !w.has_servo || !w.servo.settings.on) continue;
        WallServoState& st = w.servo;
        const WallServoSettings& s = st.settings;
        const Vec2 d = s.dir;
        // The balls push the wall along -dir when they are compressed.
        st.force = -w.force.dot(d);
        st.stress = st.force / s.length;
        st.knest = w.knest;
        const double error = s.target - (s.stress ? st.stress : st.force);
        double v;
        if (!std::isnan(s.gain)) {
            st.gain = s.gain;
            v = s.gain * error;
        } else if (w.knest > 0.0 && dt > 0.0) {
            st.gain = s.alpha * (s.stress ? s.length : 1.0) / (w.knest * dt);
            v = st.gain * error;
        } else {
            // Nothing touches the wall: move at full speed toward the target.
            st.gain = std::numeric_limits<double>::infinity();
            v = error > 0.0 ? s.vmax : (error < 0.0 ? -s.vmax : 0.0);
        }
        v = std::max(-s.vmax, std::min(s.vmax, v));
        st.vel = v;
        w.vel += (v - w.vel.dot(d)) * d;
    }
}

}  // namespace talus
