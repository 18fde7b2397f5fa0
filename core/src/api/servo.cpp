// SPDX-License-Identifier: MIT
//
// The facade, servos over sets of walls (talus/servo.hpp, step/servo.cpp; docs/lua-api.md
// "Servos"): set once, checked here; the step phase runs them.
#include <cmath>
#include <limits>
#include <string>

#include "api/operations.hpp"
#include "step/step.hpp"
#include "talus/errors.hpp"
#include "world/messages.hpp"

namespace talus {

Vec2 servoDirection(const World& world, const WallData& w, Vec2 dir, const std::string& who) {
    if (std::isnan(dir.x()) || std::isnan(dir.y())) {
        // The normal of the chord from the first to the last vertex, pointing to the balls'
        // centroid (the side of the material). A closed wall has no such side.
        if (w.closed)
            throw InputError(who + "a closed wall has no default direction: give dir = {x, y}");
        const Vec2 a = world.bodies.vertices[w.first_vertex];
        const Vec2 b = world.bodies.vertices[w.first_vertex + w.vertex_count - 1];
        const Vec2 n = perp((b - a).normalized());
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
        dir = side > 0.0 ? n : Vec2(-n);
    }
    const double dn = dir.norm();
    if (!(dn > 0.0) || !std::isfinite(dn))
        throw InputError(who + "dir must be a finite non-zero vector (got " + vecText(dir) + ")");
    return dir / dn;
}

double chainLength(const World& world, const WallData& w) {
    double len = 0.0;
    for (uint32_t k = 0; k < w.segment_count; ++k) {
        const Segment& sg = world.bodies.segments[w.first_segment + k];
        len += (world.bodies.vertices[sg.b] - world.bodies.vertices[sg.a]).norm();
    }
    return len;
}

namespace {

std::string servoName(ServoId id) { return "servo " + std::to_string(id.index) + ": "; }

const ServoData& servoOf(const World& world, ServoId id) {
    if (id.index == 0 || id.index > world.servos.list.size() ||
        !world.servos.list[id.index - 1].alive)
        throw InputError("servo " + std::to_string(id.index) + ": no such servo (removed, or " +
                         std::to_string(world.servos.list.size()) + " were made)");
    return world.servos.list[id.index - 1];
}

ServoData& servoOf(World& world, ServoId id) {
    return const_cast<ServoData&>(servoOf(static_cast<const World&>(world), id));
}

/// The walls: each alive, listed once, in no other servo and without a wall servo switched on.
void checkWalls(const World& world, const ServoSettings& s, uint32_t self, const std::string& who) {
    if (s.walls.empty()) throw InputError(who + "walls: give at least one wall");
    if (!s.dirs.empty() && s.dirs.size() != s.walls.size())
        throw InputError(who + "dirs: " + std::to_string(s.dirs.size()) + " directions for " +
                         std::to_string(s.walls.size()) + " walls");
    for (std::size_t k = 0; k < s.walls.size(); ++k) {
        const WallId id = s.walls[k];
        const WallData& w = world.bodies.wallOf(id);
        for (std::size_t j = 0; j < k; ++j)
            if (s.walls[j].index == id.index)
                throw InputError(who + "wall " + std::to_string(id.index) + " is listed twice");
        if (w.has_servo && w.servo.settings.on)
            throw InputError(who + "wall " + std::to_string(id.index) +
                             " has its own servo switched on (w:servo{on = false} first)");
        for (std::size_t i = 0; i < world.servos.list.size(); ++i) {
            const ServoData& o = world.servos.list[i];
            if (!o.alive || i + 1 == self) continue;
            for (const WallId& other : o.state.settings.walls)
                if (other.index == id.index)
                    throw InputError(who + "wall " + std::to_string(id.index) +
                                     " is moved by servo " + std::to_string(i + 1));
        }
    }
}

void requirePositive(double v, const std::string& what) {
    if (!(v > 0.0) || !std::isfinite(v))
        throw InputError(what + " must be > 0 (got " + messageNumber(v) + ")");
}

/// The settings checked, with the directions, the cap, the length and the gauge resolved.
ServoSettings resolved(const World& world, ServoSettings s, uint32_t self, const std::string& who) {
    checkWalls(world, s, self, who);
    if (!std::isfinite(s.target))
        throw InputError(who + "target must be finite (got " + messageNumber(s.target) + ")");
    if (s.ramp < 0)
        throw InputError(who + "ramp must be >= 0 steps (got " + std::to_string(s.ramp) + ")");
    std::vector<Vec2> dirs(s.walls.size(), Vec2(kNotSet, kNotSet));
    for (std::size_t k = 0; k < s.walls.size(); ++k)
        dirs[k] = servoDirection(world, world.bodies.wallOf(s.walls[k]),
                                 s.dirs.empty() ? dirs[k] : s.dirs[k],
                                 who + "wall " + std::to_string(s.walls[k].index) + ": ");
    s.dirs = dirs;
    const bool pfc = s.control == ServoControl::Stress || s.control == ServoControl::Force;
    if (pfc && !(s.alpha > 0.0 && s.alpha < 2.0))
        throw InputError(who +
                         "alpha must be in (0, 2) (the servo closes the fraction alpha of the gap "
                         "per step; got " +
                         messageNumber(s.alpha) + ")");
    if (std::isnan(s.vmax))
        s.vmax = pfc ? 1.0 : std::numeric_limits<double>::infinity();
    else if (!(s.vmax > 0.0))
        throw InputError(who + "vmax must be > 0 [m/s] (got " + messageNumber(s.vmax) + ")");
    if (s.control == ServoControl::Stress) {
        const bool span = s.span[0].valid() || s.span[1].valid();
        if (!std::isnan(s.length)) {
            requirePositive(s.length, who + "length [m]");
        } else if (span) {
            if (!s.span[0].valid() || !s.span[1].valid())
                throw InputError(who + "span: give two walls");
            (void)world.bodies.wallOf(s.span[0]), (void)world.bodies.wallOf(s.span[1]);
            requirePositive(wallGap(world, s.span[0], s.span[1]), who + "the gap of span");
        } else {
            double len = 0.0;
            for (const WallId& id : s.walls) len += chainLength(world, world.bodies.wallOf(id));
            s.length = len;
        }
    }
    if (!std::isnan(s.hold_ratio)) {
        if (pfc)
            throw InputError(who +
                             "hold: an equilibrium hold stops walls that move at a rate or a "
                             "velocity (a stress or force servo follows its target)");
        requirePositive(s.hold_ratio, who + "hold: ratio");
        if (std::isnan(s.hold_resume)) s.hold_resume = s.hold_ratio;
        if (!(s.hold_resume >= 0.0 && s.hold_resume <= s.hold_ratio))
            throw InputError(who + "hold: resume must be in [0, ratio] (got " +
                             messageNumber(s.hold_resume) + " with ratio " +
                             messageNumber(s.hold_ratio) + ")");
        if (s.hold_max_steps < 1)
            throw InputError(who + "hold: max_steps must be >= 1 (the longest hold; got " +
                             std::to_string(s.hold_max_steps) + ")");
    }
    if (s.control == ServoControl::Rate) {
        if (std::isnan(s.gauge)) {
            if (s.walls.size() < 2)
                throw InputError(who + "a rate needs gauge = the length its strain refers to [m]");
            s.gauge = wallGap(world, s.walls[0], s.walls[1]);
        }
        requirePositive(s.gauge, who + "gauge [m]");
    }
    return s;
}

/// The walls stop moving along their directions (the rest of their velocity stays).
void stopWalls(World& world, ServoData& sd) {
    const ServoSettings& s = sd.state.settings;
    for (std::size_t k = 0; k < s.walls.size(); ++k) {
        WallData& w = world.bodies.wallOf(s.walls[k]);
        w.vel -= w.vel.dot(s.dirs[k]) * s.dirs[k];
    }
    sd.state.speed = 0.0;
}

}  // namespace

ServoId Model::addServo(const ServoSettings& in) {
    World& world = *m_world;
    const auto self = static_cast<uint32_t>(world.servos.list.size() + 1);
    ServoData sd;
    sd.state.settings = resolved(world, in, self, servoName(ServoId{self}));
    world.servos.list.push_back(sd);
    world.servos.on += sd.state.settings.on ? 1 : 0;
    world.stepping.limits_stale = true;
    return ServoId{self};
}

void Model::setServo(ServoId id, const ServoSettings& in) {
    World& world = *m_world;
    ServoData& sd = servoOf(world, id);
    const ServoSettings s = resolved(world, in, id.index, servoName(id));
    const bool was_on = sd.state.settings.on;
    // A new ramp starts from the speed the walls have now.
    sd.ramp_from = was_on ? sd.state.speed : 0.0;
    if (was_on) stopWalls(world, sd);
    ServoState st;
    st.settings = s;
    st.displacement = sd.state.displacement;
    sd.state = st;
    world.servos.on += (s.on ? 1 : 0) - (was_on ? 1 : 0);
    world.stepping.limits_stale = true;
}

ServoState Model::servo(ServoId id) const { return servoOf(*m_world, id).state; }

void Model::removeServo(ServoId id) {
    World& world = *m_world;
    ServoData& sd = servoOf(world, id);
    if (sd.state.settings.on) {
        stopWalls(world, sd);
        --world.servos.on;
    }
    sd.alive = false;
    world.stepping.limits_stale = true;
}

std::size_t Model::servoCount() const {
    std::size_t n = 0;
    for (const ServoData& sd : m_world->servos.list) n += sd.alive ? 1 : 0;
    return n;
}

}  // namespace talus
