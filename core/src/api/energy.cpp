// SPDX-License-Identifier: MIT
//
// The facade, energy: switching tracing on and off, and the books it reads, for the whole model
// and per group (docs/physics/energy.md).
#include "step/group_energy.hpp"
#include "talus/errors.hpp"

namespace talus {

void Model::setEnergyTracing(bool on) {
    World& world = *m_world;
    if (on && !world.books.on) {
        world.books.acc = EnergyTotals{};
        const auto& b = world.bodies.balls;
        double ke = 0.0;
        for (std::size_t s = 0; s < b.size(); ++s)
            if (b.clump[s] == kNoClump)  // a pebble's motion is its clump's (below)
                ke += 0.5 *
                      (b.mass[s] * b.vel[s].squaredNorm() + b.inertia[s] * b.spin[s] * b.spin[s]);
        for (const ClumpData& c : world.bodies.clumps)
            if (c.alive) ke += 0.5 * (c.mass * c.vel.squaredNorm() + c.inertia * c.spin * c.spin);
        world.books.acc.initial_kinetic = ke;
        world.books.acc.kinetic = ke;
        world.books.dashpot_pending = 0.0;
        world.books.strain_baseline_pending = false;
        // Until the next step these are the half-step velocities' (m:energies() before any
        // step). The books open at a whole step (law_of_motion.cpp, openBooks): at the next
        // snapshot, or, while contacts are active, at the one after, once their models have said
        // what they hold.
        bool loaded = false;
        for (const Pair& p : world.contacts.pairs) loaded |= p.active;
        world.books.opening = loaded ? 2 : 1;
        world.guard_state.balance = GuardState::BalanceWatch{};
        world.guard_state.balance.open = world.books.acc;
        world.guard_state.balance.open_step = world.clock.step;
        // Models report stored energy only while tracing is on; until the next step it is not
        // known.
        world.books.acc.strain = 0.0;
        for (auto& held : world.contacts.stored) held = PairStored{};
        world.books.snapshot = world.books.acc;
        world.books.on = true;
        world.books.groups = EnergyBooks::GroupBooks{};
        world.books.script = EnergyBooks::ScriptChanges{};
        openGroupBooks(world);
    }
    world.books.on = on;
    if (!on) world.books.groups = EnergyBooks::GroupBooks{};  // tracing off: no group books
}

EnergyTotals Model::energies() const {
    const World& world = *m_world;
    if (!world.books.on)
        throw InputError("energies: energy tracing is off (call energy{on = true} first)");
    return world.books.snapshot;
}

EnergyTotals Model::energies(const std::string& group) const {
    const World& world = *m_world;
    if (!world.books.on)
        throw InputError("energies: energy tracing is off (call energy{on = true} first)");
    for (std::size_t g = 0; g < world.bodies.group_names.size(); ++g)
        if (world.bodies.group_names[g] == group)
            return g < world.books.groups.g.size() ? world.books.groups.g[g].snapshot
                                                   : EnergyTotals{};
    std::string known;
    for (const auto& n : world.bodies.group_names) known += (known.empty() ? "" : ", ") + n;
    throw InputError("energies: unknown group '" + group +
                     "' (groups: " + (known.empty() ? std::string("none") : known) + ")");
}

}  // namespace talus
