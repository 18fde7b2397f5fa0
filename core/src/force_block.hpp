// SPDX-License-Identifier: MIT
//
// The force loop's blocks (force_displacement.cpp; docs/architecture.md, "Force loop"): what
// pass 1 (geometry) and pass 2 (the laws) of up to kBlock consecutive pairs hand to pass 3
// (forces onto the ends and the books, in pair order), and the scratch the loop keeps between
// steps: one block for a single thread, a ring of them for the threads' pipeline. Not installed.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "narrowphase.hpp"
#include "talus/contact_model.hpp"

namespace talus {

/// Pairs per block: a block's FdBlocks (about 13 kB) stay in the L1 cache between its passes.
constexpr std::size_t kBlock = 64;

/// What pass 1 found for a pair.
enum class PairStep : uint8_t {
    Apart,      // not touching (nor within the model's activity distance)
    Elsewhere,  // a wall pair whose ball is in a neighbouring segment's region, no contact
    Contact,    // an active contact: its law runs; as a block's stop: none (full, or the end)
    Touch,      // touching for the first time: to activate (rare, alone)
    HandOver,   // an active wall contact whose point crossed a vertex (rare, alone)
    Wall,       // as a block's stop only: a wall pair, left to the threads' consumer
};

/// Pass 1's result for one pair of a block.
struct BlockEntry {
    ContactGeometry g;
    Vec2 x2{0.0, 0.0};    // centre of end 2: the ball's, or the wall's (moment arms)
    Vec2 vrel{0.0, 0.0};  // contact-point velocity of end 2 relative to end 1 (activation)
    uint32_t pair = 0;
    uint32_t block = 0;  // index of the contact's FdBlock
    PairStep step = PairStep::Apart;
};

struct ForceBlock {
    BlockEntry entries[kBlock];
    FdBlock fd[kBlock];
    ContactModel* models[kBlock];
    BatchFdLawFn laws[kBlock];
    std::size_t n = 0;          // entries produced
    std::size_t ncontacts = 0;  // FdBlocks (contacts) among them
    std::size_t next = 0;       // the pair after the last entry: the stop's pair, if any
    PairStep stop = PairStep::Contact;
    int64_t batched = 0;  // laws run through a batched FDlaw (the profile's count)
    std::string error;    // an exception's text caught at the plugin boundary
};

/// A counter on a cache line of its own: the threads' pipeline polls these, and two of them
/// on one line would make every poll of one a miss for the writer of the other.
struct alignas(64) PaddedCounter {
    std::atomic<std::size_t> value{0};
};

struct ForceScratch {
    std::vector<std::unique_ptr<ForceBlock>> ring;  // [0] serves the single-thread loop
    std::unique_ptr<ForceBlock> remainder;          // the consumer's, for a block's rest
    std::vector<PaddedCounter> ready;               // ring slot -> block + 1 when produced
    std::vector<uint8_t> wall;  // pair -> wall pair, read by the producers (not the pairs)
};

}  // namespace talus
