// SPDX-License-Identifier: MIT
//
// Section BRPH: the broadphase margin, both trees (world/broadphase.cpp saves and restores a
// tree: docs/save-format.md, "Box2D's tree"), and the bodies re-inserted this step with
// their flags. A restore checks that every body's proxy is a leaf naming that body and that the
// trees hold no other leaves: a query's hit is turned into a slot through its leaf's body.
#include <cmath>
#include <string>
#include <unordered_set>

#include "save/sections.hpp"

namespace talus {

void writeBroadphase(const World& world, SaveWriter& w) {
    const ContactStore& cs = world.contacts;
    w.f64(cs.margin);
    w.boolean(cs.broadphase_ready);
    if (cs.broadphase_ready) {
        cs.broadphase->save(w);
        cs.wall_broadphase->save(w);
    }
    w.array(cs.moved_balls), w.array(cs.moved_segments);
    w.array(cs.ball_moved), w.array(cs.segment_moved);
}

namespace {

void checkProxies(const World& world, SaveReader& r) {
    const ContactStore& cs = world.contacts;
    const BodyStore& bs = world.bodies;
    const BallArrays& b = bs.balls;
    std::unordered_set<int32_t> used;
    for (std::size_t s = 0; s < b.size(); ++s)
        if (!cs.broadphase->isLeaf(b.proxy[s]) || cs.broadphase->user(b.proxy[s]) != b.handle[s] ||
            !used.insert(b.proxy[s]).second)
            r.fail("ball slot " + std::to_string(s) + " has an invalid broadphase proxy");
    if (cs.broadphase->leafCount() != b.size())
        r.fail("the ball tree holds bodies that do not exist");
    used.clear();
    std::size_t segs = 0;
    for (std::size_t g = 0; g < bs.segments.size(); ++g) {
        const int32_t px = bs.segments[g].proxy;
        if (!bs.walls[bs.segments[g].wall].alive && px == -1) continue;
        if (!cs.wall_broadphase->isLeaf(px) || cs.wall_broadphase->user(px) != g ||
            !used.insert(px).second)
            r.fail("segment " + std::to_string(g) + " has an invalid broadphase proxy");
        ++segs;
    }
    if (cs.wall_broadphase->leafCount() != segs)
        r.fail("the wall tree holds segments that do not exist");
}

/// The force loop reads a flag per ball and per segment, and the detection clears the flags of
/// the listed bodies: sizes and entries must match the bodies.
void checkMoved(const World& world, SaveReader& r) {
    const ContactStore& cs = world.contacts;
    if (cs.broadphase_ready ? (cs.ball_moved.size() != world.bodies.balls.size() ||
                               cs.segment_moved.size() != world.bodies.segments.size())
                            : (!cs.moved_balls.empty() || !cs.moved_segments.empty()))
        r.fail("moved-body flags do not match the bodies");
    for (uint32_t s : cs.moved_balls)
        if (s >= cs.ball_moved.size()) r.fail("a moved ball is out of range");
    for (uint32_t s : cs.moved_segments)
        if (s >= cs.segment_moved.size()) r.fail("a moved segment is out of range");
    for (uint8_t f : cs.ball_moved)
        if (f > 1) r.fail("invalid moved flag");
    for (uint8_t f : cs.segment_moved)
        if (f > 1) r.fail("invalid moved flag");
}

}  // namespace

void readBroadphase(RestoreContext& ctx, SaveReader& r) {
    ContactStore& cs = ctx.world.contacts;
    cs.margin = r.f64();
    if (!(cs.margin >= 0.0) || !std::isfinite(cs.margin)) r.fail("invalid margin");
    cs.broadphase_ready = r.boolean();
    if (cs.broadphase_ready) {
        cs.broadphase->restore(r);
        cs.wall_broadphase->restore(r);
        checkProxies(ctx.world, r);
    }
    r.array(cs.moved_balls, "moved balls"), r.array(cs.moved_segments, "moved segments");
    r.array(cs.ball_moved, "ball flags"), r.array(cs.segment_moved, "segment flags");
    checkMoved(ctx.world, r);
    r.expectEnd();
}

}  // namespace talus
