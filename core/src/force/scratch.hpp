// SPDX-License-Identifier: MIT
//
// The force loop's scratch (force/loop.cpp; docs/architecture.md, "Force loop" and
// "Threads"): what pass 1 (geometry) of a pair hands to its law and its finish, each thread's
// part (one thread alone has one), the rules' kernel rows, and, when threads run the loop, which
// thread adds onto which ball (the routes), what a pair does to the ends it cannot add onto
// (PairAction) and the balls' pairs in pair order (the incidence the gather reads). The world
// holds it (ContactStore::force_scratch) without knowing its type. Not installed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <utility>
#include <vector>

#include "step/narrowphase.hpp"
#include "talus/contact_model.hpp"
#include "world/world.hpp"

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
    // The law's kinematic inputs (FdBlock's names): rates at the half step.
    double u_dot_n = 0.0, u_dot_s = 0.0, t_dot_rel = 0.0;
};
static_assert(sizeof(PairEntry) == 112,
              "PairEntry is 112 bytes: pass 1 hands it to passes 2 and 3, per pair");

/// What one pair did to a ball it may not add onto at once, kept per pair when threads run the
/// loop (a ball whose pairs two threads share, or one a deferred pair diverted): such a ball then
/// adds its pairs' actions in pair order (gatherPairActions), the same additions in the same
/// order as one thread adding each contact onto its ends at once.
/// add[e] is what end e (0: end 1, 1: end 2) gets: force x, force y, moment. End 1's are the
/// negated values one thread subtracts (x - y == x + (-y) exactly in IEEE 754), and a pair that
/// did nothing holds -0.0, which leaves every sum as it was (x + (-0.0) == x, -0.0 included): so
/// the gather adds without a branch.
struct PairAction {
    double add[2][3];
};
static_assert(sizeof(PairAction) == 48,
              "PairAction is 48 bytes: written per pair and read by the gather when threads run");

/// A ball's route with threads (ForceScratch::route): the thread that owns all of its pairs and
/// adds them onto it at once, in pair order as one thread does; or one of these.
constexpr uint16_t kRouteShared = 0xFFFF;    // its pairs span two threads' ranges: gathered
constexpr uint16_t kRouteDiverted = 0xFFFE;  // its thread deferred one of its pairs this step
constexpr int kMaxRoutedThreads = 0xFFFD;

/// The same for the automatic step's stiffness sums: translational, rotational per end.
struct PairStiffness {
    double add[2][2];
};
static_assert(sizeof(PairStiffness) == 32,
              "PairStiffness is 32 bytes: written per pair with threads and the automatic step");

/// Work a thread leaves for the serial part of the step, in pair order: what allocates or frees
/// model objects, grows or reorders the pairs, raises events or reads another pair.
enum class Deferred : uint8_t {
    Pair,      // a wall pair or a pair touching for the first time: processed whole, serially
    Break,     // a bond broke (queueBreak)
    End,       // a contact ended (endContact), then its pair's broadphase check
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
static_assert(sizeof(PairEnergy) == 80,
              "PairEnergy is 80 bytes: written per pair with threads and energy tracing");

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

/// What one thread counts of the laws it ran (Profile).
struct LawCounts {
    int64_t kernel = 0;           // contacts stepped by the host's kernels
    int64_t kernel_declined = 0;  // ... of which the kernel declined (FDlaw ran instead)
};

/// One thread's part of the force loop (one thread alone has one too): its FdBlock and pass 1's
/// result, what it leaves for after its range, and its sums. Each on cache lines of its own: the
/// threads write their FdBlock and counters at every contact, and a line shared by two of them
/// would move between the cores at every write (false sharing; two lines, for the
/// adjacent-line prefetch).
struct alignas(128) ForceThreadPart {
    uint16_t index = 0;  // the thread's number (its route)
    FdBlock fd;          // the thread's FdBlock (a copy of the step's template)
    PairEntry entry;     // pass 1's result for the pair at hand
    std::string error;   // an exception's text caught at the plugin boundary
    LawCounts counts;
    // Contacts to put into their rule's kernel rows after the loop (in pair order: the rows'
    // tables do not grow while the loop reads them), and rows to free (threads).
    std::vector<uint32_t> row_entries;
    std::vector<std::pair<LaneTable*, uint32_t>> row_releases;
    std::vector<DeferredItem> items;  // threads: the serial part's work, in pair order
    // Threads: its balls diverted this step: (ball, the first pair it did not add), pair order.
    std::vector<std::pair<uint32_t, uint32_t>> diverted;
    std::vector<uint32_t> watch_ends;     // guard: contacts that outlived their watch (freed after)
    std::vector<uint32_t> apart;          // automatic step: its pairs apart, for the approach notes
    std::vector<ContractNote> contracts;  // energy tracing: laws to check (Deferred::Contract)
    StepLimits limits;                    // automatic step: from its contacts
    double finite_check = 0.0;            // sum of the laws' outputs (non-finite if one was)
    std::exception_ptr failure;           // threads: what stopped the thread ...
    std::size_t failure_pair = SIZE_MAX;  // ... at this pair
};

/// A rule's kernel rows as the loop reads them this step: where they start and the kernel that
/// runs them (Kernel::None: the rule's contacts run FDlaw). The rows' tables do not grow during
/// the loop (ForceThreadPart::row_entries), so `base` stays valid through it.
struct RuleRows {
    double* base = nullptr;
    uint32_t size = 0;  // doubles per row
    Kernel kernel = Kernel::None;
};

struct ForceScratch {
    std::vector<ForceThreadPart> parts;    // one per thread (one alone: parts[0])
    std::vector<RuleRows> rows;            // per rule (Pair::rule), this step
    std::vector<PairAction> actions;       // threads: per pair (the ends not routed)
    std::vector<PairStiffness> stiffness;  // threads, automatic step: per pair
    std::vector<PairEnergy> energies;      // threads, energy tracing: per pair
    // Threads: ball -> its pairs in pair order, as (pair index << 1) | (ball is end 2), CSR.
    std::vector<uint32_t> incidence_start, incidence;
    // Threads: per ball, the thread that adds onto it (or kRouteShared), and the shared balls.
    std::vector<uint16_t> route;
    std::vector<uint32_t> shared;
    // ContactStore::pairs_version and thread count the incidence and routes were built for
    // (UINT64_MAX while a threaded loop runs: one that fails leaves balls diverted).
    uint64_t incidence_version = UINT64_MAX;
    int route_threads = 0;
};

/// The force loop's scratch of a world, made at its first use (force/loop.cpp).
ForceScratch& forceScratch(World& world);

}  // namespace talus
