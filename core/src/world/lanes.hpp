// SPDX-License-Identifier: MIT
//
// A contact's lane (contact_lanes.cpp; docs/plugin-abi.md, "Lanes"): while a contact has a row
// in its rule's lanes, the row holds its model's state and its object is out of date. Not
// installed.
#pragma once

#include "world/world.hpp"

namespace talus {

/// Puts p into its rule's lanes if its model's lane law takes it now (after an FDlaw).
bool enterLane(ContactStore& cs, Pair& p);
/// Brings p's object up to date from its row (before anything reads the object).
void syncLane(const ContactStore& cs, const Pair& p);
/// Takes p out of the lanes, its object up to date (before anything changes the object).
void leaveLane(ContactStore& cs, Pair& p);
/// Frees p's row without updating the object (which is about to be destroyed).
void dropLane(ContactStore& cs, Pair& p);
void leaveAllLanes(World& world);
/// Every table's rows in the order of their pairs (after the pairs were sorted).
void reorderLanes(World& world);

}  // namespace talus
