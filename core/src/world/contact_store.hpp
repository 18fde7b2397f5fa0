// SPDX-License-Identifier: MIT
//
// The contact store: every broadphase candidate pair (hot part `pairs`, cold part `cold`, same
// index), the key index, the contact-model rules with their object pools, and the two broadphase
// trees (balls, wall segments) with the lists of bodies re-inserted this step. Not installed.
//
// The store holds data and the pair-level operations that only need data (lookup by key, index
// of a pair, swapping two pairs' state); making and removing pairs also needs the bodies and the
// rules' plugins (step/detection.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "world/broadphase.hpp"
#include "world/types.hpp"

namespace talus {

/// The force loop's scratch (force/scratch.hpp): held here for its lifetime, made and freed by
/// the force loop, which alone knows its type.
struct ForceScratch;
struct ForceScratchDelete {
    void operator()(ForceScratch* s) const;  // force/loop.cpp
};

struct ContactStore {
    ContactStore();

    // --- pairs (broadphase candidates; active pairs carry a model object)
    std::vector<Pair> pairs;
    std::vector<PairCold> cold;                        // same index as `pairs`
    std::vector<PairStored> stored;                    // same index (energy tracing)
    std::unordered_map<uint64_t, uint32_t> key_index;  // ContactKey value -> index
    // The guard's watch of young contacts (GuardWatch), one record per watched contact; freed
    // records are reused, and the list is compacted when most of it is free (compactWatches).
    std::vector<GuardWatch> watches;
    std::vector<uint32_t> free_watches;
    // Bumped whenever a pair is added or removed or an end's slot changes (the threads'
    // incidence lists are rebuilt then; force/scratch.hpp).
    uint64_t pairs_version = 0;

    // --- contact-model rules; [0] is the default rule. Each rule owns the object pool its
    // contacts' model objects are placed in.
    std::vector<std::unique_ptr<Rule>> rules;
    uint32_t rules_version = 1;
    double max_activity = 0.0;  // largest activity distance of any rule [m]

    // --- broadphase
    std::unique_ptr<Broadphase> broadphase;       // balls
    std::unique_ptr<Broadphase> wall_broadphase;  // wall segments
    double margin = 0.0;
    bool broadphase_ready = false;
    std::vector<int32_t> query;  // scratch for the broadphase
    // Bodies re-inserted this step: only their pairs can have stopped overlapping.
    std::vector<uint32_t> moved_balls, moved_segments;
    std::vector<uint8_t> ball_moved, segment_moved;
    std::vector<uint8_t> leaving;     // scratch: ball slot -> left its fat box this step
    std::vector<uint32_t> to_remove;  // scratch for the force loop
    std::unique_ptr<ForceScratch, ForceScratchDelete> force_scratch;  // (force/scratch.hpp)
    // Pairs whose bond broke or was removed (key -> the ends' generations, so that a reused
    // handle is not mistaken for the pair): no bond on touch for them again (api/bonds.cpp).
    // Empty, and never looked at, in a model without bonds.
    std::unordered_map<uint64_t, uint64_t> unbonded;

    // --- the force loop's FdBlock template (sizes, ABI version) and the first-call flags of the
    // contact activate() just made
    FdBlock fd_template{};
    uint32_t activation_flags = 0;

    /// A contact's watch record, or nullptr when the guard does not watch it.
    GuardWatch* watchOf(const PairCold& c) {
        return c.watch == kNoWatch ? nullptr : &watches[c.watch];
    }
    const GuardWatch* watchOf(const PairCold& c) const {
        return c.watch == kNoWatch ? nullptr : &watches[c.watch];
    }
    /// The guard starts watching the contact (a fresh record; the one it has, if any).
    GuardWatch& startWatch(Pair& p, PairCold& c);
    /// The guard stops watching it (its record freed).
    void endWatch(Pair& p, PairCold& c);
    /// The records in a list no larger than what is watched, when at most a quarter is (after a
    /// packing's contacts outlived their watch).
    void compactWatches();
    /// The watch as a save file holds it for every pair (docs/save-format.md): the record, or,
    /// for a contact that outlived its watch (or was never watched), steps past the watch.
    GuardWatch savedWatch(const Pair& p, const PairCold& c) const;
    /// A restored pair's watch: a record when it is active and within its watch.
    void restoreWatch(Pair& p, PairCold& c, const GuardWatch& w);

    /// A pair's cold record (same index) and its rule.
    PairCold& coldOf(const Pair& p) { return cold[pairIndex(p)]; }
    const PairCold& coldOf(const Pair& p) const { return cold[pairIndex(p)]; }
    PairStored& storedOf(const Pair& p) { return stored[pairIndex(p)]; }
    Rule& ruleOf(const Pair& p) const { return *rules[p.rule]; }
    /// The index of a rule (for Pair::rule); throws InputError beyond 65 535 rules.
    uint16_t ruleIndex(const Rule* rule) const;

    Pair* pairByKey(ContactKey key);
    const Pair* pairByKey(ContactKey key) const;
    std::size_t pairIndex(const Pair& p) const {
        return static_cast<std::size_t>(&p - pairs.data());
    }
    /// Exchanges the state of pairs i and j, keeping each pair's identity (its segment, its key):
    /// a wall contact moving from one segment's pair to the next (step/detection.cpp).
    void swapState(std::size_t i, std::size_t j);
};

}  // namespace talus
