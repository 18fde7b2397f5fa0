// SPDX-License-Identifier: MIT
//
// The force loop's scratch (force_displacement.cpp; docs/architecture.md, "Force loop" and
// "Threads"): what pass 1 (geometry) of a pair hands to its law and its finish, and, when threads
// run the loop, what each pair does to its ends (PairAction), the balls' pairs in pair order
// (the incidence the gather reads) and each thread's deferred work. Not installed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include "model_internal.hpp"
#include "narrowphase.hpp"
#include "talus/contact_model.hpp"

namespace talus {

/// What pass 1 found for a pair.
enum class PairStep : uint8_t {
    Apart,      // not touching (nor within the model's activity distance)
    Elsewhere,  // a wall pair whose ball is in a neighbouring segment's region, no contact
    Contact,    // an active contact: its law runs
    Touch,      // touching for the first time: to activate (rare; serial)
    HandOver,   // an active wall contact whose point crossed a vertex (rare; serial)
};

/// Pass 1's result for one pair.
struct PairEntry {
    ContactGeometry g;
    Vec2 x2{0.0, 0.0};    // centre of end 2: the ball's, or the wall's (moment arms)
    Vec2 vrel{0.0, 0.0};  // contact-point velocity of end 2 relative to end 1 (activation)
};

/// What one pair did to its balls in this step, kept per pair when threads run the loop: every
/// ball then adds its pairs' actions in pair order (Model::gatherPairActions), the same
/// additions in the same order as one thread adding each contact onto its ends at once.
/// add[e] is what end e (0: end 1, 1: end 2) gets: force x, force y, moment. End 1's are the
/// negated values one thread subtracts (x - y == x + (-y) exactly in IEEE 754), and a pair that
/// did nothing holds -0.0, which leaves every sum as it was (x + (-0.0) == x, -0.0 included): so
/// the gather adds without a branch.
struct PairAction {
    double add[2][3];
};

/// The same for the automatic step's stiffness sums: translational, rotational per end.
struct PairStiffness {
    double add[2][2];
};

/// Work a thread leaves for the serial part of the step, in pair order: what allocates or frees
/// model objects, grows or reorders the pairs, raises events or reads another pair.
enum class Deferred : uint8_t {
    Pair,      // a wall pair or a pair touching for the first time: processed whole, serially
    Break,     // a bond broke (Model::queueBreak)
    End,       // a contact ended (Model::endContact), then its pair's broadphase check
    Remove,    // a pair whose ends' fat boxes no longer overlap: to remove after the loop
    Contract,  // a law's energies to check against the ABI (rare; ForceThreadPart::contracts)
};

/// What one pair adds to the energy books in a step (tracing on), kept per pair when threads
/// run the loop and added in pair order afterwards: the additions one thread makes at once.
struct PairEnergy {
    enum : uint8_t {
        kContact = 1,    // slip, dashpot, plastic and the law's released energy
        kPlacement = 2,  // born overlapping: placement
        kHeld = 4,       // the baseline of contacts older than the tracing: held
        kEnds = 8,       // the contact ended: its stored energy released (released_end)
        kStored = 16,    // it goes on: strain and bond stored
        kHandOver = 32,  // a wall contact nobody took over: released_end
    };
    double slip = 0.0, dashpot = 0.0, plastic = 0.0, released = 0.0, released_end = 0.0;
    double placement = 0.0, held = 0.0, strain = 0.0, bond = 0.0;
    uint8_t what = 0;  // the flags above; 0: nothing this step
};

/// A law's output kept for the energy contract's check (Deferred::Contract).
struct ContractNote {
    FdBlock fd;
    double fn_old, fs_old, m_old, strain_old, bond_old;
};

struct DeferredItem {
    uint32_t pair = 0;
    Deferred kind = Deferred::Pair;
    int32_t break_mode = 0;
    uint32_t flags = 0;  // the FdBlock's, for a break
    Vec2 point{0.0, 0.0};
    double sigma = 0.0, tau = 0.0;
};

/// One thread's share of a threaded force loop. Each on cache lines of its own: the threads
/// write their FdBlock and counters at every contact, and a line shared by two of them would
/// move between the cores at every write (false sharing; two lines, for the adjacent-line
/// prefetch).
struct alignas(128) Model::ForceThreadPart {
    FdBlock fd;                           // the thread's FdBlock (a copy of the step's template)
    std::vector<DeferredItem> items;      // in pair order
    std::vector<uint32_t> apart;          // automatic step: its pairs apart, for the approach notes
    std::vector<ContractNote> contracts;  // energy tracing: laws to check (Deferred::Contract)
    StepLimits limits;                    // automatic step: from its contacts
    double finite_check = 0.0;            // sum of the laws' outputs (non-finite if one was)
    int64_t batched = 0;                  // laws run through a batched FDlaw
    std::string error;                    // an exception's text caught at the plugin boundary
    std::exception_ptr failure;           // what stopped the thread ...
    std::size_t failure_pair = SIZE_MAX;  // ... at this pair
};

struct ForceScratch {
    FdBlock fd{};                               // one thread's FdBlock
    std::string error;                          // one thread's caught exception text
    std::vector<uint32_t> apart;                // one thread: pairs apart (automatic step)
    std::vector<Model::ForceThreadPart> parts;  // threads: one per thread
    std::vector<PairAction> actions;            // threads: per pair
    std::vector<PairStiffness> stiffness;       // threads, automatic step: per pair
    std::vector<PairEnergy> energies;           // threads, energy tracing: per pair
    // Threads: ball -> its pairs in pair order, as (pair index << 1) | (ball is end 2), CSR.
    std::vector<uint32_t> incidence_start, incidence;
    uint64_t incidence_version = UINT64_MAX;  // ContactStore::pairs_version it was built for
};

}  // namespace talus
