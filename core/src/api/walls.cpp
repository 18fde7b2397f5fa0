// SPDX-License-Identifier: MIT
//
// The facade, walls: create a chain of segments, read and set its motion, its contact properties,
// its groups and its servo (docs/lua-api.md, "Walls" and "Servo walls").
#include <algorithm>
#include <cmath>

#include "api/input_checks.hpp"
#include "api/operations.hpp"
#include "step/detection.hpp"
#include "talus/errors.hpp"
#include "world/messages.hpp"

namespace talus {

std::vector<std::string> Model::wallGroups(WallId id) const {
    const World& world = *m_world;
    std::vector<std::string> out;
    const uint64_t g = world.bodies.wallOf(id).groups;
    for (std::size_t i = 0; i < world.bodies.group_names.size(); ++i)
        if (g & (uint64_t(1) << i)) out.push_back(world.bodies.group_names[i]);
    return out;
}

void Model::addWallGroup(WallId id, const std::string& group) {
    World& world = *m_world;
    WallData& w = world.bodies.wallOf(id);
    w.groups |= uint64_t(1) << talus::groupIndex(world, group, true);
}

void requireClearOfWalls(const World& world, const Vec2& centre, double radius,
                         const std::string& what) {
    // A wall pushes a ball out on the side its centre is on (walls are two-sided). A ball meant
    // to rest on a floor but placed with its centre at or a little below the floor's line was
    // pushed out underneath and fell through it: with the centre that close to the line, which
    // side it is on is a slip of the coordinates, not a choice. So a ball placed with its centre
    // within half its radius of a segment (overlapping it by more than half its radius) is
    // refused, on either side. Such an overlap is outside what the contact models are for in any
    // case: they assume overlaps small against the radius (the soft-contact approach of Cundall
    // & Strack 1979), and it would launch the ball with at least kn R^2 / 8.
    const double limit = 0.5 * radius;
    for (std::size_t k = 0; k < world.bodies.segments.size(); ++k) {
        const Segment& sg = world.bodies.segments[k];
        const WallData& w = world.bodies.walls[sg.wall];
        if (!w.alive) continue;
        const Vec2& a = world.bodies.vertices[sg.a];
        const Vec2& b = world.bodies.vertices[sg.b];
        const Vec2 d = b - a;
        const double t = std::clamp((centre - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
        const double dist = (centre - (a + t * d)).norm();
        if (!(dist <= limit)) continue;
        throw InputError(what + ": pos " + vecText(centre) + " puts its centre " +
                         messageNumber(dist) + " m from wall " + std::to_string(sg.wall + 1) +
                         " segment " + std::to_string(k - w.first_segment + 1) + " (" + vecText(a) +
                         " to " + vecText(b) + "), at most half its radius " +
                         messageNumber(radius) +
                         ": a wall pushes a ball out on the side its centre is on, and this "
                         "close to the wall's line that side is not meant (a ball placed so on a "
                         "floor falls through it); place it with its centre at least half its "
                         "radius in front of the wall (docs/physics/walls.md)");
    }
}

WallId Model::createWall(const WallDef& d) {
    World& world = *m_world;
    world.stepping.limits_stale = true;
    const std::size_t n = d.points.size();
    if (n < 2) throw InputError("wall: needs at least 2 points (got " + std::to_string(n) + ")");
    if (d.closed && n < 3) throw InputError("wall: a closed wall needs at least 3 points");
    for (std::size_t i = 0; i < n; ++i) {
        const Vec2& p = d.points[i];
        if (!std::isfinite(p.x()) || !std::isfinite(p.y()))
            throw InputError("wall: point " + std::to_string(i + 1) + " is not finite");
        requireCoordinate("wall: point " + std::to_string(i + 1), p);
        const std::size_t j = (i + 1) % n;
        if ((i + 1 < n || d.closed) && (d.points[j] - p).norm() <= 0.0)
            throw InputError("wall: points " + std::to_string(i + 1) + " and " +
                             std::to_string(j + 1) + " coincide (zero-length segment)");
    }
    if (!std::isfinite(d.vel.x()) || !std::isfinite(d.vel.y()) || !std::isfinite(d.spin))
        throw InputError("wall: vel and spin must be finite");
    if (!std::isnan(d.center.x()) || !std::isnan(d.center.y()))
        requireCoordinate("wall: center", d.center);
    for (double v : {d.kn, d.ks, d.fric})
        if (!std::isnan(v) && !(v >= 0.0 && std::isfinite(v)))
            throw InputError("wall: kn, ks and fric must be >= 0 (got " + messageNumber(v) + ")");

    WallData w;
    w.closed = d.closed;
    w.first_vertex = static_cast<uint32_t>(world.bodies.vertices.size());
    w.vertex_count = static_cast<uint32_t>(n);
    Vec2 centroid = Vec2::Zero();
    for (const auto& p : d.points) {
        world.bodies.vertices.push_back(p);
        centroid += p;
    }
    centroid /= static_cast<double>(n);
    w.center = std::isnan(d.center.x()) ? centroid : d.center;
    w.vel = d.vel;
    w.spin = d.spin;
    for (const auto& g : d.groups) w.groups |= uint64_t(1) << talus::groupIndex(world, g, true);
    w.kn = d.kn, w.ks = d.ks, w.fric = d.fric;
    const uint32_t wall_index = static_cast<uint32_t>(world.bodies.walls.size());
    const std::size_t nseg = d.closed ? n : n - 1;
    w.first_segment = static_cast<uint32_t>(world.bodies.segments.size());
    w.segment_count = static_cast<uint32_t>(nseg);
    for (std::size_t i = 0; i < nseg; ++i) {
        Segment s;
        s.wall = wall_index;
        s.a = w.first_vertex + static_cast<uint32_t>(i);
        s.b = w.first_vertex + static_cast<uint32_t>((i + 1) % n);
        const int32_t first = static_cast<int32_t>(w.first_segment);
        const int32_t k = static_cast<int32_t>(i), ns = static_cast<int32_t>(nseg);
        s.prev = (i > 0) ? first + k - 1 : (d.closed ? first + ns - 1 : -1);
        s.next = (i + 1 < nseg) ? first + k + 1 : (d.closed ? first : -1);
        world.bodies.segments.push_back(s);
    }
    world.bodies.walls.push_back(w);
    if (world.contacts.broadphase_ready)
        for (uint32_t i = 0; i < nseg; ++i) insertSegment(world, w.first_segment + i);
    return WallId{wall_index + 1, world.bodies.walls.back().generation};
}

std::size_t Model::wallCount() const {
    const World& world = *m_world;
    return world.bodies.walls.size();
}

std::vector<WallId> Model::wallIds() const {
    const World& world = *m_world;
    std::vector<WallId> ids;
    for (std::size_t i = 0; i < world.bodies.walls.size(); ++i)
        if (world.bodies.walls[i].alive)
            ids.push_back(WallId{static_cast<uint32_t>(i + 1), world.bodies.walls[i].generation});
    return ids;
}

std::vector<Vec2> Model::wallPoints(WallId id) const {
    const World& world = *m_world;
    const WallData& w = world.bodies.wallOf(id);
    return std::vector<Vec2>(world.bodies.vertices.begin() + w.first_vertex,
                             world.bodies.vertices.begin() + w.first_vertex + w.vertex_count);
}

bool Model::wallClosed(WallId id) const {
    const World& world = *m_world;
    return world.bodies.wallOf(id).closed;
}

Vec2 Model::wallVel(WallId id) const {
    const World& world = *m_world;
    return world.bodies.wallOf(id).vel;
}

void Model::setWallVel(WallId id, const Vec2& v) {
    World& world = *m_world;
    world.stepping.limits_stale = true;
    if (!std::isfinite(v.x()) || !std::isfinite(v.y()))
        throw InputError("wall: vel must be finite");
    world.bodies.wallOf(id).vel = v;
}

double Model::wallSpin(WallId id) const {
    const World& world = *m_world;
    return world.bodies.wallOf(id).spin;
}

void Model::setWallSpin(WallId id, double w) {
    World& world = *m_world;
    world.stepping.limits_stale = true;
    if (!std::isfinite(w)) throw InputError("wall: spin must be finite");
    world.bodies.wallOf(id).spin = w;
}

Vec2 Model::wallCenter(WallId id) const {
    const World& world = *m_world;
    return world.bodies.wallOf(id).center;
}

void Model::setWallCenter(WallId id, const Vec2& c) {
    World& world = *m_world;
    requireCoordinate("wall: center", c);
    world.bodies.wallOf(id).center = c;
}

Vec2 Model::wallForce(WallId id) const {
    const World& world = *m_world;
    return world.bodies.wallOf(id).force;
}

double Model::wallContactProp(WallId id, const std::string& name) const {
    const World& world = *m_world;
    const WallData& w = world.bodies.wallOf(id);
    const std::string n = lower(name);
    if (n == "kn") return w.kn;
    if (n == "ks") return w.ks;
    if (n == "fric") return w.fric;
    throw InputError("wall: unknown contact property '" + name + "' (inheritable: kn, ks, fric)");
}

void Model::setWallContactProp(WallId id, const std::string& name, double v) {
    World& world = *m_world;
    if (!std::isnan(v) && !(v >= 0.0 && std::isfinite(v)))
        throw InputError("wall: " + name + " must be >= 0 (got " + messageNumber(v) + ")");
    WallData& w = world.bodies.wallOf(id);
    const std::string n = lower(name);
    if (n == "kn")
        w.kn = v;
    else if (n == "ks")
        w.ks = v;
    else if (n == "fric")
        w.fric = v;
    else
        throw InputError("wall: unknown contact property '" + name +
                         "' (inheritable: kn, ks, fric)");
}

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
    if (std::isnan(s.length)) s.length = chainLength(world, w);
    if (!(s.length > 0.0) || !std::isfinite(s.length))
        throw InputError(who + "length must be > 0 [m] (got " + messageNumber(s.length) + ")");
    s.dir = servoDirection(world, w, s.dir, who);
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

}  // namespace talus
