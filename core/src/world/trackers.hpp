// SPDX-License-Identifier: MIT
//
// Trackers: per-body records the engine keeps at every step (impacts, line crossings, rest,
// envelopes, paths) so that a script reads them at the end or by event instead of looking at
// every contact and every body each step (docs/lua-api.md, "Trackers"). The data of the World's
// `trackers` part; the per-step update is step/trackers.cpp, the facade api/trackers.cpp. Not
// installed.
//
// A model without trackers pays one test of `live` per step (bookkeeping.cpp).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "talus/model_types.hpp"

namespace talus {

/// One tracker: its definition, its state between samples and its records.
struct Tracker {
    TrackerDef def;
    BallId ball;  // the tracked body: a free ball, or
    ClumpId clump;
    TrackerState state = TrackerState::Tracking;
    int64_t samples = 0;
    // The last complete sample, and whether the body touched anything then (the crossings'
    // interpolation takes gravity as the acceleration only between two samples in free flight).
    bool has_last = false;
    TrackedState last;
    bool last_touched = false;
    // Touching something of the impacts' kind at the last sample; the open impact (-1: none).
    bool touching = false;
    int32_t open_impact = -1;
    double rest_since = kNotSet;
    std::size_t ground_segment = 0;  // where the envelope's ground was last looked up
    // A sample halted at a line with `event`: the rest of it (lines after `resume_line`, the
    // envelope, the path, the end rules) is taken after the handler has run.
    bool halted = false;
    int32_t resume_line = 0;
    TrackedState pending;
    bool pending_touched = false, pending_free = false;
    double pending_ke = 0.0, pending_mass = 0.0, pending_inertia = 0.0;
    // The lines' unit directions and lengths (from -> to), fixed at creation.
    std::vector<Vec2> line_dir;
    std::vector<double> line_length;
    // Records.
    std::vector<TrackedImpact> impacts;
    std::vector<TrackedCrossing> crossings;
    std::vector<double> envelope_height, envelope_energy;  // NaN: never in that bin
    std::vector<TrackedPoint> path;
};

/// What one step's scan of the contacts found for one tracker (step/trackers.cpp). What was hit
/// is copied at the scan: a handler run later in the step may delete bodies and their pairs.
struct TrackerTouch {
    bool any = false;   // some contact of the body has a positive overlap
    bool kind = false;  // ... and the fields below are the first such contact (in pair order)
                        // of the impacts' kind
    int32_t segment = -1;
    Vec2 normal{0.0, 0.0};  // from what was hit toward the body
    Vec2 point{0.0, 0.0};
    WallId wall;
    BallId ball;
    ClumpId clump;
    uint64_t groups = 0;
};

struct Trackers {
    std::vector<Tracker> list;  // id = index + 1; ended trackers keep their records
    std::size_t live = 0;       // trackers still tracking
    // Body -> index in `list` of its live tracker, -1 when none: by ball handle - 1 and by clump
    // index (identities that survive the balls' re-ordering in memory).
    std::vector<int32_t> by_ball, by_clump;
    std::function<void(const TrackerEvent&)> handler;
    std::vector<TrackerTouch> touch;  // scratch, one per tracker
    int updating = 0;                 // > 0 while the step's sample runs (handlers may be called)
};

}  // namespace talus
