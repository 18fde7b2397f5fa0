// SPDX-License-Identifier: MIT
//
// Barriers (talus/model_types.hpp, BarrierDef; step/barriers.cpp): segments with an energy
// capacity, checked at every step while one exists. Not installed.
#pragma once

#include <cstdint>
#include <unordered_set>
#include <vector>

#include "talus/model_types.hpp"

namespace talus {

/// A body's key in a barrier's record: a ball by handle and generation, a clump by index and
/// generation (the high bit set).
inline uint64_t barrierBallKey(uint32_t handle, uint32_t generation) {
    return (uint64_t(generation) << 32) | handle;
}
inline uint64_t barrierClumpKey(uint32_t index, uint32_t generation) {
    return (uint64_t(1) << 63) | (uint64_t(generation) << 32) | index;
}

struct Barrier {
    BarrierInfo info;
    Vec2 dir{0.0, 0.0};  // unit vector from -> to
    double length = 0.0;
    std::unordered_set<uint64_t> caught;  // body keys (step/barriers.cpp) it has caught
};

/// A body a barrier acted on in this step, as it was before: the trackers' sample of the step
/// takes this state, so that it sees the crossing the barrier saw (step/trackers.cpp).
struct BarrierActed {
    uint64_t key = 0;
    Vec2 vel{0.0, 0.0};
    double spin = 0.0;
    uint8_t fixity = 0;
};

/// A body's state at the start of the step (before the law of motion), by ball slot or clump.
struct BodyStart {
    uint32_t handle = 0;  // the ball's handle (0: a pebble or no ball); a clump: its generation
    Vec2 pos{0.0, 0.0}, vel{0.0, 0.0};
    double spin = 0.0;
    bool pushed = false;  // a contact force or moment acted on it (the last force loop's)
};

struct Barriers {
    std::vector<Barrier> list;  // id = index + 1
    std::vector<BodyStart> ball_start, clump_start;
    double start_time = 0.0;          // the clock at the start of the step
    std::vector<BarrierActed> acted;  // this step's, until the trackers' sample
};

}  // namespace talus
