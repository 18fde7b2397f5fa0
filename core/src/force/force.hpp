// SPDX-License-Identifier: MIT
//
// The force-displacement phase beyond its entry point (step/step.hpp): the threads' parts
// (threads.cpp), a contact's life (contact_life.cpp: activation, placement, the guard at its end,
// bond breaks) and the checks of what a law returned (checks.cpp). Not installed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "force/kernels.hpp"
#include "step/narrowphase.hpp"
#include "world/world.hpp"

namespace talus {

/// Threads the force loop uses for `npairs` pairs this step (Model::setThreads).
int forceThreads(const World& world, std::size_t npairs);
/// Keeps every model of this process on one thread (Model::singleThreadedProcess).
void setSingleThreadedProcess();
/// The approach limits of the pairs that were apart in this force loop, from the step's
/// complete forces.
void noteApproaches(const World& world, const std::vector<uint32_t>& apart, StepLimits& limits);
/// Where thread t's share of `count` items (pairs, balls) starts; it ends at t + 1's.
inline std::size_t threadRangeStart(std::size_t count, int nthreads, int t) {
    return count * static_cast<std::size_t>(t) / static_cast<std::size_t>(nthreads);
}
/// The sums of the balls the threads did not add onto at once (shared and diverted), from the
/// pairs' actions in pair order.
void gatherPairActions(World& world, bool automatic);
/// The balls' pairs in pair order and their routes, for `nthreads` threads.
void buildIncidence(World& world, int nthreads);
/// Each rule's kernel rows for this step's loop (ForceScratch::rows), its contacts taken off
/// their rows where its kernel does not run; the runner the loop is compiled for.
Runner prepareRuleRows(World& world);
/// The threads' per-pair records and the incidence, for `nthreads` threads.
void prepareThreadScratch(World& world, int nthreads);
/// What a first touch found (activate), for its first finish.
struct Touch {
    bool first = false;            // a new contact (not a wall contact taken over)
    bool born_overlapped = false;  // more overlap than the step's motion could make (placement)
    double closure = 0.0;          // the overlap the step's motion could make [m]
};
/// A pair touching: its contact made (its duration, the guard's watch when `guard`), or a wall
/// contact taken over from a neighbouring segment's pair (Touch::first false).
Touch activate(World& world, Pair& p, PairCold& c, const ContactGeometry& g, const Vec2& vrel,
               bool guard);
void endContact(World& world, Pair& p, PairCold& c, bool check_guard);
/// The ABI's energy contract for one FDlaw (rare path). `strain_old`, `bond_old`: what the
/// contact stored before it; `before`: the run's dissipation totals before this step.
void checkEnergyContract(World& world, const Pair& p, double strain_old, double bond_old,
                         const FdBlock& fd, double fn_old, double fs_old, double m_old,
                         const EnergyTotals& before);
/// Notes a contact born overlapping; returns the placement energy to book (tracing on).
/// The contact-created event of pair `p` at `point` (only when the script asked for them).
void noteContactCreated(World& world, const Pair& p, const PairCold& c, const Vec2& point);
double notePlacement(World& world, const Pair& p, double closure, double overlap, const FdBlock& fd,
                     bool energy);
/// The guard's watch: the values at the deepest overlap (the last step's, as it stops growing).
void noteDeepest(const World& world, const PairCold& c, GuardWatch& w, double force,
                 double rate_after);
void queueBreak(World& world, std::size_t index, const Vec2& point, const FdBlock& fd);
/// The same from the FdBlock's fields: the break mode, and the stresses at failure if the model
/// gave them (kFdBreakStress).
void queueBreak(World& world, std::size_t index, const Vec2& point, int32_t mode, bool with_stress,
                double sigma, double tau);
[[noreturn]] void reportFailedLaw(const World& world, const Pair& p, const FdBlock& fd);
[[noreturn]] void findNonFiniteContact(const World& world);
[[noreturn]] void reportPassThrough(const World& world, const Pair& p, const ContactGeometry& g);

}  // namespace talus
