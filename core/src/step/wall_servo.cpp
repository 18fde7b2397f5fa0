// SPDX-License-Identifier: MIT
//
// Wall servo (PFC "wall servo"): a wall whose velocity along a direction is set every step so
// that the force the balls exert on it (or that force over a length, a stress) tracks a target.
//
// The control law is PFC's (step/servo_law.hpp); a fixed `gain` replaces its formula.
//
// The measured force is WallData::force, the same sum the force loop builds and wallForce()
// reports; the velocity is written into WallData::vel, so moveWalls books the wall's work as
// boundary work as for any moving wall. Runs only when a servo is on
// (BodyStore::servos_on).
#include <cmath>
#include <limits>

#include "step/servo_law.hpp"
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
            v = std::max(-s.vmax, std::min(s.vmax, s.gain * error));
        } else {
            v = servoLawSpeed(error, s.stress ? s.length : 1.0, w.knest, dt, s.alpha, s.vmax,
                              st.gain);
        }
        st.vel = v;
        w.vel += (v - w.vel.dot(d)) * d;
    }
}

}  // namespace talus
