// SPDX-License-Identifier: MIT
//
// Phase 4: the force-displacement law (docs/architecture.md, "Force-displacement"). Every pair
// goes through three passes, one file each:
//   1. geometry (pass_geometry.hpp): its narrowphase and, for a contact, its FdBlock;
//   2. the law (pass_law.hpp): the model's batched FDlaw (one contact per call: no virtual
//      call), or FDlaw;
//   3. finish (pass_finish.hpp): forces onto the ends, the time-step notes, the books, the guard.
// This file only sequences them. One thread runs them pair after pair (pair.hpp: runPair),
// adding each contact onto its ends at once; contacts in a model's lanes go by blocks
// (lane_block.hpp). The automatic step, energy tracing and the guard are template switches
// (LoopFeatures), so a fixed-step run without tracing pays nothing for them.
//
// Threads (docs/architecture.md, "Threads") own contiguous ranges of pairs and run all three
// passes on them, with what reaches beyond the pair kept aside: each pair's action on its ends
// goes into its PairAction, and whatever allocates or frees model objects, raises an event or
// touches another pair (activation, a wall pair, a break, the end of a contact, a pair to remove)
// into the thread's list of deferred work, in pair order. Then one thread does the deferred work
// of all threads in pair order, and the balls gather their pairs' actions in pair order
// (threads.cpp: gatherPairActions). Every sum is thus made of the same terms in the same order as
// on one thread, the time-step limits take the lowest pair on a tie, and the result is the same
// bit for bit for any thread count (lua.regress.force_loop_identical).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include "force/force.hpp"
#include "force/lane_block.hpp"
#include "force/pair.hpp"
#include "force/view.hpp"
#include "step/detection.hpp"
#include "step/group_energy.hpp"
#include "step/step.hpp"
#include "step/step_limits.hpp"
#include "talus/errors.hpp"
#include "world/lanes.hpp"

#ifdef TALUS_HAVE_OPENMP
#include <omp.h>
#endif

