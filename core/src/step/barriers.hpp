// SPDX-License-Identifier: MIT
//
// The barriers' part of a step (step/barriers.cpp; docs/rockfall.md, "Barriers"). Called only
// while a barrier exists. Not installed.
#pragma once

#include "step/step.hpp"
#include "world/world.hpp"

namespace talus {

/// Every free body's position, velocity and spin before the law of motion moves it.
void recordBodyStarts(World& world);
/// Catches the bodies that crossed a barrier in this step (bookkeeping, before the trackers'
/// sample): slows or stops them and books what it took as `barrier`.
void applyBarriers(World& world, const StepContext& step);

}  // namespace talus
