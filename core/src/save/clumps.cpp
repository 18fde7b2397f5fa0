// SPDX-License-Identifier: MIT
//
// Section CLMP: every clump (its rigid-body state, mass properties, forces, fixity, groups,
// properties, and its pebbles with their offsets) and the clump templates.
#include <string>

#include "save/sections.hpp"

namespace talus {

void writeClumps(const World& world, SaveWriter& w) {
    const BodyStore& bs = world.bodies;
    w.u64(bs.clumps.size());
    for (const ClumpData& c : bs.clumps) {
        w.u32(c.generation), w.boolean(c.alive);
        w.vec2(c.pos), w.vec2(c.vel), w.f64(c.angle), w.f64(c.spin);
        w.f64(c.mass), w.f64(c.inv_mass), w.f64(c.inertia), w.f64(c.inv_inertia);
        w.f64(c.density), w.i32(static_cast<int32_t>(c.mode));
        w.vec2(c.force), w.f64(c.moment), w.vec2(c.fapp), w.f64(c.mapp);
        w.u8(c.fixity), w.u64(c.groups), w.f64(c.kn), w.f64(c.ks), w.f64(c.fric);
        w.array(c.pebbles), w.vec2Array(c.offset), w.array(c.angle_offset);
    }
    w.u64(bs.live_clumps), w.u64(bs.pebble_count);
    w.u64(bs.clump_templates.size());
    for (const ClumpTemplate& t : bs.clump_templates) {
        w.u64(t.pebbles.size());
        for (const Pebble& p : t.pebbles) w.vec2(p.pos), w.f64(p.radius);
        w.i32(static_cast<int32_t>(t.mass_mode));
        w.f64(t.props.area), w.vec2(t.props.centroid), w.f64(t.props.polar_moment);
    }
}

namespace {

void readClump(SaveReader& r, ClumpData& c, std::size_t k) {
    c.generation = r.u32(), c.alive = r.boolean();
    c.pos = r.vec2(), c.vel = r.vec2(), c.angle = r.f64(), c.spin = r.f64();
    c.mass = r.f64(), c.inv_mass = r.f64(), c.inertia = r.f64(), c.inv_inertia = r.f64();
    c.density = r.f64();
    c.mode = r.enumValue<ClumpMassMode>(3, "clump mass mode");
    c.force = r.vec2(), c.moment = r.f64(), c.fapp = r.vec2(), c.mapp = r.f64();
    c.fixity = r.u8(), c.groups = r.u64();
    c.kn = r.f64(), c.ks = r.f64(), c.fric = r.f64();
    r.array(c.pebbles, "pebbles");
    r.vec2Array(c.offset, "pebble offsets");
    r.array(c.angle_offset, "pebble angles");
    if (c.offset.size() != c.pebbles.size() || c.angle_offset.size() != c.pebbles.size())
        r.fail("clump " + std::to_string(k + 1) + ": pebble arrays differ in length");
    if (c.fixity > (kFixX | kFixY | kFixSpin)) r.fail("invalid clump fixity bits");
}

/// Pebbles and their clumps name each other, and the counts match.
void checkClumps(const BodyStore& bs, SaveReader& r) {
    const BallArrays& b = bs.balls;
    const std::size_t nc = bs.clumps.size();
    std::size_t live = 0, pebbles = 0;
    for (std::size_t k = 0; k < nc; ++k) {
        const ClumpData& c = bs.clumps[k];
        if (!c.alive) {
            if (!c.pebbles.empty()) r.fail("a deleted clump has pebbles");
            continue;
        }
        ++live;
        if (c.pebbles.empty()) r.fail("clump " + std::to_string(k + 1) + " has no pebbles");
        for (uint32_t h : c.pebbles) {
            if (h == 0 || h > bs.slot_of.size() || bs.slot_of[h - 1] == kDeadSlot ||
                b.clump[bs.slot_of[h - 1]] != k)
                r.fail("clump " + std::to_string(k + 1) + " names an invalid pebble");
            ++pebbles;
        }
    }
    std::size_t marked = 0;
    for (uint32_t k : b.clump) {
        if (k == kNoClump) continue;
        if (k >= nc || !bs.clumps[k].alive) r.fail("a ball names an invalid clump");
        ++marked;
    }
    if (live != bs.live_clumps || pebbles != bs.pebble_count || marked != pebbles)
        r.fail("the clump counts do not match");
}

}  // namespace

void readClumps(RestoreContext& ctx, SaveReader& r) {
    BodyStore& bs = ctx.world.bodies;
    const std::size_t nc = r.count(100, "clumps");
    bs.clumps.resize(nc);
    for (std::size_t k = 0; k < nc; ++k) readClump(r, bs.clumps[k], k);
    bs.live_clumps = r.u64(), bs.pebble_count = r.u64();
    bs.clump_templates.resize(r.count(8, "clump templates"));
    for (ClumpTemplate& t : bs.clump_templates) {
        t.pebbles.resize(r.count(24, "template pebbles"));
        for (Pebble& p : t.pebbles) p.pos = r.vec2(), p.radius = r.f64();
        t.mass_mode = r.enumValue<ClumpMassMode>(3, "template mass mode");
        t.props.area = r.f64(), t.props.centroid = r.vec2(), t.props.polar_moment = r.f64();
    }
    r.expectEnd();
    checkClumps(bs, r);
}

}  // namespace talus
