// SPDX-License-Identifier: MIT
//
// The force loop's view of the world for one step (as Box2D's solver takes its arrays into a
// context before its stages): the arrays the passes read and write, taken once per step, and
// the step's constants. The passes (pass_*.hpp) are inline functions of this view and a pair
// index; loop.cpp builds it and runs them. Not installed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "force/scratch.hpp"
#include "world/world.hpp"

namespace talus {

/// What a finish does with what reaches beyond its pair (loop.cpp, "Threads").
enum class Delivery {
    Direct,    // one thread: onto the ends at once, rare work at once
    Serial,    // threads, serial part: actions recorded, rare work at once
    Parallel,  // threads, a range: onto the balls the thread owns at once, else recorded; rare
               // work deferred to the serial part
};

/// The loop's compile-time switches: a scene pays only for the extras it asks for.
template <bool Auto, bool Energy, bool Guard>
struct LoopFeatures {
    static constexpr bool kAuto = Auto;      // gather the automatic step's limits and sums
    static constexpr bool kEnergy = Energy;  // book the contacts' energies
    static constexpr bool kGuard = Guard;    // the stability guard's per-contact checks
};

struct ForceView {
    Rule& rule(const Pair& p) const { return *rules[p.rule]; }
    /// The kernel rows of p's rule this step (kernel None: its contacts run FDlaw).
    const RuleRows& rowsOf(const Pair& p) const { return rows[p.rule]; }

    World& world;  // the rare paths
    // Pairs through their vectors: a wall contact's hand-over may add a pair (and move the
    // arrays) in the middle of the loop.
    std::vector<Pair>& pairs;
    std::vector<PairCold>& cold;
    std::vector<PairStored>& stored;
    const std::unique_ptr<Rule>* rules;  // Pair::rule indexes it
    const RuleRows* rows;                // ... and this
    // Balls and walls do not change size during the loop.
    const Vec2* pos;
    const Vec2* vel;
    const double* radius;
    const double* spin;
    const Box* fat;
    Vec2* force;
    double* moment;
    WallData* walls;
    const Segment* segments;
    const uint8_t* ball_moved;
    const uint8_t* segment_moved;
    // Threads: per ball, the thread that adds onto it at once; per pair, what it does to the
    // ends no thread owns (gathered after the loop).
    uint16_t* route;
    PairAction* actions;
    PairStiffness* stiffness;
    PairEnergy* energies;
    std::vector<uint32_t>& to_remove;  // pairs whose fat boxes stopped overlapping
    // The step.
    double dt;
    double window;               // between the half-step velocities around this force's time
    FdBlock fd_template;         // the step's FdBlock fields
    EnergyTotals totals_before;  // the energy contract's reference
    bool groups;                 // energy per group
};

struct StepContext;  // step/step.hpp

/// The view of `world` for the force loop of `step` (loop.cpp): the arrays as they are now, so
/// it is taken after everything that resizes them (the threads' scratch and the rules' rows
/// included: prepareRuleRows).
ForceView forceView(World& world, const StepContext& step, const FdBlock& fd_template, int nthreads,
                    bool groups);

/// The energy books' running sums of a step, on one thread or in the threads' serial part.
struct ForceSums {
    double strain_now = 0.0, bond_now = 0.0;  // stored energies, this step
    double held_before = 0.0;  // stored by contacts older than the tracing (baseline, once)
};

}  // namespace talus
