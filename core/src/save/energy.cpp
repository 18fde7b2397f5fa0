// SPDX-License-Identifier: MIT
//
// Section ENRG: the energy books (world.hpp, EnergyBooks): the tracing switch, accumulators and
// snapshot, the pending dashpot work, whether the books are still opening, the per-group books
// and the exchange records the last force loop left for the next law of motion.
#include "save/sections.hpp"

namespace talus {

void writeTotals(SaveWriter& w, const EnergyTotals& e) { w.pod(e); }
EnergyTotals readTotals(SaveReader& r) { return r.pod<EnergyTotals>(); }

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
    for (auto& g : e.groups.g) g = r.pod<EnergyBooks::GroupBooks::Group>();
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
    r.expectEnd();
}

}  // namespace talus
