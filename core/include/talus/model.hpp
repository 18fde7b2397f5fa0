// SPDX-License-Identifier: MIT
//
// Model: the facade of the engine, a 2D DEM model of balls, clumps, walls and contacts cycled in
// the PFC order (timestep -> law of motion -> contact detection -> force-displacement ->
// bookkeeping; docs/architecture.md). It holds the world (core/src/world/world.hpp) and nothing
// else; the methods are grouped by the thing they act on, as Box2D groups b2Body_*, b2Shape_*:
//   model and running   balls   clumps   walls   servos   contact models   contacts   bonds
//   energy   measurement   trackers   callbacks   performance   save and restore
// The plain data they take and return is in talus/model_types.hpp.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "talus/model_types.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/profile.hpp"
#include "talus/servo.hpp"

namespace talus {

class SaveWriter;  // talus/save_file.hpp
class SaveReader;
struct World;  // core/src/world/world.hpp

class Model {
public:
    explicit Model(const ModelDef& def = ModelDef{},
                   PluginRegistry& registry = PluginRegistry::global());
    ~Model();
    Model(const Model&) = delete;
    Model& operator=(const Model&) = delete;

    // ------------------------------------------------------------------ model and running
    /// Advances `steps` cycles. Throws NumericalError / PluginError on a fault; the model stays
    /// at the step that failed (nothing earlier is lost).
    void cycle(int64_t steps);
    /// Cycles until the simulated time has advanced by `duration` (the last step is shortened
    /// to land on it exactly).
    void solveTime(double duration);
    /// Cycles until the first of the criteria is reached (SolveSpec); returns which.
    SolveStop solve(const SolveSpec& spec);

    double time() const;
    int64_t step() const;
    double lastTimestep() const;
    StepRule lastStepRule() const;
    /// What governed the last automatic step, in words (rule and where).
    std::string lastStepReason() const;

    TimestepSettings& timestep();
    GuardSettings& guard();
    /// The warning about contacts that start overlapping (bodies created or moved into each
    /// other; docs/physics/guard.md), on by default. A routine that overlaps bodies on purpose
    /// (a genesis growing its balls) switches it off for that stretch and says so in its own
    /// words; the energy of such contacts is still booked as `placement`. A run-time switch,
    /// not saved. Returns the previous setting.
    bool setPlacementWarning(bool on);
    bool placementWarning() const;
    DampingSettings& damping();
    Vec2& gravity();
    MassMode massMode() const;

    /// Group names share one table (bit index); up to 64 groups per model.
    int groupIndex(const std::string& name, bool create);
    const std::vector<std::string>& groupNames() const;

    // ------------------------------------------------------------------ balls
    BallId createBall(const BallDef& def);
    void deleteBall(BallId id);
    bool isAlive(BallId id) const;
    std::size_t ballCount() const;
    /// Ids of the live balls, in creation order of their slots.
    std::vector<BallId> ballIds() const;

    // Ball state (throws InputError for a stale id). Velocities are at the half step.
    Vec2 ballPos(BallId id) const;
    void setBallPos(BallId id, const Vec2& p);
    Vec2 ballVel(BallId id) const;
    void setBallVel(BallId id, const Vec2& v);
    double ballSpin(BallId id) const;
    void setBallSpin(BallId id, double w);
    double ballAngle(BallId id) const;
    double ballRadius(BallId id) const;
    void setBallRadius(BallId id, double r);
    double ballMass(BallId id) const;
    double ballInertia(BallId id) const;
    double ballDensity(BallId id) const;
    void setBallDensity(BallId id, double rho);
    Vec2 ballForce(BallId id) const;  ///< contact force of the last step [N]
    double ballMoment(BallId id) const;
    Vec2 ballAppliedForce(BallId id) const;
    void setBallAppliedForce(BallId id, const Vec2& f);
    double ballAppliedMoment(BallId id) const;
    void setBallAppliedMoment(BallId id, double m);
    uint8_t ballFixity(BallId id) const;
    void setBallFixity(BallId id, uint8_t fixity);
    /// Inheritable contact property of a ball: "kn", "ks" or "fric" (NaN = not set).
    double ballContactProp(BallId id, const std::string& name) const;
    void setBallContactProp(BallId id, const std::string& name, double v);
    std::vector<std::string> ballGroups(BallId id) const;
    void addBallGroup(BallId id, const std::string& group);

