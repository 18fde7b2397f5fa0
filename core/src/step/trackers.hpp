// SPDX-License-Identifier: MIT
//
// The trackers' part of a step (step/trackers.cpp): one sample of every live tracker at the end
// of the step, in the bookkeeping phase; what the facade (api/trackers.cpp) needs of it. The data
// is world/trackers.hpp. Not installed.
#pragma once

#include <cstddef>
#include <vector>

#include "world/world.hpp"

namespace talus {

/// This step's sample of every live tracker, and its events (bookkeeping.cpp, only while a
/// tracker is live).
void updateTrackers(World& world);
/// The first sample of the tracker at `index`, taken when it is created (no event is delivered).
void firstTrackerSample(World& world, std::size_t index);
/// Ends the tracker at `index`: an open touch closes at its last complete sample (not ended).
void endTracker(World& world, std::size_t index, TrackerState state);
/// Whether the tracker's body still exists.
bool trackedBodyAlive(const World& world, const Tracker& t);
/// Height of the polyline `pts` (x not decreasing) under x: its end heights beyond its ends, the
/// lower end of a vertical step at the step. `hint` (or nullptr): the segment to try first,
/// updated to the one found.
double groundHeight(const std::vector<Vec2>& pts, double x, std::size_t* hint = nullptr);

}  // namespace talus
