// SPDX-License-Identifier: MIT
//
// The engine's operations on a world, as free functions, grouped by the file that defines them.
// Not installed: a helper added here recompiles the engine, not its users.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "narrowphase.hpp"
#include "world.hpp"

namespace talus {

// --- the step (model.cpp)
void prepareRun(World& world);
void runSteps(World& world, int64_t steps);
/// Refuses a solve time no run can reach (solveTime and solve{time}).
void requireReachableTime(const World& world, double duration);
/// Whether the simulated time has landed on `end` (to round-off).
inline bool reached(const World& world, double end) {
    return !(end - world.clock.time > 1e-12 * std::max(1.0, std::fabs(end)));
}
void warn(World& world, const std::string& text);
/// The bit of a group name (Model::groupIndex); creates it when asked.
int groupIndex(World& world, const std::string& name, bool create);
[[noreturn]] void throwNonFinite(const World& world, const std::string& what);

// --- phase 1, the time step (timestep.cpp; step_limits.hpp: noteContact, noteContactLimits)
void computeTimestep(World& world);
/// The limits the force loop gathers, from the stored state (first step, scene changed).
void surveyPairs(World& world);
void noteApproach(const World& world, const Pair& p, const PairCold& c, double gap,
                  const Vec2& vrel, double accel, const Vec2& normal, StepLimits& limits);
/// For a pair with a pebble end off its clump's centroid: the lower bound of the true effective
/// mass over the pair's (clump) effective mass, <= 1; 1 otherwise.
double pebbleMassRatio(const World& world, const Pair& p);

// --- phase 2, the law of motion (law_of_motion.cpp, clump_motion.cpp, wall_servo.cpp)
void servoWalls(World& world);  // servo velocities, before the walls move
void lawOfMotion(World& world);
void moveWalls(World& world);
void reportNonFiniteBall(const World& world);
[[noreturn]] void reportNonFiniteEnergy(const World& world, double kinetic, double body,
                                        double damping, double driven);
void moveClumps(World& world, double& kinetic, double& body, double& damping, double& driven);
/// Pebble forces summed to the centroids.
void gatherClumpForces(World& world);
void placePebbles(World& world, const ClumpData& c);

// --- phase 3, contact detection (contact_detection.cpp)
void detectContacts(World& world);
void initBroadphase(World& world);
void rebuildBallTree(World& world);
void insertBall(World& world, uint32_t slot);
void insertSegment(World& world, uint32_t seg);
void addPairsForBall(World& world, uint32_t slot);
void addPairsForSegment(World& world, uint32_t seg);
void clearMovedFlags(World& world);
Box ballBox(const World& world, uint32_t slot);
Box segmentBox(const World& world, uint32_t seg);
/// Ball against wall segment `seg` with the chain's shared-vertex rule (narrowphase.hpp).
bool segmentGeometry(const World& world, uint32_t seg, const Vec2& centre, double radius,
                     ContactGeometry& g);
/// The segment of seg's chain that holds a ball seg gives up (-1: none).
int32_t wallHolder(const World& world, uint32_t seg, const Vec2& centre, double radius);
bool makePair(World& world, uint32_t ball_slot, uint32_t other, bool other_is_segment);
void removePair(World& world, std::size_t index);
ContactModel* cloneFor(World& world, Pair& p);
PropBlock propBlockFor(const World& world, const Pair& p);
double tangentialInverseMass(const World& world, const Pair& p);
void refreshRule(World& world, Pair& p);
void resetPair(World& world, Pair& p);
void swapPairState(World& world, std::size_t i, std::size_t j);
bool handOverWallContact(World& world, std::size_t index);
bool adoptWallContact(World& world, std::size_t index);
void sortBalls(World& world);
void repackContactObjects(World& world);

// --- phase 4, force-displacement (force_displacement.cpp)
void forceDisplacement(World& world);
/// Threads the force loop uses for `npairs` pairs this step (Model::setThreads).
int forceThreads(const World& world, std::size_t npairs);
/// The approach limits of the pairs that were apart in this force loop, from the step's
/// complete forces.
void noteApproaches(const World& world, const std::vector<uint32_t>& apart, StepLimits& limits);
/// The per-ball sums of the threads' per-pair actions, in pair order.
void gatherPairActions(World& world, int nthreads, bool automatic);
/// The balls' pairs in pair order, for the threads' gather.
void buildIncidence(World& world);
void prepareForceScratch(World& world, int nthreads, const FdBlock& tmpl);
bool activate(World& world, Pair& p, PairCold& c, const ContactGeometry& g, const Vec2& vrel);
void endContact(World& world, Pair& p, PairCold& c, bool check_guard);
/// The ABI's energy contract for one FDlaw (rare path). `strain_old`, `bond_old`: what the
/// contact stored before it; `before`: the run's dissipation totals before this step.
void checkEnergyContract(World& world, const Pair& p, double strain_old, double bond_old,
                         const FdBlock& fd, double fn_old, double fs_old, double m_old,
                         const EnergyTotals& before);
/// Notes a contact born overlapping; returns the placement energy to book (tracing on).
double notePlacement(World& world, const Pair& p, const PairCold& c, double overlap,
                     const FdBlock& fd, bool energy);
void noteDeepest(World& world, const Pair& p, PairCold& c, double force, double rate_after);
void queueBreak(World& world, std::size_t index, const Vec2& point, const FdBlock& fd);
/// The same from the FdBlock's fields: the break mode, and the stresses at failure if the model
/// gave them (kFdBreakStress).
void queueBreak(World& world, std::size_t index, const Vec2& point, int32_t mode, bool with_stress,
                double sigma, double tau);
[[noreturn]] void reportFailedLaw(const World& world, const Pair& p, const FdBlock& fd);
[[noreturn]] void findNonFiniteContact(const World& world);
[[noreturn]] void reportPassThrough(const World& world, const Pair& p, const ContactGeometry& g);

// --- lanes (contact_lanes.cpp; docs/plugin-abi.md, "Lanes"): while a contact has a row in its
// rule's lanes, the row holds its model's state and its object is out of date.
/// Puts p into its rule's lanes if its model's lane law takes it now (after an FDlaw).
bool enterLane(Pair& p);
/// Brings p's object up to date from its row (before anything reads the object).
void syncLane(const Pair& p);
/// Takes p out of the lanes, its object up to date (before anything changes the object).
void leaveLane(Pair& p);
/// Frees p's row without updating the object (which is about to be destroyed).
void dropLane(Pair& p);
void leaveAllLanes(World& world);
/// Every table's rows in the order of their pairs (after the pairs were sorted).
void reorderLanes(World& world);

// --- phase 5, bookkeeping (bookkeeping.cpp)
void bookkeeping(World& world);
/// The run-level energy check.
void checkBalance(World& world);
void flushWarnings(World& world);

// --- per-group energy books (group_energy.cpp); run only while world.books.groups.on
/// Tracing switched on (or groups added): size and zero the books.
void openGroupBooks(World& world);
/// Books a body's terms of this step to each of its groups (the law of motion; the clump pass
/// calls it with a clump's mask): kinetic energy at the snapshot, body work, damping and fixity
/// work (`driven`, split at the snapshot like the whole model's).
inline void bookBodyToGroups(World& world, uint64_t mask, double kinetic, double body,
                             double damping, double driven) {
    auto* groups = world.books.groups.g.data();
    for (uint64_t m = mask & world.books.groups.traced; m; m &= m - 1) {
        auto& gr = groups[__builtin_ctzll(m)];
        gr.step_kinetic += kinetic;
        gr.step_body += body;
        gr.step_damping += damping;
        gr.step_driven += driven;
    }
}
/// The force loop's per-contact share (rare path: called only with groups traced).
void bookContactToGroups(World& world, std::size_t i, const FdBlock& fd, bool first, bool ends,
                         double held, const Vec2& f, const Vec2& point);
void bookReleasedToGroups(World& world, const Pair& p, double released);
/// Kinetic energy that left the model with a deleted body (or changed at a clump release).
void bookDeletedToGroups(World& world, uint64_t mask, double kinetic);
/// A ball slot is being removed (deleted ball or pebble): mark its pending exchange records gone
/// and follow the last slot, which moves into it.
void followRemovedSlot(World& world, uint32_t slot);
void groupForceLoopStart(World& world);         // zero the scratch, drop stale records
void groupForceLoopEnd(World& world);           // strain/bond current values, baseline
void gatherExchangeStart(World& world);         // law of motion: rates before the update
void groupSnapshot(World& world, double lead);  // law of motion: split, snapshot, accumulate
void bookWallToGroups(World& world, uint64_t mask, double work, double lead);
/// Velocity and spin of a contact end (a ball slot) before and after the law of motion's
/// update; the clump pass routes pebble ends to their clump here.
void endRates(const World& world, uint32_t slot, Vec2& v, double& w);
/// The point an end's moments are taken about: a ball's centre, a pebble's clump centroid.
Vec2 endCentre(const World& world, uint32_t slot);
uint64_t endGroups(const World& world, const Pair& p, bool end2);

// --- bodies (model_bodies.cpp)
BallId createBallIn(World& world, const BallDef& def, uint32_t clump);  // kNoClump: free ball
void removeBall(World& world, BallId id, bool book_energy);
void updateMass(World& world, uint32_t slot);
void refreshPairMasses(World& world, uint32_t slot);

// --- contacts (model_contacts.cpp)
const Rule& ruleFor(const World& world, uint64_t groups1, uint64_t groups2);
/// Geometry of a pair now (for queries): normal, overlap, contact point.
bool pairGeometry(const World& world, const Pair& p, Vec2& normal, double& overlap, Vec2& point);
ContactInfo infoOf(const World& world, std::size_t index);
std::string describePair(const World& world, const Pair& p);

// --- bonds (model_bonds.cpp): which pairs a bond call selects, and the memory of pairs whose
// bond broke or was removed (a rule that bonds on touch, cbond's cb_bond, must not bond them
// again: kFdNoAutoBond at their next first FDlaw).
bool bondSelects(const World& world, const Pair& p, const BondSettings& s, int ga, int gb);
void forgetBond(World& world, std::size_t index);
uint32_t autoBondFlags(const World& world, const Pair& p, const PairCold& c);

}  // namespace talus