    // ------------------------------------------------------------------ clumps
    /// Creates a rigid clump (docs/physics/clumps.md); throws InputError on bad input.
    ClumpId createClump(const ClumpDef& def);
    /// Makes a clump of existing balls (PFC "clump replicate"-like conversion): they keep their
    /// ids and their contacts with other bodies, their mutual pairs go, and the clump takes
    /// their momentum and angular momentum. `opts` gives density (default: the balls' mass
    /// over their area) or direct mass, groups (default: the union of the balls'), fixity and
    /// kn/ks/fric; its pebbles, template, pos and angle must be empty/unset.
    ClumpId createClumpFromBalls(const std::vector<BallId>& balls, const ClumpDef& opts = {});
    /// Defines a template (pebbles in its frame, Union or PlainSum or Direct); returns its id.
    int defineClumpTemplate(const std::vector<Pebble>& pebbles,
                            ClumpMassMode mode = ClumpMassMode::Union);
    const ClumpTemplate& clumpTemplate(int id) const;
    /// Deletes a clump, its pebbles and their contacts (books its kinetic energy as deleted).
    void deleteClump(ClumpId id);
    /// PFC "clump release": the pebbles become free balls (disk mass from the clump's density;
    /// in direct mode the clump's mass shared by area) moving with the clump's rigid velocity.
    std::vector<BallId> releaseClump(ClumpId id);
    bool isAlive(ClumpId id) const;
    std::size_t clumpCount() const;
    std::vector<ClumpId> clumpIds() const;
    /// The clump a ball belongs to as a pebble (invalid for a free ball).
    ClumpId clumpOf(BallId id) const;

    Vec2 clumpPos(ClumpId id) const;  ///< centroid
    void setClumpPos(ClumpId id, const Vec2& p);
    Vec2 clumpVel(ClumpId id) const;
    void setClumpVel(ClumpId id, const Vec2& v);
    double clumpSpin(ClumpId id) const;
    void setClumpSpin(ClumpId id, double w);
    double clumpAngle(ClumpId id) const;
    void setClumpAngle(ClumpId id, double a);
    double clumpMass(ClumpId id) const;
    double clumpInertia(ClumpId id) const;
    double clumpDensity(ClumpId id) const;
    Vec2 clumpForce(ClumpId id) const;  ///< contact force summed to the centroid, last step
    double clumpMoment(ClumpId id) const;
    Vec2 clumpAppliedForce(ClumpId id) const;
    void setClumpAppliedForce(ClumpId id, const Vec2& f);
    double clumpAppliedMoment(ClumpId id) const;
    void setClumpAppliedMoment(ClumpId id, double m);
    uint8_t clumpFixity(ClumpId id) const;
    void setClumpFixity(ClumpId id, uint8_t fixity);
    double clumpContactProp(ClumpId id, const std::string& name) const;
    /// Sets kn/ks/fric of the clump and of its pebbles.
    void setClumpContactProp(ClumpId id, const std::string& name, double v);
    std::vector<std::string> clumpGroups(ClumpId id) const;
    void addClumpGroup(ClumpId id, const std::string& group);
    /// The pebbles in world coordinates (centre, radius).
    std::vector<Pebble> clumpPebbles(ClumpId id) const;
    std::vector<BallId> clumpPebbleIds(ClumpId id) const;

    // ------------------------------------------------------------------ walls
    WallId createWall(const WallDef& def);
    std::size_t wallCount() const;
    std::vector<WallId> wallIds() const;
    std::vector<Vec2> wallPoints(WallId id) const;
    /// The chain joins its last point to its first (WallDef::closed).
    bool wallClosed(WallId id) const;
    Vec2 wallVel(WallId id) const;
    void setWallVel(WallId id, const Vec2& v);
    double wallSpin(WallId id) const;
    void setWallSpin(WallId id, double w);
    Vec2 wallCenter(WallId id) const;
    void setWallCenter(WallId id, const Vec2& c);
    Vec2 wallForce(WallId id) const;  ///< total force the balls exert on the wall [N]
    double wallContactProp(WallId id, const std::string& name) const;
    void setWallContactProp(WallId id, const std::string& name, double v);
    std::vector<std::string> wallGroups(WallId id) const;
    void addWallGroup(WallId id, const std::string& group);
    /// Sets (or replaces) the wall's servo; dir and length are resolved here (WallServoSettings).
    void setWallServo(WallId id, const WallServoSettings& s);
    /// The servo of a wall; false when it has none.
    bool wallServo(WallId id, WallServoState& out) const;

