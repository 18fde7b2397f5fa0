// SPDX-License-Identifier: MIT
//
// The body store: every body of a model and the handle tables that name them (the "world's
// bodies" of Box2D v3's layout). Balls live in structure-of-arrays form (BallArrays, indexed by
// slot); scripts hold handles (index + generation) that the tables map to slots, so that slots
// can be compacted and re-ordered without invalidating a script's ids. Walls are chains of
// segments over a shared vertex list. Not installed.
//
// The store holds data and the operations that only need data (lookup, describe); everything
// that also needs the contacts or the settings (create/delete a body, mass update) is in
// api/balls.cpp, which keeps both stores consistent.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "world/types.hpp"

namespace talus {

struct BodyStore {
    // --- balls
    BallArrays balls;
    std::vector<uint32_t> slot_of;     // handle index - 1 -> slot (or kDeadSlot)
    std::vector<uint32_t> generation;  // handle index - 1 -> generation
    std::vector<uint32_t> free_handles;

    // --- clumps (docs/physics/clumps.md): indexed by handle - 1 (never re-used; a
    // deleted clump stays as a dead entry). Their pebbles occupy ball slots
    // (BallArrays::clump names the clump of each slot).
    std::vector<ClumpData> clumps;
    std::size_t live_clumps = 0;
    std::size_t pebble_count = 0;  // ball slots that are pebbles
    bool hasClumps() const { return pebble_count > 0; }
    /// Index of a live clump; throws InputError naming the id for an unknown or stale id.
    uint32_t clumpIndex(ClumpId id) const;
    ClumpId clumpId(uint32_t index) const { return ClumpId{index + 1, clumps[index].generation}; }
    /// Slot of pebble k of clump c.
    uint32_t pebbleSlot(const ClumpData& c, std::size_t k) const {
        return slot_of[c.pebbles[k] - 1];
    }

    // --- walls: chains of segments; a segment joins two entries of `vertices`
    std::vector<WallData> walls;
    std::vector<Segment> segments;
    std::vector<Vec2> vertices;

    // --- what the bodies share
    std::vector<std::string> group_names;  // bit index -> name; at most 64 (Model::groupIndex)
    std::vector<ClumpTemplate> clump_templates;
    std::size_t fixed_balls = 0;  // balls with any fixity bit (they need the general loop)
    int servos_on = 0;            // walls with a servo switched on (wall_servo.cpp)

    /// Slot of a live ball; throws InputError naming the id for an unknown or stale id.
    uint32_t slotOf(BallId id) const;
    bool isAlive(BallId id) const;
    /// The current id of the ball in `slot`.
    BallId ballId(uint32_t slot) const {
        const uint32_t h = balls.handle[slot];
        return BallId{h, generation[h - 1]};
    }
    /// "ball N at (x, y)", for messages.
    std::string describeBall(uint32_t slot) const;

    /// Wall data of a live wall; throws InputError for an unknown id.
    const WallData& wallOf(WallId id) const;
    WallData& wallOf(WallId id);
};

}  // namespace talus
