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

#include "body_store.hpp"
#include "engine.hpp"
#include "model_internal.hpp"
#include "talus/errors.hpp"

namespace talus {

void Model::setWallServo(WallId id, const WallServoSettings& in) {
    World& world = *m_world;
    WallData& w = world.bodies.wallOf(id);
    WallServoSettings s = in;
    const std::string who = "wall " + std::to_string(id.index) + " servo: ";
    if (!std::isfinite(s.target))
        throw InputError(who + "target must be finite (got " + messageNumber(s.target) + ")");
    if (!(s.alpha > 0.0 && s.alpha < 2.0))
        throw InputError(who +
                         "alpha must be in (0, 2) (the servo closes the fraction alpha of "
                         "the gap per step; got " +
                         messageNumber(s.alpha) + ")");
    if (!(s.vmax > 0.0) || !std::isfinite(s.vmax))
        throw InputError(who + "vmax must be > 0 [m/s] (got " + messageNumber(s.vmax) + ")");
    if (!std::isnan(s.gain) && !(s.gain > 0.0 && std::isfinite(s.gain)))
        throw InputError(who + "gain must be > 0 (got " + messageNumber(s.gain) + ")");
    // Length of the stress form: the wall chain's length unless given.
    if (std::isnan(s.length)) {
        double len = 0.0;
        for (uint32_t k = 0; k < w.segment_count; ++k) {
            const Segment& sg = world.bodies.segments[w.first_segment + k];
            len += (world.bodies.vertices[sg.b] - world.bodies.vertices[sg.a]).norm();
        }
        s.length = len;
    }
    if (!(s.length > 0.0) || !std::isfinite(s.length))
        throw InputError(who + "length must be > 0 [m] (got " + messageNumber(s.length) + ")");
    // Direction: the normal of the chord from the first to the last vertex, pointing to the
    // balls' centroid (the side of the material). A closed wall has no such side: give dir.
    if (std::isnan(s.dir.x()) || std::isnan(s.dir.y())) {
        if (w.closed)
            throw InputError(who + "a closed wall has no default direction: give dir = {x, y}");
        const Vec2 a = world.bodies.vertices[w.first_vertex];
        const Vec2 b = world.bodies.vertices[w.first_vertex + w.vertex_count - 1];
        Vec2 n = perp((b - a).normalized());
        const auto& balls = world.bodies.balls;
        if (balls.size() == 0)
            throw InputError(who + "no balls to tell the material's side: give dir = {x, y}");
        Vec2 c{0.0, 0.0};
        for (std::size_t i = 0; i < balls.size(); ++i) c += balls.pos[i];
        c /= static_cast<double>(balls.size());
        const double side = (c - a).dot(n);
        if (side == 0.0)
            throw InputError(who +
                             "the balls' centroid lies on the wall's line: give dir = {x, y}");
        s.dir = side > 0.0 ? n : Vec2(-n);
    }
    const double dn = s.dir.norm();
    if (!(dn > 0.0) || !std::isfinite(dn))
        throw InputError(who + "dir must be a finite non-zero vector (got " + vecText(s.dir) + ")");
    s.dir /= dn;
    const bool was_on = w.has_servo && w.servo.settings.on;
    if (was_on && !s.on) {
        // Switched off: the wall stops moving along the servo direction (the rest of its
        // velocity, set by the user, stays).
        const Vec2 d = w.servo.settings.dir;
        w.vel -= w.vel.dot(d) * d;
        w.servo.vel = 0.0;
    }
    w.has_servo = true;
    w.servo.settings = s;
    world.bodies.servos_on += (s.on ? 1 : 0) - (was_on ? 1 : 0);
    world.stepping.limits_stale = true;
}

bool Model::wallServo(WallId id, WallServoState& out) const {
    const World& world = *m_world;
    const WallData& w = world.bodies.wallOf(id);
    if (!w.has_servo) return false;
    out = w.servo;
    return true;
}

void servoWalls(World& world) {
    const double dt = world.clock.dt;
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