    // ------------------------------------------------------------------ servos
    /// A servo over a set of walls (talus/servo.hpp): checked and resolved here, run every step.
    ServoId addServo(const ServoSettings& s);
    /// Replaces a servo's settings; its ramp starts again from the walls' speed now.
    void setServo(ServoId id, const ServoSettings& s);
    ServoState servo(ServoId id) const;
    /// Removes a servo; its walls stop moving along their directions.
    void removeServo(ServoId id);
    std::size_t servoCount() const;

    // ------------------------------------------------------------------ contact models
    /// Sets the model new contacts get by default, with properties by name.
    void setDefaultContactModel(const std::string& name, const std::vector<PropValue>& props);
    /// Adds a rule for contacts between group_a and group_b (either order; "" = any, a wall's
    /// groups count). The most specific rule wins; among equals the latest.
    void addContactModelRule(const std::string& name, const std::vector<PropValue>& props,
                             const std::string& group_a, const std::string& group_b);
    /// Property names and metadata of a model (loads it if needed).
    const ModelFactory& contactModelFactory(const std::string& name);

    // ------------------------------------------------------------------ contacts
    std::size_t contactCount(bool active_only = true) const;
    std::vector<ContactInfo> contacts(bool active_only = true) const;
    bool findContact(ContactKey key, ContactInfo& out) const;
    /// Property of an active contact's model by name; throws InputError if unknown.
    double contactProp(ContactKey key, const std::string& name) const;
    void setContactProp(ContactKey key, const std::string& name, double value);
    /// Sets the stored normal/shear force of an active contact (PFC "contact force" write).
    void setContactForce(ContactKey key, double normal_force, double shear_force);
    /// Broadphase margin [m] (half the extra room of each fat box). 0 = automatic: 5% of the
    /// mean ball radius, fixed at the first cycle.
    void setBroadphaseMargin(double margin);
    double broadphaseMargin() const;

    // ------------------------------------------------------------------ bonds
    /// Installs a fresh clone of a bond model at the selected contacts and near-contacts (the
    /// old model's same-named properties carry over), bonded at their current geometry;
    /// returns how many (core/src/api/bonds.cpp). Throws InputError naming what is wrong.
    std::size_t bond(const BondSettings& s);
    /// Removes the bonds of the selected contacts (their model's `bonded` = 0; only contacts of
    /// model `model` unless empty); returns how many. Uses s.groups, s.walls (s.model: filter).
    std::size_t unbond(const BondSettings& s);

    // ------------------------------------------------------------------ energy
    void setEnergyTracing(bool on);
    bool energyTracing() const;
    /// Whole-model energies (docs/physics/energy.md); kinetic and strain are current values.
    EnergyTotals energies() const;
    /// Energies of one group (docs/physics/energy.md, "Energy per group"): the same items, with
    /// `exchanged` the work done on the group by contacts with bodies outside it. Unknown
    /// group, or tracing off: InputError.
    EnergyTotals energies(const std::string& group) const;

    // ------------------------------------------------------------------ measurement
    /// Unbalanced force of the last step (PFC's ratio; UnbalancedForce).
    UnbalancedForce unbalanced() const;
    /// Porosity, coordination, stress and strain rate in a region (MeasureResult).
    MeasureResult measure(const MeasureRegion& region) const;

    // ------------------------------------------------------------------ barriers
    /// Adds a barrier (BarrierDef; checked every step while one exists). Returns its id (>= 1).
    int createBarrier(const BarrierDef& def);
    std::size_t barrierCount() const;
    BarrierInfo barrierInfo(int id) const;

