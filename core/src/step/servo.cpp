// SPDX-License-Identifier: MIT
//
// Servos over sets of walls (talus/servo.hpp; docs/lua-api.md "Servos"). Every step, after the
// time step is chosen and before the walls move, each servo measures what its walls carry (the
// force loop's last wall forces along their directions) and sets one speed for all of them:
//
//   stress, force:  PFC's law on the summed push (servo_law.hpp), the target ramped from what
//                   the walls measured at the first step;
//   rate:           each wall at rate * gauge / 2, so that two walls facing each other close
//                   their gap at the strain rate (a polygon shrinking about its centre: its
//                   apothem at the rate);
//   velocity:       each wall at the target speed;
//
// rates and velocities ramped from the speed when the servo was set. With an equilibrium hold
// (rate, velocity) the walls stand still while PFC's mechanical ratio is above the hold's limit:
// a strain-controlled test with equilibrium holds. A bond that breaks hands its load to its
// neighbours, which break in turn only once the balls between them have moved; local damping
// slows those motions to tens of P-wave crossings, and walls that keep moving meanwhile load a
// specimen whose strength is already going, so the peak rises with the rate. Held, the cascade
// runs its course at fixed strain, and the peak is the last state the specimen holds in
// equilibrium. The walls' velocity
// along their direction is written into WallData::vel, so moveWalls moves them and books their
// work as boundary work, as for any moving wall.
#include <algorithm>
#include <cmath>

#include "step/servo_law.hpp"
#include "step/step.hpp"
#include "world/body_store.hpp"
#include "world/types.hpp"

namespace talus {

double wallGap(const World& world, WallId from, WallId to) {
    const BodyStore& bs = world.bodies;
    const WallData& a = bs.wallOf(from);
    const WallData& b = bs.wallOf(to);
    const Vec2 a0 = bs.vertices[a.first_vertex];
    const Vec2 n = perp((bs.vertices[a.first_vertex + 1] - a0).normalized());
    return std::fabs((bs.vertices[b.first_vertex] - a0).dot(n));
}

namespace {

/// The fraction of the ramp done at step `k` of the servo (1 without a ramp).
double rampFraction(int64_t k, int64_t ramp) {
    return ramp > 0 ? std::min(1.0, static_cast<double>(k + 1) / static_cast<double>(ramp)) : 1.0;
}

/// What the walls carry: each wall's push along its direction, their sum, their stiffness and,
/// for a stress, the loaded length.
void measure(const World& world, ServoState& st) {
    const ServoSettings& s = st.settings;
    st.force = 0.0, st.knest = 0.0;
    st.forces.resize(s.walls.size());
    for (std::size_t k = 0; k < s.walls.size(); ++k) {
        const WallData& w = world.bodies.wallOf(s.walls[k]);
        // The balls push a wall against its direction when they are compressed.
        st.forces[k] = -w.force.dot(s.dirs[k]);
        st.force += st.forces[k];
        st.knest += w.knest;
    }
    if (s.control != ServoControl::Stress) {
        st.stress = kNotSet;
        return;
    }
    st.length = std::isnan(s.length) ? wallGap(world, s.span[0], s.span[1]) : s.length;
    st.stress = st.force / st.length;
}

double servoSpeed(const ServoData& sd, ServoState& st, double dt) {
    const ServoSettings& s = st.settings;
    const double ramp = rampFraction(st.steps, s.ramp);
    switch (s.control) {
        case ServoControl::Rate:
        case ServoControl::Velocity: {
            const double goal =
                s.control == ServoControl::Rate ? 0.5 * s.target * s.gauge : s.target;
            const double v = sd.ramp_from + (goal - sd.ramp_from) * ramp;
            return std::max(-s.vmax, std::min(s.vmax, v));
        }
        case ServoControl::Stress:
        case ServoControl::Force: {
            const bool stress = s.control == ServoControl::Stress;
            const double measured = stress ? st.stress : st.force;
            if (st.steps == 0) st.start = measured;
            const double target = st.start + (s.target - st.start) * ramp;
            double gain = 0.0;
            return servoLawSpeed(target - measured, stress ? st.length : 1.0, st.knest, dt, s.alpha,
                                 s.vmax, gain);
        }
    }
    return 0.0;
}

/// The equilibrium hold (settings.hold_ratio set): the fraction of the speed the walls move at
/// this step. A hold begins when the ratio rises above hold_ratio and ends when it is at or
/// below hold_resume, or after hold_max_steps (after a capped hold the walls move until the
/// ratio falls to hold_resume once). The walls stop at once, and start again over `ramp` steps:
/// a platen that jumps to its speed sends a wave through the specimen whose unbalanced force
/// would hold it again.
double holdFraction(const World& world, ServoState& st) {
    const ServoSettings& s = st.settings;
    st.ratio = unbalancedForce(world).ratio;
    // no contact force at all (infinite ratio): nothing is out of equilibrium that holding
    // would settle, so the walls move on to the material
    const bool finite = std::isfinite(st.ratio);
    const bool settled = !finite || st.ratio <= s.hold_resume;
    if (settled) st.capped = false;
    const bool holding = st.hold_run > 0;
    const auto moving = [&] {
        if (st.hold_run > 0) st.since_hold = 0;
        st.hold_run = 0;
        if (st.since_hold < 0) return 1.0;
        return rampFraction(st.since_hold++, s.ramp);
    };
    if (settled || st.capped || (!holding && !(st.ratio > s.hold_ratio))) return moving();
    if (!holding) ++st.holds;
    if (st.hold_run >= s.hold_max_steps) {
        st.capped = true;
        ++st.holds_capped;
        return moving();
    }
    ++st.hold_run;
    ++st.held;
    return 0.0;
}

}  // namespace

void runServos(World& world, const StepContext& step) {
    for (ServoData& sd : world.servos.list) {
        if (!sd.alive || !sd.state.settings.on) continue;
        ServoState& st = sd.state;
        measure(world, st);
        double v = servoSpeed(sd, st, step.dt);
        if (!std::isnan(st.settings.hold_ratio)) v *= holdFraction(world, st);
        st.speed = v;
        st.displacement += v * step.dt;
        ++st.steps;
        const ServoSettings& s = st.settings;
        for (std::size_t k = 0; k < s.walls.size(); ++k) {
            WallData& w = world.bodies.wallOf(s.walls[k]);
            const Vec2 d = s.dirs[k];
            w.vel += (v - w.vel.dot(d)) * d;
        }
    }
}

}  // namespace talus
