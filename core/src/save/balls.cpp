// SPDX-License-Identifier: MIT
//
// Section BALL: every ball array as it is in memory (slot order: the force loop's order), the
// broadphase proxy and fat box of each ball, and the handle tables (slot of each handle,
// generations, free handles), so that ball ids stay valid across a restore.
#include <cmath>
#include <string>

#include "save/sections.hpp"

namespace talus {

void writeBalls(const World& world, SaveWriter& w) {
    const BallArrays& b = world.bodies.balls;
    w.u64(b.size());
    w.vec2Array(b.pos), w.vec2Array(b.vel), w.vec2Array(b.force), w.vec2Array(b.fapp);
    w.array(b.angle), w.array(b.spin), w.array(b.moment), w.array(b.mapp);
    w.array(b.radius), w.array(b.mass), w.array(b.inv_mass), w.array(b.inertia);
    w.array(b.inv_inertia), w.array(b.density), w.array(b.fixity), w.array(b.handle);
    w.array(b.proxy);
    w.u64(b.fat.size());
    for (const Box& f : b.fat) w.box(f);
    w.array(b.groups), w.array(b.kn), w.array(b.ks), w.array(b.fric);
    w.array(b.k_tran), w.array(b.k_rot), w.array(b.clump);
    w.array(world.bodies.slot_of), w.array(world.bodies.generation),
        w.array(world.bodies.free_handles);
    w.u64(world.bodies.fixed_balls);
}

namespace {

/// Every live slot named by exactly one handle and back, radii valid, the fixity bits and the
/// count of fixed balls consistent.
void checkBalls(const BodyStore& bs, SaveReader& r) {
    const BallArrays& b = bs.balls;
    const std::size_t n = b.size();
    for (std::size_t s = 0; s < n; ++s) {
        const uint32_t h = b.handle[s];
        if (h == 0 || h > bs.slot_of.size() || bs.slot_of[h - 1] != s)
            r.fail("ball slot " + std::to_string(s) + " has an invalid handle");
        if (!(b.radius[s] > 0.0) || !std::isfinite(b.radius[s]))
            r.fail("ball slot " + std::to_string(s) + " has an invalid radius");
    }
    std::size_t live = 0, fixed = 0;
    for (uint32_t slot : bs.slot_of) {
        if (slot == kDeadSlot) continue;
        if (slot >= n) r.fail("the handle table names a slot out of range");
        ++live;
    }
    if (live != n) r.fail("the handle table does not match the balls");
    for (uint32_t h : bs.free_handles)
        if (h == 0 || h > bs.slot_of.size() || bs.slot_of[h - 1] != kDeadSlot)
            r.fail("a free handle is in use or out of range");
    for (uint8_t f : b.fixity) {
        if (f > (kFixX | kFixY | kFixSpin)) r.fail("invalid fixity bits");
        fixed += f != 0;
    }
    if (fixed != bs.fixed_balls) r.fail("the count of fixed balls does not match");
}

}  // namespace

void readBalls(RestoreContext& ctx, SaveReader& r) {
    BodyStore& bs = ctx.world.bodies;
    BallArrays& b = bs.balls;
    const std::size_t n = r.count(8 * 20, "balls");
    if (n >= kDeadSlot) r.fail("too many balls");
    b.resize(n);
    auto vecs = [&](std::vector<Vec2>& v, const char* what) {
        r.vec2Array(v, what);
        if (v.size() != n) r.fail(std::string(what) + ": wrong number of entries");
    };
    vecs(b.pos, "pos"), vecs(b.vel, "vel"), vecs(b.force, "force"), vecs(b.fapp, "fapp");
    r.array(b.angle, n, "angle"), r.array(b.spin, n, "spin"), r.array(b.moment, n, "moment");
    r.array(b.mapp, n, "mapp"), r.array(b.radius, n, "radius"), r.array(b.mass, n, "mass");
    r.array(b.inv_mass, n, "inv_mass"), r.array(b.inertia, n, "inertia");
    r.array(b.inv_inertia, n, "inv_inertia"), r.array(b.density, n, "density");
    r.array(b.fixity, n, "fixity"), r.array(b.handle, n, "handle");
    r.array(b.proxy, n, "proxy");
    if (r.count(32, "fat boxes") != n) r.fail("fat boxes: wrong number of entries");
    for (Box& f : b.fat) f = r.box();
    r.array(b.groups, n, "groups"), r.array(b.kn, n, "kn"), r.array(b.ks, n, "ks");
    r.array(b.fric, n, "fric"), r.array(b.k_tran, n, "k_tran"), r.array(b.k_rot, n, "k_rot");
    r.array(b.clump, n, "clump");
    r.array(bs.slot_of, "handle table");
    r.array(bs.generation, bs.slot_of.size(), "generations");
    r.array(bs.free_handles, "free handles");
    bs.fixed_balls = r.u64();
    r.expectEnd();
    checkBalls(bs, r);
}

}  // namespace talus
