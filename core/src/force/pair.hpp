// SPDX-License-Identifier: MIT
//
// One pair through the three passes (geometry, law, finish): the same code on one thread, in a
// thread's range of pairs and in the threads' serial part (the Delivery says what reaches beyond
// the pair), for a loop compiled for one kernel's rows or any (the Runner). The rare pairs take
// the serial path: a first touch (activation) and a wall contact handed over at a vertex. Not
// installed.
#pragma once

#include <cstddef>
#include <string>

#include "force/pass_finish.hpp"
#include "force/pass_geometry.hpp"
#include "force/pass_law.hpp"
#include "step/detection.hpp"
#include "world/lanes.hpp"

namespace talus {

/// A contact whose law runs through FDlaw reads its object and the first line of its cold record
/// (the effective masses), which live apart from the pair: ask for both a few pairs ahead of
/// pair i (the first three cache lines of the object: the shipped models' objects are 88 to 184
/// bytes). A contact on a kernel row needs neither.
constexpr std::size_t kPrefetchAhead = 4;
__attribute__((always_inline)) inline void prefetchModel(const ForceView& v, std::size_t i,
                                                         std::size_t end) {
    if (i + kPrefetchAhead >= end) return;
    const Pair& ahead = v.pairs[i + kPrefetchAhead];
    if (!ahead.active || ahead.lane != kNoLane) return;
    const char* obj = reinterpret_cast<const char*>(ahead.model);
    __builtin_prefetch(obj);
    __builtin_prefetch(obj + 64);
    __builtin_prefetch(obj + 128);
    __builtin_prefetch(&v.cold[i + kPrefetchAhead]);
}

/// A contact whose rule runs a kernel this step goes onto a row after an FDlaw, if its model
/// takes it now (docs/plugin-abi.md, "Kernels"): noted here, done after the loop in pair order
/// (the rows' tables do not grow while the loop reads them). Wall contacts stay with FDlaw.
inline void offerRow(const ForceView& v, const Pair& p, std::size_t i, ForceThreadPart& part) {
    if (p.active && p.lane == kNoLane && !p.wall && v.rowsOf(p).kernel != Kernel::None)
        part.row_entries.push_back(static_cast<uint32_t>(i));
}

/// Passes 2 and 3 for a contact on a kernel row: the kernel (runner R), or, where it declines,
/// FDlaw on the object brought up to date (kernelLaw). Pass 1 left the law's inputs in `e`.
template <class Features, Delivery kMode, Runner R>
__attribute__((always_inline)) inline void kernelContact(const ForceView& v, ForceSums& sums,
                                                         std::size_t i, const PairEntry& e,
                                                         ForceThreadPart& part) {
    KernelFd kf;
    if (kernelLaw<Features, R>(v, i, e, kf, part.fd, part, kMode != Delivery::Parallel))
        finishContact<Features, kMode>(v, sums, i, e, kf, kNoTouch, part);
    else
        finishContact<Features, kMode>(v, sums, i, e, part.fd, kNoTouch, part);
}

/// A rare pair, alone (one thread, or the threads' serial part); returns the next pair to
/// process. Pass 1 left its geometry in `e` and its FdBlock in part.fd.
template <class Features, Delivery kMode>
std::size_t processRarePair(const ForceView& v, ForceSums& sums, std::size_t i, PairStep stop,
                            const PairEntry& e, ForceThreadPart& part) {
    World& world = v.world;
    FdBlock& fd = part.fd;
    if (stop == PairStep::HandOver) {
        // The contact crossed a convex vertex and moves, state and all, to the holder's pair,
        // which now sits in slot i: process slot i again (a pair may have been created).
        if (handOverWallContact(world, i)) return i;
        // No pair can take it (no holder, or one with a contact of its own): the contact ends
        // here, and what it still stores is released.
        Pair& p = v.pairs[i];
        const double stored = v.stored[i].total();
        if constexpr (Features::kEnergy) {
            if constexpr (kMode == Delivery::Direct) v.world.books.acc.released += stored;
            if (v.groups) bookReleasedToGroups(world, p, stored);
        }
        endContact(world, p, v.cold[i], Features::kGuard);
        finishApart<Features, kMode>(v, i, PairStep::Elsewhere, part);
        if constexpr (Features::kEnergy && kMode != Delivery::Direct) {
            v.energies[i] = PairEnergy{};
            v.energies[i].what = PairEnergy::kHandOver;
            v.energies[i].released_end = stored;
        }
        return i + 1;
    }
    // A pair touching for the first time: activate it, then its law (FDlaw, and the first
    // call's flags), then its finish.
    Pair& p = v.pairs[i];
    const Touch touch = activate(world, p, v.cold[i], e.g, e.vrel, Features::kGuard);
    if (touch.first) {
        fd.flags |= kFdFirstCall | v.world.contacts.activation_flags;
    } else {
        // A wall pair that took over its chain's contact from a neighbouring segment's pair
        // (activate, adoptWallContact): the forces are that contact's.
        fd.n_force = p.n_force;
        fd.s_force = p.s_force;
        fd.moment = p.moment;
    }
    callLaw(v.pairs[i].model, fd, part.error);
    finishContact<Features, kMode>(v, sums, i, e, fd, touch, part);
    offerRow(v, p, i, part);
    return i + 1;
}

/// A pair a thread leaves to the serial part (a wall pair, a first touch). Its balls' later
/// pairs in this thread's range must not add onto them before it: from it on, they are recorded
/// (diverted) and gathered after the serial part (gatherPairActions).
inline void deferPair(const ForceView& v, std::size_t i, ForceThreadPart& part) {
    const auto divert = [&](uint32_t k) {
        if (v.route[k] != part.index) return;
        v.route[k] = kRouteDiverted;
        part.diverted.emplace_back(k, static_cast<uint32_t>(i));
    };
    const Pair& p = v.pairs[i];
    divert(p.end1);
    if (!p.wall) divert(p.end2);
    part.items.push_back({static_cast<uint32_t>(i), Deferred::Pair});
}

/// One pair, all three passes; returns the next pair to process. In a thread's range
/// (Delivery::Parallel) a wall pair and a first touch are deferred to the serial part; on one
/// thread and in the serial part they are processed here.
template <class Features, Delivery kMode, Runner R>
__attribute__((always_inline)) inline std::size_t runPair(const ForceView& v, ForceSums& sums,
                                                          std::size_t i, std::size_t end,
                                                          ForceThreadPart& part) {
    prefetchModel(v, i, end);
    Pair& p = v.pairs[i];
    if constexpr (kMode == Delivery::Parallel) {
        if (p.wall) {
            deferPair(v, i, part);
            return i + 1;
        }
    }
    // A contact on a kernel row keeps its law's inputs in the entry; any other pair gets its
    // FdBlock from pass 1.
    const bool on_row = p.lane != kNoLane;
    PairEntry& e = part.entry;
    const PairStep step = geometryPass<Features>(v, i, e, on_row ? nullptr : &part.fd);
    if (step == PairStep::Contact) {
        if (on_row) {
            kernelContact<Features, kMode, R>(v, sums, i, e, part);
        } else {
            callLaw(p.model, part.fd, part.error);
            finishContact<Features, kMode>(v, sums, i, e, part.fd, kNoTouch, part);
            offerRow(v, p, i, part);
        }
        return i + 1;
    }
    if (step == PairStep::Apart || step == PairStep::Elsewhere) {
        finishApart<Features, kMode>(v, i, step, part);
        return i + 1;
    }
    if constexpr (kMode == Delivery::Parallel) {
        deferPair(v, i, part);  // a first touch (wall pairs were deferred above)
        return i + 1;
    } else {
        return processRarePair<Features, kMode>(v, sums, i, step, e, part);
    }
}

}  // namespace talus