namespace talus {

ForceView forceView(World& world, const StepContext& step, const FdBlock& fd_template, int nthreads,
                    bool lanes, bool blocks, bool groups) {
    auto& b = world.bodies.balls;
    ForceScratch& scratch = world.contacts.force_scratch;
    return ForceView{world, world.contacts.pairs, world.contacts.cold, world.contacts.stored,
                     world.contacts.rules.data(), b.pos.data(), b.vel.data(), b.radius.data(),
                     b.spin.data(), b.fat.data(), b.force.data(), b.moment.data(),
                     world.bodies.walls.data(), world.bodies.segments.data(),
                     world.contacts.ball_moved.data(), world.contacts.segment_moved.data(),
                     scratch.route.data(), scratch.actions.data(),
                     step.automatic && nthreads > 1 ? scratch.stiffness.data() : nullptr,
                     step.energy && nthreads > 1 ? scratch.energies.data() : nullptr,
                     world.contacts.to_remove, scratch.apart, step.dt, step.window, fd_template,
                     // the dissipation totals before this step, for the energy contract's check
                     // (the same for every contact, so for every thread count)
                     world.books.acc, world.settings.batched_law, lanes, blocks, groups};
}

namespace {

/// The threads' ranges: contiguous, of equal pair counts; then the serial part.
template <class Features>
void runThreads(const ForceView& v, ForceSums& sums, std::size_t npairs, int nthreads) {
#ifdef TALUS_HAVE_OPENMP
    World& world = v.world;
    ForceScratch& scratch = world.contacts.force_scratch;
    ++world.profile.threaded_steps;
    auto& parts = scratch.parts;
    auto& balls = world.bodies.balls;
    const std::size_t nballs = balls.size();
    uint16_t* route = scratch.route.data();
    // Until the routes are whole again (gatherPairActions), a failure must rebuild them.
    const uint64_t routes_version = scratch.incidence_version;
    scratch.incidence_version = UINT64_MAX;
#pragma omp parallel num_threads(nthreads)
    {
        const int t = omp_get_thread_num();
        ForceThreadPart& part = parts[static_cast<std::size_t>(t)];
        const std::size_t lo = threadRangeStart(npairs, nthreads, t);
        const std::size_t hi = threadRangeStart(npairs, nthreads, t + 1);
        // Every ball's sums start from zero (a thread adds onto the balls it owns at once).
        for (std::size_t k = threadRangeStart(nballs, nthreads, t);
             k < threadRangeStart(nballs, nthreads, t + 1); ++k) {
            balls.force[k] = Vec2::Zero();
            balls.moment[k] = 0.0;
            if constexpr (Features::kAuto) balls.k_tran[k] = balls.k_rot[k] = 0.0;
        }
#pragma omp barrier
        // A pair left to the serial part adds onto its balls after the thread's later pairs:
        // from it on, the thread's pairs record what they do to those balls (gatherPairActions).
        const auto defer = [&](std::size_t i) {
            const auto divert = [&](uint32_t k) {
                if (route[k] != part.index) return;
                route[k] = kRouteDiverted;
                part.diverted.emplace_back(k, static_cast<uint32_t>(i));
            };
            const Pair& p = v.pairs[i];
            divert(p.end1);
            if (!p.wall) divert(p.end2);
            part.items.push_back({static_cast<uint32_t>(i), Deferred::Pair});
        };
        std::size_t i = lo;
        try {
            PairEntry e;
            LaneCounts counts;
            if (v.blocks) part.lanes.prepare();
            while (i < hi) {
                if (v.blocks) {
                    std::size_t at = i;
                    try {
                        const std::size_t next = runLaneBlock<Features, Delivery::Parallel>(
                            v, sums, i, hi, part.lanes, &part, part.error, counts, at);
                        if (next != i) {
                            i = next;
                            continue;
                        }
                    } catch (...) {
                        i = at;
                        throw;
                    }
                }
                prefetchModel(v, i, hi);
                if (v.pairs[i].wall) {
                    defer(i);
                    ++i;
                    continue;
                }
                const bool kernel = v.pairs[i].lane != kNoLane;  // (blocks ran above)
                const PairStep step = geometryPass<Features>(v, i, e, kernel ? nullptr : &part.fd);
                if (step == PairStep::Contact) {
                    Pair& p = v.pairs[i];
                    if (kernel) {
                        kernelContact<Features, Delivery::Parallel>(v, sums, i, e, part.fd,
                                                                    part.error, counts, &part);
                    } else {
                        lawPass(v, i, part.fd, part.error, counts.batched);
                        finishContact<Features, Delivery::Parallel>(v, sums, i, e, part.fd, false,
                                                                    &part);
                    }
                    if (v.lanes && p.lane == kNoLane && laneable(v, p))
                        part.lane_entries.push_back(static_cast<uint32_t>(i));
                } else if (step == PairStep::Apart) {
                    finishApart<Features, Delivery::Parallel>(v, i, step, &part);
                } else {  // Touch
                    defer(i);
                }
                ++i;
            }
            part.batched = counts.batched;
            part.lane_steps = counts.steps;
            part.lane_declined = counts.declined;
            part.kernel_steps = counts.kernel;
            part.kernel_declined = counts.kernel_declined;
        } catch (...) {
            part.failure = std::current_exception();
            part.failure_pair = i;
        }
    }
    // ---- the serial part: the threads' deferred work in pair order, up to the first pair that
    // failed (as one thread would have stopped there)
    std::size_t failed = SIZE_MAX;
    const ForceThreadPart* failed_part = nullptr;
    for (const auto& part : parts)
        if (part.failure && part.failure_pair < failed)
            failed = part.failure_pair, failed_part = &part;
    PairEntry e;
    FdBlock& fd = parts[0].fd;
    LaneCounts serial;
    for (auto& part : parts) {
        for (const DeferredItem& item : part.items) {
            const std::size_t i = item.pair;
            if (i >= failed) break;
            switch (item.kind) {
                case Deferred::Pair:
                    // (a vertex hand-over leaves the contact's new holder in slot i: again)
                    for (std::size_t next = i; next == i;)
                        next = runPair<Features, Delivery::Serial>(v, sums, i, npairs, e, fd,
                                                                   scratch.error, serial);
                    break;
                case Deferred::Break:
                    queueBreak(world, i, item.point, item.break_mode,
                               (item.flags & kFdBreakStress) != 0, item.sigma, item.tau);
                    break;
                case Deferred::End:
                    endAndCheck<Features>(v, i);
                    break;
                case Deferred::Remove:
                    v.to_remove.push_back(static_cast<uint32_t>(i));
                    break;
                case Deferred::Contract: {
                    const ContractNote& note = part.contracts[item.flags];
                    checkEnergyContract(world, v.pairs[i], note.strain_old, note.bond_old, note.fd,
                                        note.fn_old, note.fs_old, note.m_old, v.totals_before);
                    break;
                }
            }
        }
        sums.finite_check += part.finite_check;
        serial.batched += part.batched;
        world.profile.lane_steps += part.lane_steps;
        world.profile.lane_declined += part.lane_declined;
        world.profile.kernel_steps += part.kernel_steps;
        world.profile.kernel_declined += part.kernel_declined;
        if constexpr (Features::kAuto) world.stepping.limits.merge(part.limits);
    }
    world.profile.batched_laws += serial.batched;
    world.profile.lane_steps += serial.steps;
    world.profile.lane_declined += serial.declined;
    world.profile.kernel_steps += serial.kernel;
    world.profile.kernel_declined += serial.kernel_declined;
    // The lanes' rows the threads let go, then the contacts they offer (in pair order).
    for (auto& part : parts)
        for (const auto& [table, row] : part.lane_releases) table->release(row);
    for (auto& part : parts)
        for (const uint32_t i : part.lane_entries)
            if (i < failed) offerLane(v, v.pairs[i]);
    if (failed_part) std::rethrow_exception(failed_part->failure);
    gatherPairActions(world, Features::kAuto);
    scratch.incidence_version = routes_version;
    if constexpr (Features::kEnergy)
        for (std::size_t i = 0; i < npairs; ++i)
            if (v.energies[i].what) bookPairEnergy(world.books, sums, v.energies[i]);
#else
    (void)v, (void)sums, (void)npairs, (void)nthreads;
#endif
}

template <class Features>
void forceLoop(World& world, const StepContext& step) {
    auto& b = world.bodies.balls;
    ForceScratch& scratch = world.contacts.force_scratch;
    const std::size_t npairs = world.contacts.pairs.size();
    const int nthreads = forceThreads(world, npairs);
    world.clock.threads = nthreads;
    if (nthreads <= 1) {
        std::fill(b.force.begin(), b.force.end(), Vec2::Zero());
        std::fill(b.moment.begin(), b.moment.end(), 0.0);
    }  // (threads: the gather writes every ball)
    for (auto& w : world.bodies.walls) w.force.setZero(), w.moment = 0.0, w.knest = 0.0;
    if constexpr (Features::kAuto) {
        if (nthreads <= 1) {
            std::fill(b.k_tran.begin(), b.k_tran.end(), 0.0);
            std::fill(b.k_rot.begin(), b.k_rot.end(), 0.0);
        }
        world.stepping.limits = StepLimits{};
        world.stepping.limits_stale = false;
        scratch.apart.clear();
    }
    FdBlock fd_template = world.contacts.fd_template;
    fd_template.tdel = step.dt;
    fd_template.time = world.clock.time;
    fd_template.flags = Features::kEnergy ? kFdEnergyOn : 0u;
    world.contacts.to_remove.clear();
    const bool groups = Features::kEnergy && step.groups;
    if (groups) groupForceLoopStart(world);
    // How each rule's contacts run this step (LaneMode): the model's lane law over blocks if
    // m:lanes asks for it, else the host's kernel of the model's law (kernels.hpp) where it has
    // one, else its law per contact. A rule without them takes its contacts out first (their
    // objects run FDlaw).
    bool lanes = false, blocks = false, leave = false;
    for (const auto& rule : world.contacts.rules) {
        LaneMode mode = LaneMode::None;
        if (rule->factory) {
            if (world.settings.lanes && world.settings.batched_law && rule->factory->lanes)
                mode = LaneMode::Blocks;
            else if (rule->kernel != Kernel::None && world.settings.kernels)
                mode = LaneMode::Kernel;
        }
        leave = leave || (mode != rule->lane_mode && rule->lanes && rule->lanes->used() > 0);
        rule->lane_mode = mode;
        lanes = lanes || mode != LaneMode::None;
        blocks = blocks || mode == LaneMode::Blocks;
    }
    if (leave)
        for (Pair& p : world.contacts.pairs)
            if (p.lane != kNoLane && world.contacts.ruleOf(p).lane_mode == LaneMode::None)
                leaveLane(world.contacts, p);
    if (nthreads > 1) prepareForceScratch(world, nthreads, fd_template);
    const ForceView v = forceView(world, step, fd_template, nthreads, lanes, blocks, groups);
    ForceSums sums;

    if (nthreads <= 1) {
        PairEntry e;
        FdBlock fd = fd_template;
        LaneCounts counts;
        LaneScratch& ls = scratch.lanes;
        if (blocks) ls.prepare();
        std::size_t at = 0;
        if (blocks) {
            for (std::size_t i = 0; i < npairs;) {
                const std::size_t next = runLaneBlock<Features, Delivery::Direct>(
                    v, sums, i, npairs, ls, nullptr, scratch.error, counts, at);
                i = next != i ? next
                              : runPair<Features, Delivery::Direct>(v, sums, i, npairs, e, fd,
                                                                    scratch.error, counts);
            }
        } else {
            for (std::size_t i = 0; i < npairs;)
                i = runPair<Features, Delivery::Direct>(v, sums, i, npairs, e, fd, scratch.error,
                                                        counts);
        }
        world.profile.batched_laws += counts.batched;
        world.profile.lane_steps += counts.steps;
        world.profile.lane_declined += counts.declined;
        world.profile.kernel_steps += counts.kernel;
        world.profile.kernel_declined += counts.kernel_declined;
    } else {
        runThreads<Features>(v, sums, npairs, nthreads);
    }
    if constexpr (Features::kAuto) {
        noteApproaches(world, scratch.apart, world.stepping.limits);
        if (nthreads > 1)
            for (const auto& part : scratch.parts)
                noteApproaches(world, part.apart, world.stepping.limits);
    }

    if (!std::isfinite(sums.finite_check)) findNonFiniteContact(world);
    auto& to_remove = world.contacts.to_remove;
    for (auto it = to_remove.rbegin(); it != to_remove.rend(); ++it) removePair(world, *it);
    clearMovedFlags(world);
    if constexpr (Features::kEnergy) {
        world.books.acc.strain = sums.strain_now;
        world.books.acc.bond = sums.bond_now;
        if (groups) groupForceLoopEnd(world);
        if (world.books.strain_baseline_pending) {
            // Tracing was switched on with loaded contacts: what they hold was put in before the
            // books opened (api/energy.cpp, setEnergyTracing).
            world.books.acc.initial_strain = sums.held_before;
            world.books.strain_baseline_pending = false;
        }
    }
}

}  // namespace

void forceDisplacement(World& world, const StepContext& step) {
    // The guard follows a contact through its first steps (Pair::watched). Switched on over
    // contacts that are older, it leaves them be, as it would have after their first steps.
    if (step.guard && !world.stepping.guard_was_on)
        for (std::size_t i = 0; i < world.contacts.pairs.size(); ++i) {
            Pair& p = world.contacts.pairs[i];
            if (p.active) p.watched = false, world.contacts.cold[i].steps = kGuardWatch + 1;
        }
    world.stepping.guard_was_on = step.guard;
    if (!step.automatic) world.stepping.estimates_stale = true;
    // Dispatch once per step to the loop compiled for exactly what this scene needs.
    if (step.automatic) {
        if (step.energy)
            step.guard ? forceLoop<LoopFeatures<true, true, true>>(world, step)
                       : forceLoop<LoopFeatures<true, true, false>>(world, step);
        else
            step.guard ? forceLoop<LoopFeatures<true, false, true>>(world, step)
                       : forceLoop<LoopFeatures<true, false, false>>(world, step);
    } else {
        if (step.energy)
            step.guard ? forceLoop<LoopFeatures<false, true, true>>(world, step)
                       : forceLoop<LoopFeatures<false, true, false>>(world, step);
        else
            step.guard ? forceLoop<LoopFeatures<false, false, true>>(world, step)
                       : forceLoop<LoopFeatures<false, false, false>>(world, step);
    }
}

void noteApproaches(const World& world, const std::vector<uint32_t>& apart, StepLimits& limits) {
    const auto& b = world.bodies.balls;
    const auto& pairs = world.contacts.pairs;
    const auto& cold = world.contacts.cold;
    for (const uint32_t i : apart) {
        const Pair& p = pairs[i];
        const uint32_t s1 = p.end1;
        if (!p.wall) {
            const uint32_t s2 = p.end2;
            const Vec2 d = b.pos[s2] - b.pos[s1];
            const double dist = d.norm();
            const Vec2 arel = (b.force[s2] + b.fapp[s2]) * b.inv_mass[s2] -
                              (b.force[s1] + b.fapp[s1]) * b.inv_mass[s1];
            noteApproach(world, p, cold[i], dist - (b.radius[s1] + b.radius[s2]),
                         b.vel[s2] - b.vel[s1], arel.norm(),
                         dist > 0.0 ? Vec2(d / dist) : Vec2(0.0, 1.0), limits);
        } else {
            // (the pair was Apart: its ball is in this segment's region)
            ContactGeometry g;
            if (!segmentGeometry(world, p.end2, b.pos[s1], b.radius[s1], g)) continue;
            const WallData& wall = world.bodies.walls[world.bodies.segments[p.end2].wall];
            const Vec2 v2c = wall.vel + spinCross(wall.spin, g.point - wall.center);
            const Vec2 a1 = (b.force[s1] + b.fapp[s1]) * b.inv_mass[s1] + world.settings.gravity;
            noteApproach(world, p, cold[i], -g.overlap, v2c - b.vel[s1], a1.norm(), g.normal,
                         limits);
        }
    }
}

}  // namespace talus
