// SPDX-License-Identifier: MIT
// Stable handles for bodies: a 1-based index into a handle table plus a generation, so that a
// handle kept after its body was deleted is recognised as stale (zero means "none").
#pragma once

#include <cstdint>
#include <functional>

namespace talus {

struct BallId {
    uint32_t index = 0;  ///< 1-based; 0 = none
    uint32_t generation = 0;
    bool valid() const { return index != 0; }
    bool operator==(const BallId& o) const {
        return index == o.index && generation == o.generation;
    }
    bool operator!=(const BallId& o) const { return !(*this == o); }
};

struct WallId {
    uint32_t index = 0;  ///< 1-based; 0 = none
    uint32_t generation = 0;
    bool valid() const { return index != 0; }
    bool operator==(const WallId& o) const {
        return index == o.index && generation == o.generation;
    }
};

struct ClumpId {
    uint32_t index = 0;  ///< 1-based; 0 = none
    uint32_t generation = 0;
    bool valid() const { return index != 0; }
    bool operator==(const ClumpId& o) const {
        return index == o.index && generation == o.generation;
    }
    bool operator!=(const ClumpId& o) const { return !(*this == o); }
};

/// A contact is named by its ordered ends: end 1 is a ball (the lower id of two balls), end 2 a
/// ball or a wall segment. The key stays valid while the contact exists.
struct ContactKey {
    uint64_t value = 0;
    bool operator==(const ContactKey& o) const { return value == o.value; }
};

}  // namespace talus
