// SPDX-License-Identifier: MIT
//
// Phase 4: the force-displacement law (docs/architecture.md, "Force-displacement"). Every pair
// goes through three passes, one file each:
//   1. geometry (pass_geometry.hpp): its narrowphase and, for a contact, its law's inputs;
//   2. the law (pass_law.hpp): the host's kernel of the model's law on the contact's row, or the
//      model's FDlaw (the runner table, kernels.hpp);
//   3. finish (pass_finish.hpp): forces onto the ends, the time-step notes, the books, the guard.
// This file only sequences them: one pair at a time through runPair (pair.hpp), on one thread or
// on several. The automatic step, energy tracing and the guard are template switches
// (LoopFeatures), so a fixed-step run without tracing pays nothing for them; the loop is compiled
// for the kernel the scene's rules run (Runner), so that the law of a pack of one model needs no
// switch per contact.
//
// Threads (docs/architecture.md, "Threads") own contiguous ranges of pairs and run the same
// runPair on them, with what reaches beyond the pair kept aside: a pair's action on a ball the
// thread does not own goes into its PairAction, and whatever allocates or frees model objects,
// raises an event or touches another pair (activation, a wall pair, a break, the end of a
// contact, a pair to remove) into the thread's list of deferred work, in pair order. Then one
// thread does the deferred work of all threads in pair order, and the balls gather their pairs'
// actions in pair order (threads.cpp: gatherPairActions). Every sum is thus made of the same
// terms in the same order as on one thread, the time-step limits take the lowest pair on a tie,
// and the result is the same bit for bit for any thread count
// (lua.regress.force_loop_identical).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "force/force.hpp"
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

void ForceScratchDelete::operator()(ForceScratch* s) const { delete s; }

ForceScratch& forceScratch(World& world) {
    auto& held = world.contacts.force_scratch;
    if (!held) held.reset(new ForceScratch);
    return *held;
}

ForceView forceView(World& world, const StepContext& step, const FdBlock& fd_template, int nthreads,
                    bool groups) {
    auto& b = world.bodies.balls;
    ForceScratch& scratch = forceScratch(world);
    return ForceView{world, world.contacts.pairs, world.contacts.cold, world.contacts.stored,
                     world.contacts.rules.data(), scratch.rows.data(), b.pos.data(), b.vel.data(),
                     b.radius.data(), b.spin.data(), b.fat.data(), b.force.data(), b.moment.data(),
                     world.bodies.walls.data(), world.bodies.segments.data(),
                     world.contacts.ball_moved.data(), world.contacts.segment_moved.data(),
                     scratch.route.data(), scratch.actions.data(),
                     step.automatic && nthreads > 1 ? scratch.stiffness.data() : nullptr,
                     step.energy && nthreads > 1 ? scratch.energies.data() : nullptr,
                     world.contacts.to_remove, step.dt, step.window, fd_template,
                     // the dissipation totals before this step, for the energy contract's check
                     // (the same for every contact, so for every thread count)
                     world.books.acc, groups};
}

/// Each rule's kernel rows this step: its kernel where the kernels are on, else none, and a rule
/// without them takes its contacts off their rows (their objects run FDlaw). Returns the runner
/// the loop is compiled for: the one kernel that every rule with contacts on rows runs, or Any.
/// (Contacts offered to the rows in this step enter them after its loop.)
Runner prepareRuleRows(World& world) {
    ForceScratch& scratch = forceScratch(world);
    auto& rules = world.contacts.rules;
    scratch.rows.assign(rules.size(), RuleRows{});
    bool leave = false;
    Kernel only = Kernel::None;
    bool mixed = false;
    for (std::size_t r = 0; r < rules.size(); ++r) {
        Rule& rule = *rules[r];
        const Kernel k = world.settings.kernels ? rule.kernel : Kernel::None;
        leave = leave || (k == Kernel::None && rule.lanes && rule.lanes->used() > 0);
        if (k == Kernel::None) continue;
        if (!rule.lanes) rule.lanes = std::make_unique<LaneTable>(*rule.factory->lanes);
        scratch.rows[r] =
            RuleRows{rule.lanes->state(), static_cast<uint32_t>(rule.lanes->law().state_size), k};
        if (rule.lanes->used() == 0) continue;
        mixed = mixed || (only != Kernel::None && only != k);
        only = k;
    }
    if (leave)
        for (Pair& p : world.contacts.pairs)
            if (p.lane != kNoLane && scratch.rows[p.rule].kernel == Kernel::None)
                leaveLane(world.contacts, p);
    if (mixed) return Runner::Any;
    if (only == Kernel::Linear) return Runner::Linear;
    if (only == Kernel::ContactBond) return Runner::ContactBond;
    return Runner::Any;
}

