// SPDX-License-Identifier: MIT
//
// Section GARD: the stability guard's counters and first findings, and the balance check's
// window and peak (world.hpp, GuardState; docs/physics/guard.md).
#include "save/sections.hpp"

namespace talus {

void writeGuard(const World& world, SaveWriter& w) {
    const GuardState& g = world.guard_state;
    w.i64(g.underresolved), w.str(g.underresolved_first);
    w.i64(g.energy_gain), w.str(g.energy_gain_first);
    w.i64(g.stiffness_lies), w.str(g.stiffness_lies_first);
    w.i64(g.placed), w.f64(g.placed_energy), w.str(g.placed_first);
    writeTotals(w, g.balance.open);
    w.i64(g.balance.open_step), w.f64(g.balance.peak), w.f64(g.balance.reported);
    w.i64(g.balance.findings), w.str(g.balance.first), w.str(g.balance.last);
}

void readGuard(RestoreContext& ctx, SaveReader& r) {
    GuardState& g = ctx.world.guard_state;
    g.underresolved = r.i64(), g.underresolved_first = r.str();
    g.energy_gain = r.i64(), g.energy_gain_first = r.str();
    g.stiffness_lies = r.i64(), g.stiffness_lies_first = r.str();
    g.placed = r.i64(), g.placed_energy = r.f64(), g.placed_first = r.str();
    g.balance.open = readTotals(r);
    g.balance.open_step = r.i64(), g.balance.peak = r.f64(), g.balance.reported = r.f64();
    g.balance.findings = r.i64(), g.balance.first = r.str(), g.balance.last = r.str();
    r.expectEnd();
}

}  // namespace talus
