// SPDX-License-Identifier: MIT
//
// A contact's first FDlaw outside the force loop, at the pair's current geometry, with zero
// increments and rates (the bond contract's first call, docs/plugin-abi.md "Bonds"): m:bond
// installing a bond (api/bonds.cpp), and a bond model's contacts where the script built them
// (firstCallsAtPlacement). Not installed.
#pragma once

#include <cstddef>
#include <string>

#include "world/world.hpp"

namespace talus {

/// The pair's geometry at the first call.
struct FirstCallGeometry {
    Vec2 normal{0.0, 1.0};
    Vec2 point{0.0, 0.0};
    double overlap = 0.0;
};

/// What the pair held before the first call: its forces (those of the last force loop, zero for
/// a pair that was not a contact) and whether it was a contact.
struct FirstCallEntry {
    bool was_active = false;
    double n_force = 0.0, s_force = 0.0, moment = 0.0;
};

/// The step a first call reports in FdBlock::tdel: the last step, else the fixed or largest
/// step the settings give, else 1e-6 s.
double firstCallStep(const World& world);

/// Calls `model`'s FDlaw once with kFdFirstCall (and `flags`) at geometry `g`, zero increments
/// and rates, `fn`/`fs` as the entry forces, into `fd`. Returns what went wrong ("failed: " and
/// the model's message, or "returned a non-finite value"), empty when the call succeeded.
std::string firstCall(const World& world, const Pair& p, ContactModel& model,
                      const FirstCallGeometry& g, double fn, double fs, uint32_t flags,
                      FdBlock& fd);

/// After the first call of pair `i`'s object (now the pair's, its activity set): the pair
/// becomes a contact with the call's forces and estimates, the ball forces the next law of
/// motion applies are corrected by the change of its force, and, with tracing on, the books
/// take the change of what it stores: to `released` (an install, first_call.cpp says how), or,
/// for a contact the script `placed`, what it stores as placement energy. A break in the call
/// is queued.
void takeFirstCall(World& world, std::size_t i, const FirstCallGeometry& g, const FdBlock& fd,
                   const FirstCallEntry& before, bool placed = false);

/// The contacts of a bond model (kTraitBond) that the script made since the last step (bodies
/// placed, moved or given a velocity, between run calls) get their first call where the script
/// built them, before anything moves: a bond that forms on its first call (cbond's cb_bond, a
/// rule with pbond's `bonded` = 1) forms from the state the script built, as PFC's `bond` does,
/// whatever the velocities move in the first step. Every inactive pair of such a model within
/// its activity distance; nothing for a model without bond rules. Called at the start of every
/// run call (Model::cycle, Model::solve).
void firstCallsAtPlacement(World& world);

}  // namespace talus