    // ------------------------------------------------------------------ trackers
    /// Starts a tracker on a free ball or a clump (TrackerDef; docs/lua-api.md, "Trackers") and
    /// takes its first sample now (it may end at once: see trackerStatus). Returns its id (>= 1).
    /// Throws InputError naming the bad option, a stale body, a pebble, or a body that already
    /// has a live tracker.
    int createTracker(BallId ball, const TrackerDef& def);
    int createTracker(ClumpId clump, const TrackerDef& def);
    /// Ends a live tracker (state Stopped; nothing if it has ended). An open touch closes at the
    /// last complete sample; its records stay.
    void stopTracker(int id);
    /// Forgets every tracker and its records (ids start again at 1).
    void clearTrackers();
    std::size_t trackerCount() const;
    TrackerStatus trackerStatus(int id) const;
    const TrackerDef& trackerDef(int id) const;
    const std::vector<TrackedImpact>& trackerImpacts(int id) const;
    const std::vector<TrackedCrossing>& trackerCrossings(int id) const;
    /// Per envelope bin, the greatest height of the centre above the ground and the greatest
    /// kinetic energy; NaN in the bins the centre never was in.
    const std::vector<double>& trackerEnvelopeHeight(int id) const;
    const std::vector<double>& trackerEnvelopeEnergy(int id) const;
    const std::vector<TrackedPoint>& trackerPath(int id) const;
    /// Called in the bookkeeping phase for a crossing of a line with `event` (the rest of that
    /// sample is taken after it returns, unless it stopped the tracker) and when a tracker ends
    /// by its own rules or because its body was deleted. Empty = none.
    void setTrackerHandler(std::function<void(const TrackerEvent&)> fn);

    // ------------------------------------------------------------------ callbacks
    /// Called in the bookkeeping phase every `every` steps, after events are delivered.
    int addCycleHook(int64_t every, std::function<void(Model&)> fn);
    void removeCycleHook(int handle);
    void setEventHandler(std::function<void(const Event&)> fn);
    /// Contact-created events cost a queue entry per new contact; they are queued only when asked.
    void enableContactCreatedEvents(bool on);
    /// Warnings (guard findings) go here; the default prints to stderr.
    void setWarningHandler(std::function<void(const std::string&)> fn);
    void warn(const std::string& text);
    /// Called after every step of cycle/solveTime, before the stop request (Ctrl-C,
    /// run_control.hpp) is tested: the CLI's progress line. Not part of the model's state (no
    /// handle, not saved); empty = none.
    void setStepObserver(std::function<void(const Model&)> fn);

    // ------------------------------------------------------------------ performance
    Profile& profile();
    const Profile& profile() const;
    /// Re-orders the balls in memory along a space-filling curve (and the pairs with them) at
    /// the first step and every `every` steps after (steps 1, 1 + every, ...), so that
    /// neighbours are close in memory; 0 = never. The default, kSortAuto, sorts every
    /// kSortAutoEvery steps while the model holds kSortAutoBalls balls or more (docs/lua-api.md,
    /// "Force loop").
    /// The physics is the same in any order; sums taken in another order differ in their last
    /// bits.
    void setSortInterval(int64_t every);
    int64_t sortInterval() const;
    static constexpr int64_t kSortAuto = -1;
    static constexpr int64_t kSortAutoEvery = 1000;
    static constexpr std::size_t kSortAutoBalls = 4096;
    /// Threads of the force loop (docs/architecture.md, "Threads"), n >= 1; results are
    /// bit-identical for any n. The default is the environment's TALUS_THREADS, else 1. A step
    /// runs on one thread in a build without OpenMP, with a contact model that lacks
    /// kTraitThreadSafe, or with fewer than `grain` pairs per thread (a thread for fewer costs
    /// more in its start and its waits than it saves).
    void setThreads(int n, int grain = kDefaultThreadGrain);
    int threads() const;
    int threadGrain() const;  // set by setThreads, else TALUS_THREAD_GRAIN, else the default
    static constexpr int kDefaultThreadGrain = 2000;
    /// True when this build can run the force loop on several threads (OpenMP).
    static bool threadingAvailable();
    /// Keeps every model of this process on one thread: for a process forked from one whose
    /// OpenMP threads may exist (a talus.map worker): libgomp's thread pool does not survive a
    /// fork, and a worker's parallel region could wait for threads it does not have.
    static void singleThreadedProcess();

    // ------------------------------------------------------------------ save and restore
    /// Writes every section of the model's state (core/src/api/save.cpp; the file around it:
    /// talus/save_file.hpp, docs/save-format.md). Hooks and handlers are not state: the host
    /// re-registers them.
    void saveState(SaveWriter& w) const;
    /// A model from sections written by saveState; throws InputError naming the section and what
    /// is inconsistent. `notes` receives what the user should know (plugin versions differ).
    static std::unique_ptr<Model> restoreState(SaveReader& r, PluginRegistry& registry,
                                               std::vector<std::string>& notes);

private:
    friend World& worldOf(Model& model);
    friend const World& worldOf(const Model& model);
    std::unique_ptr<World> m_world;
};

}  // namespace talus