namespace {

/// A part's state at the start of a step.
void resetPart(ForceThreadPart& part, uint16_t index, const FdBlock& tmpl) {
    part.index = index;
    part.fd = tmpl;
    part.counts = LawCounts{};
    part.row_entries.clear();
    part.row_releases.clear();
    part.items.clear();
    part.diverted.clear();
    part.watch_ends.clear();
    part.apart.clear();
    part.contracts.clear();
    part.limits = StepLimits{};
    part.finite_check = 0.0;
    part.failure = nullptr;
    part.failure_pair = SIZE_MAX;
}

/// After the loop: the guard's watches that ended in it, freed; the list compacted when most of
/// it is free.
void settleWatches(World& world, const ForceThreadPart* parts, std::size_t count) {
    ContactStore& cs = world.contacts;
    for (std::size_t t = 0; t < count; ++t)
        for (const uint32_t i : parts[t].watch_ends)
            if (!cs.pairs[i].watched) cs.endWatch(cs.pairs[i], cs.cold[i]);
    cs.compactWatches();
}

/// After the loop, in pair order: the rows the threads let go, then the contacts offered to
/// their rule's rows, up to the first pair that failed.
void settleRows(World& world, ForceThreadPart* parts, std::size_t count, std::size_t failed) {
    for (std::size_t t = 0; t < count; ++t)
        for (const auto& [table, row] : parts[t].row_releases) table->release(row);
    // Each rule's table grows once for the contacts entering (many, at a packing's first step).
    std::vector<std::size_t> entering(world.contacts.rules.size(), 0);
    for (std::size_t t = 0; t < count; ++t)
        for (const uint32_t i : parts[t].row_entries) {
            if (i >= failed) break;
            ++entering[world.contacts.pairs[i].rule];
        }
    for (std::size_t r = 0; r < entering.size(); ++r) {
        Rule& rule = *world.contacts.rules[r];
        if (entering[r] == 0 || !rule.factory || !rule.factory->lanes) continue;
        if (!rule.lanes) rule.lanes = std::make_unique<LaneTable>(*rule.factory->lanes);
        rule.lanes->reserve(entering[r]);
    }
    for (std::size_t t = 0; t < count; ++t)
        for (const uint32_t i : parts[t].row_entries) {
            if (i >= failed) break;
            Pair& p = world.contacts.pairs[i];
            if (p.active && p.lane == kNoLane) enterLane(world.contacts, p);
        }
}

/// The parts' counts and sums after the loop.
void mergeParts(World& world, const ForceThreadPart* parts, std::size_t count, bool automatic,
                double& finite_check) {
    for (std::size_t t = 0; t < count; ++t) {
        const ForceThreadPart& part = parts[t];
        finite_check += part.finite_check;
        world.profile.kernel_steps += part.counts.kernel;
        world.profile.kernel_declined += part.counts.kernel_declined;
        if (automatic) world.stepping.limits.merge(part.limits);
    }
}

/// The approach limits of the parts' pairs apart, from the step's complete forces (after the
/// threads' gather).
void noteApproachesOf(World& world, const ForceThreadPart* parts, std::size_t count) {
    for (std::size_t t = 0; t < count; ++t)
        noteApproaches(world, parts[t].apart, world.stepping.limits);
}

/// One thread: every pair in order, each onto its ends at once.
template <class Features, Runner R>
void runOneThread(const ForceView& v, ForceSums& sums, std::size_t npairs, ForceThreadPart& part) {
    try {
        for (std::size_t i = 0; i < npairs;)
            i = runPair<Features, Delivery::Direct, R>(v, sums, i, npairs, part);
    } catch (...) {
        // (what the loop did so far stands; the rows it let go are free again)
        settleRows(v.world, &part, 1, 0);
        settleWatches(v.world, &part, 1);
        throw;
    }
}

#ifdef TALUS_HAVE_OPENMP
/// A thread's range of pairs (Delivery::Parallel): the balls' sums from zero over the thread's
/// share of balls, then its pairs; a failure is kept with the pair it stopped at.
template <class Features, Runner R>
void runThreadRange(const ForceView& v, ForceSums& sums, std::size_t npairs, int nthreads,
                    ForceThreadPart& part) {
    auto& balls = v.world.bodies.balls;
    const int t = part.index;
    const std::size_t nballs = balls.size();
    for (std::size_t k = threadRangeStart(nballs, nthreads, t);
         k < threadRangeStart(nballs, nthreads, t + 1); ++k) {
        balls.force[k] = Vec2::Zero();
        balls.moment[k] = 0.0;
        if constexpr (Features::kAuto) balls.k_tran[k] = balls.k_rot[k] = 0.0;
    }
#pragma omp barrier
    const std::size_t hi = threadRangeStart(npairs, nthreads, t + 1);
    std::size_t i = threadRangeStart(npairs, nthreads, t);
    try {
        while (i < hi) i = runPair<Features, Delivery::Parallel, R>(v, sums, i, hi, part);
    } catch (...) {
        part.failure = std::current_exception();
        part.failure_pair = i;
    }
}

/// The threads' serial part: their deferred work in pair order, up to the first pair that
/// failed (as one thread would have stopped there). Returns that pair (SIZE_MAX: none).
template <class Features>
std::size_t runSerialPart(const ForceView& v, ForceSums& sums, std::size_t npairs,
                          ForceThreadPart* parts, int nthreads, ForceThreadPart& serial) {
    World& world = v.world;
    std::size_t failed = SIZE_MAX;
    for (int t = 0; t < nthreads; ++t)
        if (parts[t].failure && parts[t].failure_pair < failed) failed = parts[t].failure_pair;
    for (int t = 0; t < nthreads; ++t) {
        const ForceThreadPart& part = parts[t];
        for (const DeferredItem& item : part.items) {
            const std::size_t i = item.pair;
            if (i >= failed) break;
            switch (item.kind) {
                case Deferred::Pair:
                    // (a vertex hand-over leaves the contact's new holder in slot i: again)
                    for (std::size_t next = i; next == i;)
                        next = runPair<Features, Delivery::Serial, Runner::Any>(v, sums, i, npairs,
                                                                                serial);
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
    }
    return failed;
}
#endif

/// Threads: their ranges of pairs in parallel, the serial part, the rows, then the gather of
/// the balls no one thread added onto and the energy books in pair order.
template <class Features, Runner R>
void runThreads(const ForceView& v, ForceSums& sums, std::size_t npairs, int nthreads,
                double& finite_check) {
#ifdef TALUS_HAVE_OPENMP
    World& world = v.world;
    ForceScratch& scratch = forceScratch(world);
    ++world.profile.threaded_steps;
    auto& parts = scratch.parts;
    // Until the routes are whole again (gatherPairActions), a failure must rebuild them.
    const uint64_t routes_version = scratch.incidence_version;
    scratch.incidence_version = UINT64_MAX;
#pragma omp parallel num_threads(nthreads)
    runThreadRange<Features, R>(v, sums, npairs, nthreads,
                                parts[static_cast<std::size_t>(omp_get_thread_num())]);
    ForceThreadPart& serial = parts[static_cast<std::size_t>(nthreads)];
    const std::size_t failed =
        runSerialPart<Features>(v, sums, npairs, parts.data(), nthreads, serial);
    mergeParts(world, parts.data(), parts.size(), Features::kAuto, finite_check);
    settleRows(world, parts.data(), parts.size(), failed);
    settleWatches(world, parts.data(), parts.size());
    for (const auto& part : parts)
        if (part.failure && part.failure_pair == failed) std::rethrow_exception(part.failure);
    gatherPairActions(world, Features::kAuto);
    scratch.incidence_version = routes_version;
    if constexpr (Features::kAuto) noteApproachesOf(world, parts.data(), parts.size());
    if constexpr (Features::kEnergy)
        for (std::size_t i = 0; i < npairs; ++i)
            if (v.energies[i].what) bookPairEnergy(world.books, sums, v.energies[i]);
#else
    (void)v, (void)sums, (void)npairs, (void)nthreads, (void)finite_check;
#endif
}

/// What the loop leaves at its start: the sums it adds onto from zero, the step's FdBlock.
template <class Features>
FdBlock startLoop(World& world, const StepContext& step, int nthreads) {
    auto& b = world.bodies.balls;
    if (nthreads <= 1) {
        std::fill(b.force.begin(), b.force.end(), Vec2::Zero());
        std::fill(b.moment.begin(), b.moment.end(), 0.0);
        if constexpr (Features::kAuto) {
            std::fill(b.k_tran.begin(), b.k_tran.end(), 0.0);
            std::fill(b.k_rot.begin(), b.k_rot.end(), 0.0);
        }
    }  // (threads: each zeroes its share of the balls)
    for (auto& w : world.bodies.walls) w.force.setZero(), w.moment = 0.0, w.knest = 0.0;
    if constexpr (Features::kAuto) {
        world.stepping.limits = StepLimits{};
        world.stepping.limits_stale = false;
    }
    FdBlock fd_template = world.contacts.fd_template;
    fd_template.tdel = step.dt;
    fd_template.time = world.clock.time;
    fd_template.flags = Features::kEnergy ? kFdEnergyOn : 0u;
    world.contacts.to_remove.clear();
    return fd_template;
}

/// What follows the loop: the check of the laws' outputs, the pairs to remove, the books.
template <class Features>
void endLoop(World& world, const ForceSums& sums, double finite_check, bool groups) {
    if (!std::isfinite(finite_check)) findNonFiniteContact(world);
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

template <class Features, Runner R>
void forceLoop(World& world, const StepContext& step, int nthreads) {
    ForceScratch& scratch = forceScratch(world);
    const std::size_t npairs = world.contacts.pairs.size();
    const FdBlock fd_template = startLoop<Features>(world, step, nthreads);
    const bool groups = Features::kEnergy && step.groups;
    if (groups) groupForceLoopStart(world);
    // One part per thread, and one for the threads' serial part.
    const std::size_t nparts = nthreads > 1 ? static_cast<std::size_t>(nthreads) + 1 : 1;
    scratch.parts.resize(nparts);
    for (std::size_t t = 0; t < nparts; ++t)
        resetPart(scratch.parts[t], static_cast<uint16_t>(t), fd_template);
    if (nthreads > 1) prepareThreadScratch(world, nthreads);
    const ForceView v = forceView(world, step, fd_template, nthreads, groups);
    ForceSums sums;
    double finite_check = 0.0;
    if (nthreads <= 1) {
        ForceThreadPart& part = scratch.parts[0];
        runOneThread<Features, R>(v, sums, npairs, part);
        mergeParts(world, &part, 1, Features::kAuto, finite_check);
        settleRows(world, &part, 1, SIZE_MAX);
        settleWatches(world, &part, 1);
        if constexpr (Features::kAuto) noteApproachesOf(world, &part, 1);
    } else {
        runThreads<Features, R>(v, sums, npairs, nthreads, finite_check);
    }
    endLoop<Features>(world, sums, finite_check, groups);
}

/// The loop compiled for the scene's runner.
template <class Features>
void forceLoopFor(World& world, const StepContext& step) {
    const int nthreads = forceThreads(world, world.contacts.pairs.size());
    world.clock.threads = nthreads;
    switch (prepareRuleRows(world)) {
        case Runner::Linear:
            return forceLoop<Features, Runner::Linear>(world, step, nthreads);
        case Runner::ContactBond:
            return forceLoop<Features, Runner::ContactBond>(world, step, nthreads);
        case Runner::Any:
            return forceLoop<Features, Runner::Any>(world, step, nthreads);
    }
}

}  // namespace

void forceDisplacement(World& world, const StepContext& step) {
    // The guard follows a contact through its first steps (Pair::watched). Switched on over
    // contacts that are older, it leaves them be, as it would have after their first steps.
    if (step.guard && !world.stepping.guard_was_on)
        for (std::size_t i = 0; i < world.contacts.pairs.size(); ++i)
            world.contacts.endWatch(world.contacts.pairs[i], world.contacts.cold[i]);
    world.stepping.guard_was_on = step.guard;
    if (!step.automatic) world.stepping.estimates_stale = true;
    // Dispatch once per step to the loop compiled for exactly what this scene needs.
    if (step.automatic) {
        if (step.energy)
            step.guard ? forceLoopFor<LoopFeatures<true, true, true>>(world, step)
                       : forceLoopFor<LoopFeatures<true, true, false>>(world, step);
        else
            step.guard ? forceLoopFor<LoopFeatures<true, false, true>>(world, step)
                       : forceLoopFor<LoopFeatures<true, false, false>>(world, step);
    } else {
        if (step.energy)
            step.guard ? forceLoopFor<LoopFeatures<false, true, true>>(world, step)
                       : forceLoopFor<LoopFeatures<false, true, false>>(world, step);
        else
            step.guard ? forceLoopFor<LoopFeatures<false, false, true>>(world, step)
                       : forceLoopFor<LoopFeatures<false, false, false>>(world, step);
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
