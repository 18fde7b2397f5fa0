// SPDX-License-Identifier: MIT
//
// One step of the PFC cycle, as a table of contents (step.cpp):
//   computeTimestep -> [servoWalls, runServos] -> lawOfMotion -> moveWalls -> detectContacts ->
//   forceDisplacement -> bookkeeping
// each a free function over the world (world/world.hpp), in its own file. Not installed.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "world/world.hpp"

namespace talus {

/// What one step needs, fixed once its length is known (as Box2D's b2StepContext): built by
/// beginStep after the time-step phase and handed to every phase after it.
struct StepContext {
    double dt = 0.0;         ///< this step [s]
    double dt_prev = 0.0;    ///< the step before it (0 when the integrator starts afresh)
    double window = 0.0;     ///< time between the two half-step velocities, (dt_prev + dt)/2
    bool automatic = false;  ///< the automatic step: the force loop gathers its limits
    bool energy = false;     ///< energy tracing
    bool groups = false;     ///< ... per group
    bool guard = false;      ///< any of the guard's per-contact checks
};

// --- the step (step.cpp): the phases in order, each timed into world.profile
void prepareRun(World& world);
void runSteps(World& world, int64_t steps);
StepContext beginStep(const World& world);
/// Refuses a solve time no run can reach (solveTime and solve{time}; api/model.cpp).
void requireReachableTime(const World& world, double duration);
/// Whether the simulated time has landed on `end` (to round-off).
inline bool reached(const World& world, double end) {
    return !(end - world.clock.time > 1e-12 * std::max(1.0, std::fabs(end)));
}

// --- the phases, one file each
void computeTimestep(World& world);                             // timestep.cpp
void servoWalls(World& world, const StepContext& step);         // wall_servo.cpp
void runServos(World& world, const StepContext& step);          // servo.cpp
void lawOfMotion(World& world, const StepContext& step);        // law_of_motion.cpp
void moveWalls(World& world, const StepContext& step);          // law_of_motion.cpp
void detectContacts(World& world, const StepContext& step);     // detection.cpp
void forceDisplacement(World& world, const StepContext& step);  // force/loop.cpp
void bookkeeping(World& world, const StepContext& step);        // bookkeeping.cpp

// --- parts of the phases that other files call
/// The gap between two walls: the distance of `to`'s first vertex from the line of `from`'s
/// first segment (servo.cpp; two parallel platens, a box's opposite walls).
double wallGap(const World& world, WallId from, WallId to);
/// PFC's mechanical ratio from the forces of the last force loop (unbalanced.cpp).
UnbalancedForce unbalancedForce(const World& world);
/// The limits the force loop gathers, from the stored state (first step, scene changed;
/// timestep.cpp).
void surveyPairs(World& world);
/// The run-level energy check (bookkeeping.cpp).
void checkBalance(World& world);
/// With tracing: the moving walls' work over the second half of this step (bookkeeping.cpp).
void bookWallsBefore(World& world, const StepContext& step);
/// The contacts that gave back more energy than they took this step, against the scene's energy
/// (bookkeeping.cpp); an error thrown only when `may_throw`.
void judgeEnergyGains(World& world, bool may_throw);
/// The guard's aggregated findings as warnings, once per run call (bookkeeping.cpp).
void flushWarnings(World& world);
void reportNonFiniteBall(const World& world);  // law_of_motion.cpp
/// The energy books open at this snapshot, from the kinetic energy at its whole step (or wait
/// for the contacts' models; law_of_motion.cpp).
void openBooks(World& world, double kinetic);
[[noreturn]] void reportNonFiniteEnergy(const World& world, double kinetic, double body,
                                        double damping, double driven);
// clump_motion.cpp
void moveClumps(World& world, const StepContext& step, double& kinetic, double& body,
                double& damping, double& driven);
/// Pebble forces summed to the centroids.
void gatherClumpForces(World& world);
/// One clump's force and moment about its centroid from its pebbles' (gatherClumpForces).
void sumPebbleForces(const World& world, const ClumpData& c, Vec2& force, double& moment);
void placePebbles(World& world, const ClumpData& c);

}  // namespace talus
