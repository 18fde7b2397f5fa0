// SPDX-License-Identifier: MIT
//
// One pair through the three passes (geometry, law, finish), on one thread or in the threads'
// serial part, and the rare pairs that take the serial path: a first touch (activation) and a
// wall contact handed over at a vertex. Not installed.
#pragma once

#include <cstddef>
#include <string>

#include "force/kernels.hpp"
#include "force/pass_finish.hpp"
#include "force/pass_geometry.hpp"
#include "force/pass_law.hpp"
#include "step/detection.hpp"
#include "world/lanes.hpp"

namespace talus {

/// A contact whose law runs through FDlaw reads its object and the first line of its cold record
/// (the effective masses), which live apart from the pair: ask for both a few pairs ahead of
/// pair i (the first three cache lines of the object: the shipped models' objects are 88 to 184
/// bytes). A contact in lanes needs neither.
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

/// A contact whose rule runs in lanes this step (a kernel, or lane blocks) goes into them after an
/// FDlaw, if the model's lane law takes it now (docs/plugin-abi.md, "Lanes").
inline bool laneable(const ForceView& v, const Pair& p) {
    return !p.wall && v.rule(p).lane_mode != LaneMode::None;
}
inline void offerLane(const ForceView& v, Pair& p) {
    if (v.lanes && p.active && p.lane == kNoLane && laneable(v, p)) enterLane(v.world.contacts, p);
}

/// Passes 2 and 3 for a contact in its rule's lanes whose law the host runs (kernels.hpp): the
/// kernel on the contact's row, or, where it declines, the object brought up to date, FDlaw, and
/// back into its row if the model takes it. Pass 1 left the law's inputs in `e`.
template <class Features, Delivery kMode>
__attribute__((always_inline)) inline void kernelContact(const ForceView& v, ForceSums& sums,
                                                         std::size_t i, const PairEntry& e,
                                                         FdBlock& fd, std::string& error,
                                                         LaneCounts& counts,
                                                         ForceThreadPart* part) {
    Pair& p = v.pairs[i];
    const Rule& rule = v.rule(p);
    LaneTable& table = *rule.lanes;
    double* row = table.row(p.lane);
    KernelFd kf;
    kf.flags = v.fd_template.flags;
    kf.tdel = v.dt;
    kf.time = v.fd_template.time;
    kf.u_n = e.g.overlap;
    kf.u_dot_n = e.u_dot_n;
    kf.u_dot_s = e.u_dot_s;
    kf.t_dot_rel = e.t_dot_rel;
    kf.du_n = kf.u_dot_n * v.dt;
    kf.du_s = kf.u_dot_s * v.dt;
    kf.dtheta = kf.t_dot_rel * v.dt;
    kf.n_force = p.n_force;
    kf.s_force = p.s_force;
    kf.moment = p.moment;
    if constexpr (Features::kEnergy)
        for (double& en : kf.energy) en = 0.0;
    ++counts.kernel;
    if (runKernel(rule.kernel, row, &v.cold[i], kf)) {
        finishContact<Features, kMode>(v, sums, i, e, kf, false, part);
        return;
    }
    ++counts.kernel_declined;
    ContactModel* model = v.pairs[i].model;
    table.law().unpack(model, row);
    fd = v.fd_template;
    fillFd<Features>(v, i, e.g.overlap, e.u_dot_n, e.u_dot_s, e.t_dot_rel, fd);
    lawPass(v, i, fd, error, counts.batched);
    if (table.law().pack(model, row) == 0) {
        if constexpr (kMode == Delivery::Parallel)
            part->lane_releases.emplace_back(&table, p.lane);
        else
            table.release(p.lane);
        p.lane = kNoLane;
    }
    finishContact<Features, kMode>(v, sums, i, e, fd, false, part);
}

/// A rare pair, alone (never in a thread's range); returns the next pair to process. Pass 1
/// left its geometry in `e` and its FdBlock in `fd`.
template <class Features, Delivery kMode>
std::size_t processRarePair(const ForceView& v, ForceSums& sums, std::size_t i, PairStep stop,
                            PairEntry& e, FdBlock& fd, std::string& error) {
    World& world = v.world;
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
        finishApart<Features, kMode>(v, i, PairStep::Elsewhere, nullptr);
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
    const bool first = activate(world, p, v.cold[i], e.g, e.vrel);
    if (first) {
        fd.flags |= kFdFirstCall | v.world.contacts.activation_flags;
    } else {
        // A wall pair that took over its chain's contact from a neighbouring segment's pair
        // (activate, adoptWallContact): the forces are that contact's.
        fd.n_force = p.n_force;
        fd.s_force = p.s_force;
        fd.moment = p.moment;
    }
    callLaw(v.pairs[i].model, fd, error);
    finishContact<Features, kMode>(v, sums, i, e, fd, first, nullptr);
    offerLane(v, p);
    return i + 1;
}

/// One pair, all three passes, on one thread (Direct) or in the threads' serial part; returns
/// the next pair to process.
template <class Features, Delivery kMode>
__attribute__((always_inline)) inline std::size_t runPair(const ForceView& v, ForceSums& sums,
                                                          std::size_t i, std::size_t end,
                                                          PairEntry& e, FdBlock& fd,
                                                          std::string& error, LaneCounts& counts) {
    prefetchModel(v, i, end);
    // A contact in lanes here is a kernel's (lane blocks take theirs before this): its law's
    // inputs stay in `e`.
    const bool kernel = v.pairs[i].lane != kNoLane;
    const PairStep step = geometryPass<Features>(v, i, e, kernel ? nullptr : &fd);
    if (step == PairStep::Contact) {
        Pair& p = v.pairs[i];
        if (kernel) {
            kernelContact<Features, kMode>(v, sums, i, e, fd, error, counts, nullptr);
        } else {
            lawPass(v, i, fd, error, counts.batched);
            finishContact<Features, kMode>(v, sums, i, e, fd, false, nullptr);
            offerLane(v, p);
        }
        return i + 1;
    }
    if (step == PairStep::Apart || step == PairStep::Elsewhere) {
        finishApart<Features, kMode>(v, i, step, nullptr);
        return i + 1;
    }
    return processRarePair<Features, kMode>(v, sums, i, step, e, fd, error);
}

}  // namespace talus
