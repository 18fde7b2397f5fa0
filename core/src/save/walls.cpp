// SPDX-License-Identifier: MIT
//
// Section WALL: walls with their motion state, the force and moment on them, their servo
// (settings with direction and length resolved, and its last step: wall_servo.cpp) and the count
// of servos on; the segments (links, proxies, fat boxes) and the vertices.
#include <string>

#include "save/sections.hpp"

namespace talus {

void writeWalls(const World& world, SaveWriter& w) {
    const BodyStore& bs = world.bodies;
    w.u64(bs.walls.size());
    for (const WallData& wd : bs.walls) {
        w.u32(wd.generation), w.boolean(wd.alive), w.boolean(wd.closed);
        w.u32(wd.first_segment), w.u32(wd.segment_count);
        w.u32(wd.first_vertex), w.u32(wd.vertex_count);
        w.vec2(wd.vel), w.f64(wd.spin), w.vec2(wd.center), w.u64(wd.groups);
        w.f64(wd.kn), w.f64(wd.ks), w.f64(wd.fric), w.vec2(wd.force), w.f64(wd.moment);
        w.f64(wd.knest), w.boolean(wd.has_servo);
        const WallServoState& sv = wd.servo;
        w.boolean(sv.settings.on), w.boolean(sv.settings.stress), w.f64(sv.settings.target);
        w.f64(sv.settings.length), w.f64(sv.settings.gain), w.f64(sv.settings.alpha);
        w.f64(sv.settings.vmax), w.vec2(sv.settings.dir);
        w.f64(sv.force), w.f64(sv.stress), w.f64(sv.vel), w.f64(sv.gain), w.f64(sv.knest);
    }
    w.i32(bs.servos_on);
    w.u64(bs.segments.size());
    for (const Segment& s : bs.segments) {
        w.u32(s.wall), w.u32(s.a), w.u32(s.b), w.i32(s.prev), w.i32(s.next), w.i32(s.proxy);
        w.box(s.fat);
    }
    w.vec2Array(bs.vertices);
}

namespace {

void readWall(SaveReader& r, WallData& wd) {
    wd.generation = r.u32(), wd.alive = r.boolean(), wd.closed = r.boolean();
    wd.first_segment = r.u32(), wd.segment_count = r.u32();
    wd.first_vertex = r.u32(), wd.vertex_count = r.u32();
    wd.vel = r.vec2(), wd.spin = r.f64(), wd.center = r.vec2(), wd.groups = r.u64();
    wd.kn = r.f64(), wd.ks = r.f64(), wd.fric = r.f64();
    wd.force = r.vec2(), wd.moment = r.f64();
    wd.knest = r.f64(), wd.has_servo = r.boolean();
    WallServoState& sv = wd.servo;
    sv.settings.on = r.boolean(), sv.settings.stress = r.boolean();
    sv.settings.target = r.f64(), sv.settings.length = r.f64();
    sv.settings.gain = r.f64(), sv.settings.alpha = r.f64(), sv.settings.vmax = r.f64();
    sv.settings.dir = r.vec2();
    sv.force = r.f64(), sv.stress = r.f64(), sv.vel = r.f64(), sv.gain = r.f64();
    sv.knest = r.f64();
}

/// Walls name their segments and vertices in range; segments name their wall, vertices and
/// neighbours on the same wall.
void checkWalls(const BodyStore& bs, SaveReader& r) {
    const uint64_t nw = bs.walls.size(), ns = bs.segments.size(), nv = bs.vertices.size();
    for (const WallData& wd : bs.walls)
        if (uint64_t(wd.first_segment) + wd.segment_count > ns ||
            uint64_t(wd.first_vertex) + wd.vertex_count > nv)
            r.fail("a wall names segments or vertices out of range");
    for (std::size_t i = 0; i < ns; ++i) {
        const Segment& s = bs.segments[i];
        const auto seg_ok = [&](int32_t k) { return k >= -1 && k < int64_t(ns); };
        if (s.wall >= nw || s.a >= nv || s.b >= nv || !seg_ok(s.prev) || !seg_ok(s.next))
            r.fail("segment " + std::to_string(i) + " is inconsistent");
        const WallData& wd = bs.walls[s.wall];
        if (i < wd.first_segment || i >= uint64_t(wd.first_segment) + wd.segment_count)
            r.fail("segment " + std::to_string(i) + " is outside its wall");
        if (s.prev >= 0 && bs.segments[s.prev].wall != s.wall)
            r.fail("segment " + std::to_string(i) + " links to another wall");
        if (s.next >= 0 && bs.segments[s.next].wall != s.wall)
            r.fail("segment " + std::to_string(i) + " links to another wall");
        if (s.a == s.b) r.fail("segment " + std::to_string(i) + " has one vertex");
    }
}

}  // namespace

void readWalls(RestoreContext& ctx, SaveReader& r) {
    BodyStore& bs = ctx.world.bodies;
    bs.walls.resize(r.count(200, "walls"));
    for (WallData& wd : bs.walls) readWall(r, wd);
    bs.servos_on = r.i32();
    int servos = 0;
    for (const WallData& wd : bs.walls) servos += wd.alive && wd.has_servo && wd.servo.settings.on;
    bs.segments.resize(r.count(56, "segments"));
    for (Segment& s : bs.segments) {
        s.wall = r.u32(), s.a = r.u32(), s.b = r.u32();
        s.prev = r.i32(), s.next = r.i32(), s.proxy = r.i32();
        s.fat = r.box();
    }
    r.vec2Array(bs.vertices, "vertices");
    r.expectEnd();
    if (servos != bs.servos_on) r.fail("the count of servos switched on does not match");
    checkWalls(bs, r);
}

}  // namespace talus
