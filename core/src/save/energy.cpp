// SPDX-License-Identifier: MIT
//
// Section ENRG: the energy books (world.hpp, EnergyBooks): the tracing switch, accumulators and
// snapshot, the pending dashpot work, whether the books are still opening, the per-group books
// and the exchange records the last force loop left for the next law of motion.
#include <cstddef>

#include "save/sections.hpp"

namespace talus {

void writeTotals(SaveWriter& w, const EnergyTotals& e) { w.pod(e); }
EnergyTotals readTotals(SaveReader& r) {
    if (r.version() >= 2) return r.pod<EnergyTotals>();
    // Format 1 ended the totals at `exchanged` (`script` and `barrier` came with format 2).
    EnergyTotals e;
    r.bytes(&e, offsetof(EnergyTotals, script));
    return e;
}

namespace {

// What the script changed since the last step (step/script_work.cpp), booked at the next step
// (format 2 on).
void writeMotion(SaveWriter& w, const BodyMotion& m) {
    w.f64(m.mass), w.f64(m.inv_mass), w.f64(m.inertia), w.f64(m.inv_inertia);
    w.vec2(m.vel), w.f64(m.spin), w.vec2(m.force), w.f64(m.moment);
    w.u8(m.fixity), w.u64(m.groups);
}
BodyMotion readMotion(SaveReader& r) {
    BodyMotion m;
    m.mass = r.f64(), m.inv_mass = r.f64(), m.inertia = r.f64(), m.inv_inertia = r.f64();
    m.vel = r.vec2(), m.spin = r.f64(), m.force = r.vec2(), m.moment = r.f64();
    m.fixity = r.u8(), m.groups = r.u64();
    return m;
}
void writeScriptChanges(SaveWriter& w, const EnergyBooks::ScriptChanges& sc) {
    w.boolean(sc.seen), w.vec2(sc.gravity);
    w.f64(sc.damping.local), w.f64(sc.damping.viscous);
    w.u64(sc.bodies.size());
    for (const ScriptBody& e : sc.bodies) {
        w.u32(e.index), w.u32(e.generation);
        w.boolean(e.clump), w.boolean(e.existed), w.boolean(e.deleted);
        writeMotion(w, e.before), writeMotion(w, e.gone);
    }
}
void readScriptChanges(SaveReader& r, EnergyBooks::ScriptChanges& sc, const BodyStore& bs) {
    sc.seen = r.boolean(), sc.gravity = r.vec2();
    sc.damping.local = r.f64(), sc.damping.viscous = r.f64();
    sc.bodies.resize(r.count(2 * 89 + 11, "script changes"));
    sc.index.clear();
    for (std::size_t k = 0; k < sc.bodies.size(); ++k) {
        ScriptBody& e = sc.bodies[k];
        e.index = r.u32(), e.generation = r.u32();
        e.clump = r.boolean(), e.existed = r.boolean(), e.deleted = r.boolean();
        e.before = readMotion(r), e.gone = readMotion(r);
        if (e.clump ? e.index >= bs.clumps.size() : (e.index == 0 || e.index > bs.slot_of.size()))
            r.fail("a script change names a body out of range");
        const uint64_t key =
            e.clump ? ((uint64_t(1) << 63) | e.index) : ((uint64_t(e.generation) << 32) | e.index);
        if (!sc.index.emplace(key, k).second) r.fail("a body is named twice in the script changes");
    }
}

/// One group's books: raw in format 2 on; format 1's totals were shorter.
EnergyBooks::GroupBooks::Group readGroup(SaveReader& r) {
    if (r.version() >= 2) return r.pod<EnergyBooks::GroupBooks::Group>();
    EnergyBooks::GroupBooks::Group g;
    g.acc = readTotals(r), g.snapshot = readTotals(r);
    g.dashpot_pending = r.f64(), g.exchanged_pending = r.f64();
    g.strain_now = r.f64(), g.bond_now = r.f64(), g.held_before = r.f64();
    g.step_kinetic = r.f64(), g.step_body = r.f64(), g.step_damping = r.f64();
    g.step_driven = r.f64();
    return g;
}

}  // namespace

void writeEnergy(const World& world, SaveWriter& w) {
    const EnergyBooks& e = world.books;
    w.boolean(e.on);
    writeTotals(w, e.acc), writeTotals(w, e.snapshot);
    // (the flag that once said "the next force loop books the contacts' baseline" now says
    // "the books are still opening": a file of either kind restores with the books opening)
    w.f64(e.dashpot_pending), w.boolean(e.opening != 0 || e.strain_baseline_pending),
        w.f64(e.last_placed);
    w.boolean(e.groups.on), w.u64(e.groups.traced);
    w.u64(e.groups.g.size());
    for (const auto& g : e.groups.g) w.pod(g);
    w.u64(e.groups.exchange.size());
    for (const auto& x : e.groups.exchange) {
        w.u32(x.end1), w.u32(x.end2), w.boolean(x.wall), w.boolean(x.gone1), w.boolean(x.gone2);
        w.u64(x.g1), w.u64(x.g2), w.vec2(x.f1), w.f64(x.m1), w.f64(x.m2);
        w.vec2(x.v1), w.vec2(x.v2), w.f64(x.w1), w.f64(x.w2);
    }
    writeScriptChanges(w, e.script);
}

void readEnergy(RestoreContext& ctx, SaveReader& r) {
    const World& world = ctx.world;
    EnergyBooks& e = ctx.world.books;
    e.on = r.boolean();
    e.acc = readTotals(r), e.snapshot = readTotals(r);
    // Still opening when saved (api/energy.cpp): they open afresh, at the snapshot after next
    // (as over loaded contacts), where everything they start from is known again.
    e.dashpot_pending = r.f64(), e.opening = r.boolean() ? 2 : 0;
    e.strain_baseline_pending = false;
    e.last_placed = r.f64();
    e.groups.on = r.boolean(), e.groups.traced = r.u64();
    e.groups.g.resize(r.count(sizeof(EnergyBooks::GroupBooks::Group), "group books"));
    for (auto& g : e.groups.g) g = readGroup(r);
    const std::size_t ng = e.groups.g.size();
    if (ng > world.bodies.group_names.size() || (ng < 64 && (e.groups.traced >> ng) != 0))
        r.fail("group books do not match the groups");
    e.groups.exchange.resize(r.count(100, "exchange records"));
    const std::size_t nb = world.bodies.balls.size();
    for (auto& x : e.groups.exchange) {
        x.end1 = r.u32(), x.end2 = r.u32(), x.wall = r.boolean();
        x.gone1 = r.boolean(), x.gone2 = r.boolean();
        x.g1 = r.u64(), x.g2 = r.u64(), x.f1 = r.vec2(), x.m1 = r.f64(), x.m2 = r.f64();
        x.v1 = r.vec2(), x.v2 = r.vec2(), x.w1 = r.f64(), x.w2 = r.f64();
        if (x.end1 >= nb || x.end2 >= (x.wall ? world.bodies.walls.size() : nb))
            r.fail("an exchange record names a body out of range");
    }
    if (r.version() >= 2) readScriptChanges(r, e.script, world.bodies);
    r.expectEnd();
}

}  // namespace talus
