// SPDX-License-Identifier: MIT
//
// Energy per group (group_energy.cpp; docs/physics/energy.md, "Energy per group"): the books
// of each group, filled by the law of motion and the force loop. Everything here runs only
// while world.books.groups.on. Not installed.
#pragma once

#include <cstddef>
#include <cstdint>

#include "world/world.hpp"

namespace talus {

/// Tracing switched on (or groups added): size and zero the books.
void openGroupBooks(World& world);
/// Books a body's terms of this step to each of its groups (the law of motion; the clump pass
/// calls it with a clump's mask): kinetic energy at the snapshot, body work, damping and fixity
/// work (`driven`, split at the snapshot like the whole model's).
inline void bookBodyToGroups(World& world, uint64_t mask, double kinetic, double body,
                             double damping, double driven) {
    auto* groups = world.books.groups.g.data();
    for (uint64_t m = mask & world.books.groups.traced; m; m &= m - 1) {
        auto& gr = groups[__builtin_ctzll(m)];
        gr.step_kinetic += kinetic;
        gr.step_body += body;
        gr.step_damping += damping;
        gr.step_driven += driven;
    }
}
/// Share `s` of one contact's step booked to group `gr`: its slip, dashpot, plastic and released
/// work, the placement energy `placed`, the force `held` before the step, and its stored energy
/// (released when the contact `ends`).
inline void addContactShare(EnergyBooks::GroupBooks::Group& gr, double s, const double* energy,
                            double placed, double held, bool ends, const PairStored& stored) {
    EnergyTotals& a = gr.acc;
    a.slip += s * energy[kEnergySlip];
    gr.dashpot_pending += s * energy[kEnergyDashpot];
    a.plastic += s * energy[kEnergyPlastic];
    a.released += s * energy[kEnergyReleased];
    a.placement += s * placed;
    gr.held_before += s * held;
    if (ends) {
        a.released += s * stored.total();
    } else {
        gr.strain_now += s * stored.strain;
        gr.bond_now += s * stored.bond;
    }
}
/// The force loop's per-contact share (rare path: called only with groups traced). `placement`:
/// its first step, born overlapping (the placement energy just noted, EnergyBooks::last_placed).
void bookContactToGroups(World& world, std::size_t i, const double* energy, double moment,
                         bool placement, bool ends, double held, const Vec2& f, const Vec2& point);
/// The same, with a contact between two balls of the same groups (nearly every contact of a
/// specimen or a rock) booked here, inline: each of its groups takes the whole contact (share
/// 1, so the same sums as bookContactToGroups) and no work crosses a border.
inline void bookContactToOwnGroups(World& world, std::size_t i, const double* energy, double moment,
                                   bool placement, bool ends, double held, const Vec2& f,
                                   const Vec2& point) {
    const Pair& p = world.contacts.pairs[i];
    const uint64_t* of = world.bodies.balls.groups.data();
    if (p.wall || of[p.end1] != of[p.end2]) {
        bookContactToGroups(world, i, energy, moment, placement, ends, held, f, point);
        return;
    }
    auto& gb = world.books.groups;
    const PairStored& stored = world.contacts.stored[i];  // (this step's, written before)
    const double placed = placement ? world.books.last_placed : 0.0;
    auto* groups = gb.g.data();
    for (uint64_t m = of[p.end1] & gb.traced; m; m &= m - 1)
        addContactShare(groups[__builtin_ctzll(m)], 1.0, energy, placed, held, ends, stored);
}
void bookReleasedToGroups(World& world, const Pair& p, double released);
/// Kinetic energy that left the model with a deleted body (or changed at a clump release).
void bookDeletedToGroups(World& world, uint64_t mask, double kinetic);
/// Work done by the script on a body of the groups in `mask` (step/script_work.cpp).
void bookScriptToGroups(World& world, uint64_t mask, double work);
/// Kinetic energy a barrier took from a body of the groups in `mask`.
void bookBarrierToGroups(World& world, uint64_t mask, double taken);
/// A ball slot is being removed (deleted ball or pebble): mark its pending exchange records gone
/// and follow the last slot, which moves into it.
void followRemovedSlot(World& world, uint32_t slot);
void groupForceLoopStart(World& world);         // zero the scratch, drop stale records
void groupForceLoopEnd(World& world);           // strain/bond current values, baseline
void gatherExchangeStart(World& world);         // law of motion: rates before the update
void groupSnapshot(World& world, double lead);  // law of motion: split, snapshot, accumulate
void bookWallToGroups(World& world, uint64_t mask, double work);  // a moving wall's work
/// Velocity and spin of a contact end (a ball slot) before and after the law of motion's
/// update. A pebble end moves with its clump: its work is F . v_c + (d x F + M) w_c, with the
/// moment taken about the clump's centroid (endCentre), which is exactly the clump's half-step
/// kinetic energy change that the force causes. (Inline: called twice per exchange record.)
inline void endRates(const World& world, uint32_t slot, Vec2& v, double& w) {
    const auto& b = world.bodies.balls;
    if (b.clump[slot] != kNoClump) {
        const ClumpData& c = world.bodies.clumps[b.clump[slot]];
        v = c.vel;
        w = c.spin;
        return;
    }
    v = b.vel[slot];
    w = b.spin[slot];
}
/// The point an end's moments are taken about: a ball's centre, a pebble's clump centroid.
inline Vec2 endCentre(const World& world, uint32_t slot) {
    const auto& b = world.bodies.balls;
    return b.clump[slot] != kNoClump ? world.bodies.clumps[b.clump[slot]].pos : b.pos[slot];
}
uint64_t endGroups(const World& world, const Pair& p, bool end2);

}  // namespace talus
