// SPDX-License-Identifier: MIT
//
// Work done by the script (docs/physics/energy.md, "Work done by the script"): what a script
// changes between two steps (a velocity, a spin, a mass, a fixity, an applied load, gravity,
// damping; a body added, deleted, clumped or released) changes what the next energy snapshot
// books, with no traced work behind it. The facade notes each body as it was before its first
// change (note*); the step books the difference as `script` before its law of motion
// (bookScriptWork). Nothing is noted while tracing is off. Not installed.
#pragma once

#include <cstdint>

#include "step/step.hpp"
#include "world/world.hpp"

namespace talus {

/// A ball (a free ball, not a pebble) is about to be changed by the script.
void noteBallChange(World& world, uint32_t slot);
/// A ball was just added (after createBallIn); a pebble is its clump's business.
void noteBallAdded(World& world, uint32_t slot);
/// A ball is about to be deleted by the script: what it holds leaves the books as `deleted`.
void noteBallDeleted(World& world, uint32_t slot);
/// A barrier is about to change a free ball (by slot) or a clump (by index): the change (and any
/// the script makes to the body before the next step) is booked as `barrier`, not `script`.
void noteBarrierChange(World& world, bool clump, uint32_t slot_or_index);
/// The same for a clump (by index).
void noteClumpChange(World& world, uint32_t index);
void noteClumpAdded(World& world, uint32_t index);
void noteClumpDeleted(World& world, uint32_t index);

/// Books what the script changed since the last step, at the start of `step` (before the law of
/// motion): for every body changed, and for every body when gravity or damping changed, what the
/// next snapshot takes for it now less what it would have taken. Exact: the balance after it is
/// the one the run would have had without the change.
void bookScriptWork(World& world, const StepContext& step);
/// The same between two steps (a save), with the next step taken as long as the last.
void settleScriptWork(World& world);

}  // namespace talus
