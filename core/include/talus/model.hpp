// SPDX-License-Identifier: MIT
//
// The engine: a 2D DEM model of balls, walls and contacts, cycled in the PFC order
// (docs/architecture.md walks one cycle through the code):
//   timestep -> law of motion -> contact detection -> force-displacement -> bookkeeping.
// Each phase lives in its own source file: timestep.cpp, law_of_motion.cpp,
// contact_detection.cpp, force_displacement.cpp, bookkeeping.cpp.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "talus/clump_mass.hpp"
#include "talus/contact_model.hpp"
#include "talus/energy.hpp"
#include "talus/ids.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/profile.hpp"
#include "talus/vec.hpp"

namespace talus {

class Broadphase;
class Model;
class SaveWriter;  // talus/save_file.hpp
class SaveReader;
struct BodyStore;        // core/src/body_store.hpp
struct ContactStore;     // core/src/contact_store.hpp
struct ContactGeometry;  // narrowphase.hpp

constexpr double kNotSet = std::numeric_limits<double>::quiet_NaN();

/// How a ball's mass and inertia follow from its radius.
enum class MassMode {
    Disk,    ///< unit-thickness disk: m = rho pi R^2 (1 m), I = m R^2 / 2 (PFC2D)
    Sphere,  ///< sphere: m = 4/3 rho pi R^3, I = 2/5 m R^2 (to compare with 3D data)
};

struct ModelDef {
    Vec2 gravity{0.0, 0.0};  ///< [m/s^2]
    MassMode mass_mode = MassMode::Disk;
};

/// Fixity bits (PFC "fix"): the velocity component is not integrated.
enum Fixity : uint8_t { kFixX = 1, kFixY = 2, kFixSpin = 4 };

struct BallDef {
    Vec2 pos{0.0, 0.0};        ///< [m]
    double radius = 0.0;       ///< [m], > 0
    double density = 0.0;      ///< [kg/m^3], > 0 (or set mass directly)
    double mass = kNotSet;     ///< [kg]; overrides density when set
    double inertia = kNotSet;  ///< [kg m^2]; default from the mass mode
    Vec2 vel{0.0, 0.0};        ///< [m/s]
    double spin = 0.0;         ///< [rad/s]
    double angle = 0.0;        ///< [rad]
    uint8_t fixity = 0;
    std::vector<std::string> groups;
    /// Inheritable contact properties (PFC2D 3.x ball properties); NaN = not set.
    double kn = kNotSet, ks = kNotSet, fric = kNotSet;
};

/// A rigid clump of pebbles (docs/physics/clumps.md). Pebbles are given in the clump's frame and
/// placed so that the clump's centroid lands on `pos`, turned by `angle` and scaled by `scale`;
/// without `pos` they are in world coordinates (scaled about the origin). Mass properties by
/// `mass_mode`: Union (default) and PlainSum need `density`; Direct needs `mass` and `inertia`
/// (about the centroid) and takes `centroid` (clump frame, default: the union's) if given.
struct ClumpDef {
    std::vector<Pebble> pebbles;  ///< {pos, radius}; empty when `template_id` is set
    int template_id = 0;          ///< > 0: a template's pebbles and mass properties
    Vec2 pos{kNotSet, kNotSet};   ///< [m] where the centroid goes; NaN: pebbles in world frame
    double angle = 0.0;           ///< [rad]
    double scale = 1.0;           ///< > 0; lengths scale by it, mass by scale^2, I by scale^4
    ClumpMassMode mass_mode = ClumpMassMode::Union;
    double density = kNotSet;         ///< [kg/m^3] (Union, PlainSum)
    double mass = kNotSet;            ///< [kg] (Direct)
    double inertia = kNotSet;         ///< [kg m^2] about the centroid (Direct)
    Vec2 centroid{kNotSet, kNotSet};  ///< [m] in the clump frame before scaling (Direct)
    Vec2 vel{0.0, 0.0};               ///< [m/s] of the centroid
    double spin = 0.0;                ///< [rad/s]
    uint8_t fixity = 0;
    std::vector<std::string> groups;
    double kn = kNotSet, ks = kNotSet, fric = kNotSet;  ///< inherited by the pebbles
};

/// A clump template: pebbles in its own frame and their mass properties per unit density,
/// computed once (Model::defineClumpTemplate) and scaled at each placement.
struct ClumpTemplate {
    std::vector<Pebble> pebbles;
    ClumpMassMode mass_mode = ClumpMassMode::Union;
    MassProps props;  ///< per unit density (zero for Direct)
};

struct WallDef {
    std::vector<Vec2> points;       ///< vertices of the chain, >= 2, consecutive points distinct
    bool closed = false;            ///< join the last point to the first
    Vec2 vel{0.0, 0.0};             ///< translational velocity [m/s]
    double spin = 0.0;              ///< angular velocity about `center` [rad/s]
    Vec2 center{kNotSet, kNotSet};  ///< centre of rotation; default: centroid of the points
    std::vector<std::string> groups;
    double kn = kNotSet, ks = kNotSet, fric = kNotSet;
};

/// Wall servo (PFC "wall servo"; core/src/wall_servo.cpp, docs/lua-api.md "Servo walls").
/// Each step, before the walls move, the wall's velocity along `dir` is set to
/// v = G (target - measured), capped at |v| <= vmax, where `measured` is the compressive force
/// the balls exert on the wall along -dir (or that force over `length`), and the gain is PFC's
/// G = alpha L / (sum of the wall's contacts' knest * dt) (stress form; force form without L).
struct WallServoSettings {
    bool on = true;
    bool stress = false;         ///< the target is a stress [Pa = N/m in 2D]; else a force [N]
    double target = 0.0;         ///< [N] or [Pa]; compression positive
    double length = kNotSet;     ///< [m] the stress form's length; NaN: the wall chain's length
    double gain = kNotSet;       ///< a fixed gain [m/s per N or per Pa]; NaN: PFC's formula
    double alpha = 0.5;          ///< PFC's relaxation factor, in (0, 2)
    double vmax = 1.0;           ///< [m/s] speed cap
    Vec2 dir{kNotSet, kNotSet};  ///< direction into the material; NaN: the wall's normal (below)
};

/// A wall servo's settings (dir and length resolved) and its state at the last step.
struct WallServoState {
    WallServoSettings settings;
    double force = 0.0;   ///< compressive force on the wall along -dir [N] (last force loop)
    double stress = 0.0;  ///< force / length [Pa]
    double vel = 0.0;     ///< velocity along dir the servo set for the step [m/s]
    double gain = 0.0;    ///< gain of that step (inf: no contact stiffness, moved at vmax)
    double knest = 0.0;   ///< sum of knest over the wall's contacts [N/m]
};

/// A measurement region (PFC measurement circle; core/src/measure.cpp).
struct MeasureRegion {
    bool circle = true;
    Vec2 center{0.0, 0.0};  ///< circle
    double radius = 0.0;
    Vec2 lo{0.0, 0.0}, hi{0.0, 0.0};  ///< box corners (xmin, ymin), (xmax, ymax)
};

/// What a measurement region measures (docs/lua-api.md "Measurement").
struct MeasureResult {
    double area = 0.0;          ///< region area [m^2]
    double solid = 0.0;         ///< area of the balls' parts inside [m^2]
    double porosity = 0.0;      ///< 1 - solid / area
    double coordination = 0.0;  ///< contacts per ball over the balls whose centre is inside
    double stress_xx = 0.0, stress_yy = 0.0, stress_xy = 0.0;  ///< [Pa], tension positive
    double rate_xx = 0.0, rate_yy = 0.0, rate_xy = 0.0;  ///< strain rate [1/s] (sym. part of L)
    double rate_spin = 0.0;  ///< antisymmetric part (L_yx - L_xy)/2 [rad/s]
    int64_t balls = 0;       ///< balls whose centre is inside
    int64_t contacts = 0;    ///< touching contacts whose contact point is inside
};

/// Unbalanced force (PFC's mechanical ratio; core/src/measure.cpp).
struct UnbalancedForce {
    double mean_unbalanced = 0.0;  ///< mean |net force| over the free bodies [N]
    double max_unbalanced = 0.0;
    double mean_contact = 0.0;  ///< mean |contact force| over the contacts that carry one [N]
    double ratio = 0.0;         ///< mean_unbalanced / mean_contact (inf: no contact force)
    int64_t bodies = 0, contacts = 0;
};

/// m:solve's criteria (Model::solve, core/src/solve.cpp). Unset ones (NaN, -1, empty) are off;
/// after each step the first criterion reached ends the run, targets before caps.
struct SolveSpec {
    double time = kNotSet;  ///< [s] simulated, landed on exactly as solveTime does
    int64_t steps = -1;
    double ratio = kNotSet;             ///< UnbalancedForce::ratio at or below this
    std::function<bool(Model&)> until;  ///< true stops
    int64_t max_steps = -1;             ///< cap: ends with a warning
    double max_time = kNotSet;          ///< cap on wall-clock seconds: ends with a warning
    std::function<bool()> interrupted;  ///< e.g. a SIGINT flag
};
enum class SolveStop { Time, Steps, Ratio, Until, MaxSteps, MaxTime, Interrupted };
const char* solveStopName(SolveStop s);

/// A named property value for a contact model.
struct PropValue {
    std::string name;
    double value = 0.0;
};

/// m:bond{...} (core/src/model_bonds.cpp; docs/lua-api.md, "Bonds"): one property of the bond
/// model, a fixed value or drawn per contact from a distribution (truncated at zero).
struct BondProp {
    enum Dist { Fixed, Normal, Uniform };
    std::string name;
    Dist dist = Fixed;
    double mean = 0.0;  ///< the value when Fixed
    double sd = 0.0;    ///< standard deviation (Uniform: mean +- sd sqrt 3)
};

/// Which contacts m:bond / m:unbond act on and what m:bond installs.
struct BondSettings {
    std::string model;                ///< a model whose Traits() have kTraitBond
    std::vector<BondProp> props;      ///< given properties (others carry over from the old model)
    std::vector<std::string> groups;  ///< none: all; one: both ends in it; two: one end in each
    double gap = 0.0;                 ///< near-contacts with a gap <= gap are bonded too [m]
    bool walls = false;               ///< ball-wall contacts too (else ball-ball only)
    bool reset = false;               ///< start stress-free: zero forces, lin_mode = 1
    uint64_t seed = 1;                ///< for the drawn properties
};

/// Time-step control (docs/physics/timestep.md). Automatic by default: the step is the smallest
/// of the stability rule, the resolution rule, the free-flight (kinematic) rule and `max`.
struct TimestepSettings {
    bool automatic = true;
    double fixed = 0.0;      ///< [s], used when !automatic
    double safety = 0.8;     ///< stability rule: safety * min sqrt(m/k), PFC's customary factor
    double resolution = 30;  ///< resolution rule: steps per contact duration; 0 = off
    double max = std::numeric_limits<double>::infinity();  ///< [s]
    double growth = 2.0;  ///< largest ratio between consecutive automatic steps
};

/// Which rule set the last automatic step.
enum class StepRule {
    Fixed,
    Stability,
    Resolution,
    Approach,
    Kinematic,
    Max,
    Growth,
    Idle,
    Damping
};
const char* stepRuleName(StepRule r);

/// What the stability guard does with a finding.
enum class GuardAction { Off, Warn, Error };

struct GuardSettings {
    /// A contact that returned more energy than it took over its life (docs/physics/guard.md).
    GuardAction energy = GuardAction::Warn;
    double energy_tolerance = 0.01;  ///< allowed gain as a fraction of the peak energy taken
    /// A contact whose step was too large for its own time scale: fewer than `min_steps` steps
    /// per contact duration at the stiffness the model reported (thesis A: 10-20 per impact).
    GuardAction resolution = GuardAction::Warn;
    int min_steps = 10;
    /// A model whose forces change faster than its reported stiffness allows (the time step
    /// follows the reported stiffness, so an under-reporting model gets too large a step).
    GuardAction stiffness = GuardAction::Warn;
    /// Run-level energy balance (only while energy tracing is on): |balance_error| against
    /// `balance_tolerance` times the throughput, the larger of the energy put in and the peak
    /// mechanical energy (docs/physics/guard.md), every `balance_every` steps.
    GuardAction balance = GuardAction::Warn;
    double balance_tolerance = 0.01;
    int64_t balance_every = 10;

    bool anyOn() const {
        return energy != GuardAction::Off || resolution != GuardAction::Off ||
               stiffness != GuardAction::Off;
    }
    /// Every check off (the non-finite checks always run).
    static GuardSettings allOff() {
        GuardSettings g;
        g.energy = g.resolution = g.stiffness = g.balance = GuardAction::Off;
        return g;
    }
};

/// Law-of-motion damping options.
struct DampingSettings {
    double local = 0.0;  ///< PFC local damping coefficient alpha (accuracy-reference 3.4)
    /// Mass-proportional viscous damping [1/s]: F = -viscous m v, integrated implicitly at the
    /// time level of the contact forces (thesis B eq. 2.41, seed digest section 5).
    double viscous = 0.0;
};

/// Kinds of events queued during a cycle and delivered after it.
enum class EventKind { BondBreak, ContactCreated };

struct Event {
    EventKind kind;
    double time = 0.0;
    Vec2 pos{0.0, 0.0};
    ContactKey contact;
    int32_t mode = 0;  ///< BreakMode for bond breaks
    std::string model;
    /// Bond breaks: the bond's peak normal stress (tension +) and shear stress at failure
    /// [Pa], when the model reports them (kFdBreakStress); NaN otherwise.
    double sigma = std::numeric_limits<double>::quiet_NaN();
    double tau = std::numeric_limits<double>::quiet_NaN();
};

/// A read-only view of one contact, for queries.
struct ContactInfo {
    ContactKey key;
    BallId ball1;
    BallId ball2;          ///< invalid for a ball-wall contact
    WallId wall;           ///< valid for a ball-wall contact
    ClumpId clump1;        ///< clump of end 1 when it is a pebble (else invalid)
    ClumpId clump2;        ///< clump of end 2 when it is a pebble (else invalid)
    int32_t segment = -1;  ///< segment index within the wall
    bool active = false;   ///< has a model object (touching or within activity distance)
    Vec2 normal{0.0, 0.0};
    Vec2 point{0.0, 0.0};
    double overlap = 0.0;
    double normal_force = 0.0;
    double shear_force = 0.0;
    double moment = 0.0;
    bool sliding = false;
    bool bonded = false;
    std::string model;
};

class Model {
public:
    explicit Model(const ModelDef& def = ModelDef{},
                   PluginRegistry& registry = PluginRegistry::global());
    ~Model();
    Model(const Model&) = delete;
    Model& operator=(const Model&) = delete;

    // ------------------------------------------------------------------ bodies
    BallId createBall(const BallDef& def);
    void deleteBall(BallId id);
    bool isAlive(BallId id) const;
    std::size_t ballCount() const;
    /// Ids of the live balls, in creation order of their slots.
    std::vector<BallId> ballIds() const;

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

    WallId createWall(const WallDef& def);
    std::size_t wallCount() const;
    std::vector<WallId> wallIds() const;

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

    // Wall state
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

    // ------------------------------------------------------------------ bonds
    /// Installs a fresh clone of a bond model at the selected contacts and near-contacts (the
    /// old model's same-named properties carry over), bonded at their current geometry;
    /// returns how many (core/src/model_bonds.cpp). Throws InputError naming what is wrong.
    std::size_t bond(const BondSettings& s);
    /// Removes the bonds of the selected contacts (their model's `bonded` = 0; only contacts of
    /// model `model` unless empty); returns how many. Uses s.groups, s.walls (s.model: filter).
    std::size_t unbond(const BondSettings& s);

    // ------------------------------------------------------------------ running
    /// Advances `steps` cycles. Throws NumericalError / PluginError on a fault; the model stays
    /// at the step that failed (nothing earlier is lost).
    void cycle(int64_t steps);
    /// Cycles until the simulated time has advanced by `duration` (the last step is shortened
    /// to land on it exactly).
    void solveTime(double duration);

    /// Cycles until the first of the criteria is reached (SolveSpec); returns which.
    SolveStop solve(const SolveSpec& spec);
    /// Unbalanced force of the last step (PFC's ratio; UnbalancedForce).
    UnbalancedForce unbalanced() const;
    /// Porosity, coordination, stress and strain rate in a region (MeasureResult).
    MeasureResult measure(const MeasureRegion& region) const;

    double time() const { return m_time; }
    int64_t step() const { return m_step; }
    double lastTimestep() const { return m_dt; }
    StepRule lastStepRule() const { return m_dt_rule; }
    /// What governed the last automatic step, in words (rule and where).
    std::string lastStepReason() const;

    TimestepSettings& timestep() { return m_timestep; }
    GuardSettings& guard() { return m_guard; }
    DampingSettings& damping() { return m_damping; }
    Vec2& gravity() { return m_gravity; }
    MassMode massMode() const { return m_mass_mode; }

    /// Broadphase margin [m] (half the extra room of each fat box). 0 = automatic: 5% of the
    /// mean ball radius, fixed at the first cycle.
    void setBroadphaseMargin(double margin);
    double broadphaseMargin() const;

    // ------------------------------------------------------------------ energy
    void setEnergyTracing(bool on);
    bool energyTracing() const { return m_books.on; }
    /// Whole-model energies (docs/physics/energy.md); kinetic and strain are current values.
    EnergyTotals energies() const;
    /// Energies of one group (docs/physics/energy.md, "Energy per group"): the same items, with
    /// `exchanged` the work done on the group by contacts with bodies outside it. Unknown
    /// group, or tracing off: InputError.
    EnergyTotals energies(const std::string& group) const;

    // ------------------------------------------------------------------ callbacks and output
    /// Called in the bookkeeping phase every `every` steps, after events are delivered.
    int addCycleHook(int64_t every, std::function<void(Model&)> fn);
    void removeCycleHook(int handle);
    void setEventHandler(std::function<void(const Event&)> fn) { m_event_handler = std::move(fn); }
    /// Contact-created events cost a queue entry per new contact; they are queued only when asked.
    void enableContactCreatedEvents(bool on) { m_contact_events = on; }
    /// Warnings (guard findings) go here; the default prints to stderr.
    void setWarningHandler(std::function<void(const std::string&)> fn) {
        m_warning_handler = std::move(fn);
    }
    void warn(const std::string& text);

    Profile& profile() { return m_profile; }
    const Profile& profile() const { return m_profile; }
    /// Called after every step of cycle/solveTime, before the stop request (Ctrl-C,
    /// run_control.hpp) is tested: the CLI's progress line. Not part of the model's state (no
    /// handle, not saved); empty = none.
    void setStepObserver(std::function<void(const Model&)> fn) { m_step_observer = std::move(fn); }
    /// Re-orders the balls in memory along a space-filling curve every `every` steps (0 = never)
    /// so that neighbours are close in memory.
    void setSortInterval(int64_t every) { m_sort_every = every; }
    /// Calls the batched FDlaw of the models that offer one (docs/plugin-abi.md, "Batched
    /// FDlaw"; default on). Off: FDlaw per contact. Both give the same bits; the switch is for
    /// tests and measurements.
    /// Off also takes every contact out of the models' lanes, which are part of the batched path.
    void setBatchedLaw(bool on);
    bool batchedLaw() const { return m_batched_law; }
    /// Runs the contacts of models that offer a lane law through it (docs/plugin-abi.md,
    /// "Lanes"; default off: measured no faster than the batched FDlaw on the shipped models,
    /// docs/benchmarks.md). The same bits either way; needs the batched law on.
    void setLanes(bool on);
    bool lanes() const { return m_lanes; }
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
    /// Threads the force loop uses for `npairs` pairs this step.
    int forceThreads(std::size_t npairs) const;

    // Group names share one table (bit index); up to 64 groups per model.
    int groupIndex(const std::string& name, bool create);
    const std::vector<std::string>& groupNames() const { return m_group_names; }

    // ------------------------------------------------------------------ save and restore
    /// Writes every section of the model's state (core/src/model_save.cpp; the file around it:
    /// talus/save_file.hpp, docs/save-format.md). Hooks and handlers are not state: the host
    /// re-registers them.
    void saveState(SaveWriter& w) const;
    /// A model from sections written by saveState; throws InputError naming the section and what
    /// is inconsistent. `notes` receives what the user should know (plugin versions differ).
    static std::unique_ptr<Model> restoreState(SaveReader& r, PluginRegistry& registry,
                                               std::vector<std::string>& notes);

    // Internal types (core/src/model_internal.hpp).
    struct BallArrays;
    struct Pair;
    struct PairCold;
    struct Segment;
    struct WallData;
    struct Rule;
    struct ClumpData;
    struct ForceThreadPart;  // force_scratch.hpp

    /// Limits gathered by the force loop for the next automatic step (timestep.cpp): each the
    /// smallest over the pairs, the lowest pair index on a tie (`*_pair`, not saved), so that
    /// threads' partial limits merge to what one thread finds in pair order.
    struct StepLimits {
        double stability = std::numeric_limits<double>::infinity();
        double resolution = std::numeric_limits<double>::infinity();
        double approach = std::numeric_limits<double>::infinity();
        uint64_t stability_key = 0, resolution_key = 0, approach_key = 0;
        uint32_t stability_pair = UINT32_MAX, resolution_pair = UINT32_MAX,
                 approach_pair = UINT32_MAX;
        void merge(const StepLimits& o);
    };

    /// Direct read access for scene builders and diagnostics.
    const BallArrays& balls() const;

private:
    /// Refuses a solve time no run can reach (solveTime and solve{time}).
    void requireReachableTime(double duration) const;
    /// Whether the simulated time has landed on `end` (to round-off).
    bool reached(double end) const {
        return !(end - m_time > 1e-12 * std::max(1.0, std::fabs(end)));
    }
    void prepareRun();
    void runSteps(int64_t steps);

    // phases (one source file each)
    void computeTimestep();  // timestep.cpp
    void lawOfMotion();      // law_of_motion.cpp
    template <bool kGeneral>
    void moveBalls();  // law_of_motion.cpp
    void reportNonFiniteBall() const;
    void reportNonFiniteEnergy(double kinetic, double body, double damping, double driven) const;
    void moveClumps(double& kinetic, double& body, double& damping, double& driven);
    void gatherClumpForces();  // law_of_motion.cpp: pebble forces summed to the centroids
    void placePebbles(const ClumpData& c);
    void moveWalls();          // law_of_motion.cpp
    void servoWalls();         // wall_servo.cpp: servo velocities, before the walls move
    void detectContacts();     // contact_detection.cpp
    void forceDisplacement();  // force_displacement.cpp
    void bookkeeping();        // bookkeeping.cpp

    template <bool kAuto, bool kEnergy, bool kGuard>
    void forceLoop();  // force_displacement.cpp
    void prepareForceScratch(int nthreads, const FdBlock& tmpl);
    void buildIncidence();  // the balls' pairs in pair order, for the threads' gather
    // time-step limits gathered per pair (timestep.cpp)
    void noteApproach(const Pair& p, const PairCold& c, double gap, const Vec2& vrel, double accel,
                      const Vec2& normal, StepLimits& limits) const;
    void noteContact(const Pair& p, const PairCold& c, double kn, double ks, double kr,
                     double arm1_sq, double arm2_sq, double mass_eff);
    /// noteContact's limits alone (its stiffness sums are the caller's).
    void noteContactLimits(const Pair& p, const PairCold& c, double kn, double mass_eff,
                           StepLimits& limits) const;
    /// The approach limits of the pairs that were apart in this force loop, from the step's
    /// complete forces (force_displacement.cpp).
    void noteApproaches(const std::vector<uint32_t>& apart, StepLimits& limits) const;
    /// The per-ball sums of the threads' per-pair actions, in pair order (force_displacement.cpp).
    void gatherPairActions(int nthreads, bool automatic);
    void surveyPairs();
    /// For a pair with a pebble end off its clump's centroid: the lower bound of the true
    /// effective mass over the pair's (clump) effective mass, <= 1 (timestep.cpp); 1 otherwise.
    double pebbleMassRatio(const Pair& p) const;

    // helpers
    uint32_t slotOf(BallId id) const;  // throws InputError for a stale id
    const WallData& wallOf(WallId id) const;
    WallData& wallOf(WallId id);
    void updateMass(uint32_t slot);
    BallId createBallIn(const BallDef& def, uint32_t clump);  // clump: kNoClump for a free ball
    void removeBall(BallId id, bool book_energy);
    void refreshPairMasses(uint32_t slot);
    void initBroadphase();
    void insertBall(uint32_t slot);
    void insertSegment(uint32_t seg);
    Box ballBox(uint32_t slot) const;
    /// Ball against wall segment `seg` with the chain's shared-vertex rule (narrowphase.hpp).
    bool segmentGeometry(uint32_t seg, const Vec2& centre, double radius, ContactGeometry& g) const;
    /// The segment of seg's chain that holds a ball seg gives up (-1: none).
    int32_t wallHolder(uint32_t seg, const Vec2& centre, double radius) const;
    Box segmentBox(uint32_t seg) const;
    void addPairsForBall(uint32_t slot);
    void addPairsForSegment(uint32_t seg);
    void rebuildBallTree();
    void clearMovedFlags();
    bool makePair(uint32_t ball_slot, uint32_t other, bool other_is_segment);
    void removePair(std::size_t index);
    ContactModel* cloneFor(Pair& p);
    double tangentialInverseMass(const Pair& p) const;
    void refreshRule(Pair& p);
    void resetPair(Pair& p);
    void endContact(Pair& p, PairCold& c, bool check_guard);
    bool activate(Pair& p, PairCold& c, const ContactGeometry& g, const Vec2& vrel);
    bool handOverWallContact(std::size_t index);
    bool adoptWallContact(std::size_t index);
    void swapPairState(std::size_t i, std::size_t j);
    void queueBreak(std::size_t index, const Vec2& point, const FdBlock& fd);
    /// The same from the FdBlock's fields: the break mode, and the stresses at failure if the
    /// model gave them (kFdBreakStress).
    void queueBreak(std::size_t index, const Vec2& point, int32_t mode, bool with_stress,
                    double sigma, double tau);
    void noteDeepest(const Pair& p, PairCold& c, double force, double rate_after);
    [[noreturn]] void reportFailedLaw(const Pair& p, const FdBlock& fd) const;
    [[noreturn]] void findNonFiniteContact() const;
    [[noreturn]] void reportPassThrough(const Pair& p, const ContactGeometry& g) const;
    const Rule& ruleFor(uint64_t groups1, uint64_t groups2) const;
    PropBlock propBlockFor(const Pair& p) const;
    ContactInfo infoOf(std::size_t index) const;
    /// Geometry of a pair now (for queries): normal, overlap, contact point.
    bool pairGeometry(const Pair& p, Vec2& normal, double& overlap, Vec2& point) const;
    Pair* pairByKey(ContactKey key);
    const Pair* pairByKey(ContactKey key) const;
    std::size_t pairIndex(const Pair& p) const;  // index of a pair in m_pairs
    // Bonds (model_bonds.cpp): which pairs a bond call selects, and the memory of pairs whose
    // bond broke or was removed (a rule that bonds on touch, cbond's cb_bond, must not bond
    // them again: kFdNoAutoBond at their next first FDlaw).
    bool bondSelects(const Pair& p, const BondSettings& s, int ga, int gb) const;
    void forgetBond(std::size_t index);
    uint32_t autoBondFlags(const Pair& p, const PairCold& c) const;
    uint32_t m_activation_flags = 0;  // FdFlags for the contact activate() just made

    // Lanes (contact_lanes.cpp; docs/plugin-abi.md, "Lanes"): while a contact has a row in its
    // rule's lanes, the row holds its model's state and its object is out of date.
    /// Puts p into its rule's lanes if its model's lane law takes it now (after an FDlaw).
    bool enterLane(Pair& p);
    /// Brings p's object up to date from its row (before anything reads the object).
    void syncLane(const Pair& p) const;
    /// Takes p out of the lanes, its object up to date (before anything changes the object).
    void leaveLane(Pair& p);
    /// Frees p's row without updating the object (which is about to be destroyed).
    void dropLane(Pair& p);
    void leaveAllLanes();
    /// Every table's rows in the order of their pairs (after the pairs were sorted).
    void reorderLanes();

    void sortBalls();
    void repackContactObjects();
    void compactDeleted();
    void flushWarnings();
    void checkBalance();  // bookkeeping.cpp: the run-level energy check
    /// The ABI's energy contract for one FDlaw (rare path). `strain_old`, `bond_old`: what the
    /// contact stored before it; `totals`: the run's dissipation totals before this step.
    void checkEnergyContract(const Pair& p, double strain_old, double bond_old, const FdBlock& fd,
                             double fn_old, double fs_old, double m_old,
                             const EnergyTotals& totals);
    /// Notes a contact born overlapping; returns the placement energy to book (tracing on).
    double notePlacement(const Pair& p, const PairCold& c, double overlap, const FdBlock& fd,
                         bool energy);
    // --- per-group energy books (group_energy.cpp); run only while m_books.groups.on.
    void openGroupBooks();  // tracing switched on (or groups added): size and zero the books
    bool groupBooksOn() const { return m_books.groups.on; }
    /// Books a body's terms of this step to each of its groups (the law of motion; the clump
    /// pass calls it with a clump's mask): kinetic energy at the snapshot, body work, damping
    /// and fixity work (`driven`, split at the snapshot like the whole model's).
    void bookBodyToGroups(uint64_t mask, double kinetic, double body, double damping,
                          double driven) {
        auto* groups = m_books.groups.g.data();
        for (uint64_t m = mask & m_books.groups.traced; m; m &= m - 1) {
            auto& gr = groups[__builtin_ctzll(m)];
            gr.step_kinetic += kinetic;
            gr.step_body += body;
            gr.step_damping += damping;
            gr.step_driven += driven;
        }
    }
    /// The force loop's per-contact share (rare path: called only with groups traced).
    void bookContactToGroups(std::size_t i, const FdBlock& fd, bool first, bool ends, double held,
                             const Vec2& f, const Vec2& point);
    void bookReleasedToGroups(const Pair& p, double released);
    /// Kinetic energy that left the model with a deleted body (or changed at a clump release).
    void bookDeletedToGroups(uint64_t mask, double kinetic);
    /// A ball slot is being removed (deleted ball or pebble): mark its pending exchange records
    /// gone and follow the last slot, which moves into it.
    void followRemovedSlot(uint32_t slot);
    void groupForceLoopStart();       // zero the scratch, drop stale records
    void groupForceLoopEnd();         // strain/bond current values, baseline
    void gatherExchangeStart();       // law of motion: rates before the update
    void groupSnapshot(double lead);  // law of motion: split, snapshot, accumulate
    void bookWallToGroups(uint64_t mask, double work, double lead);
    /// Velocity and spin of a contact end (a ball slot) before and after the law of motion's
    /// update; the clump pass routes pebble ends to their clump here.
    void endRates(uint32_t slot, Vec2& v, double& w) const;
    /// The point an end's moments are taken about: a ball's centre, a pebble's clump centroid.
    Vec2 endCentre(uint32_t slot) const;
    uint64_t endGroups(const Pair& p, bool end2) const;
    [[noreturn]] void throwNonFinite(const std::string& what) const;
    std::string describePair(const Pair& p) const;
    std::string describeBall(uint32_t slot) const;

    // --- the two stores (core/src/body_store.hpp, core/src/contact_store.hpp): all bodies, all
    // pairs/rules/broadphase. Phases take references to their arrays before their loops.
    std::unique_ptr<BodyStore> m_bodies;
    std::unique_ptr<ContactStore> m_contacts;

    // --- settings and state
    PluginRegistry& m_registry;
    Vec2 m_gravity;
    MassMode m_mass_mode;
    TimestepSettings m_timestep;
    GuardSettings m_guard;
    DampingSettings m_damping;
    double m_time = 0.0;
    int64_t m_step = 0;
    double m_dt = 0.0;       // step taken by the last cycle
    double m_dt_prev = 0.0;  // step before it (for the velocity update window)
    double m_window = 0.0;   // time between the two half-step velocities of the last update
    StepRule m_dt_rule = StepRule::Fixed;
    struct StepWhere {  // what set the last step; turned into words only when asked
        enum Kind { None, Ball, Pair, Wall } kind = None;
        uint32_t index = 0;
        uint64_t key = 0;
    } m_dt_where;
    bool m_first_cycle = true;
    bool m_warned_no_model = false;
    std::vector<ClumpTemplate> m_clump_templates;
    std::size_t m_fixed_balls = 0;  // balls with any fixity bit (they need the general loop)
    TimestepSettings m_last_settings;
    bool m_limits_stale = true;  // the scene changed outside a cycle: survey before the next step
    Vec2 m_limits_gravity{0.0, 0.0};  // gravity the step limits were gathered with
    bool m_dt_idle = false;   // the last automatic step was idle: nothing moved or accelerated
    double m_step_cap = 0.0;  // solveTime: upper bound for the next step (0 = none)
    int64_t m_sort_every = 0;
    bool m_batched_law = true;
    bool m_lanes = false;    // setLanes
    int m_threads = 0;       // setThreads; 0 = TALUS_THREADS or 1
    int m_thread_grain = 0;  // setThreads; 0 = TALUS_THREAD_GRAIN or kDefaultThreadGrain
    int m_step_threads = 1;  // threads of the last force loop; the law of motion takes as many
    int m_servos_on = 0;     // walls with a servo switched on (wall_servo.cpp)

    StepLimits m_limits;  // for the next automatic step (timestep.cpp)

    // --- energy books (docs/physics/energy.md). Every energy sum of the model is accumulated
    // in this one struct: body, damping, boundary and kinetic by the law of motion
    // (law_of_motion.cpp), the contact items by the force loop (force_displacement.cpp), the
    // snapshot and the balance check by the bookkeeping (bookkeeping.cpp). Per-group books
    // belong next to `acc`.
    struct EnergyBooks {
        bool on = false;
        EnergyTotals acc;       // running sums
        EnergyTotals snapshot;  // at the last whole step (law_of_motion.cpp)
        // Contact dashpot work of the last force loop, split at the next snapshot like the
        // damping impulse (its impulse spans the window around the force's time level).
        double dashpot_pending = 0.0;
        // Tracing was switched on while contacts were loaded: the next force loop books what
        // they hold as initial_strain.
        bool strain_baseline_pending = false;
        // Placement energy of the contact the force loop just activated (notePlacement), for
        // the group shares.
        double last_placed = 0.0;
        // Per-group books (group_energy.cpp), sized to the group table while tracing is on and
        // at least one group exists; empty and never touched otherwise.
        struct GroupBooks {
            bool on = false;
            uint64_t traced = 0;  // mask of the groups with books
            // One record per group, all its sums together (one base pointer in the loops).
            struct Group {
                EnergyTotals acc, snapshot;
                double dashpot_pending = 0.0, exchanged_pending = 0.0;  // split at the snapshot
                double strain_now = 0.0, bond_now = 0.0, held_before = 0.0;  // force-loop scratch
                double step_kinetic = 0.0, step_body = 0.0, step_damping = 0.0,
                       step_driven = 0.0;  // law-of-motion scratch
            };
            std::vector<Group> g;
            // A contact between ends of different groups (or with a moving wall), pushed by the
            // force loop and consumed by the next law of motion: the force on end 1 (end 2
            // gets -f1), the moments about each end's centre, the masks, and the end rates
            // before the update (gatherExchangeStart). A ball deleted in between (a hook) marks
            // its end `gone` (its force is never applied).
            struct Exchange {
                uint32_t end1 = 0, end2 = 0;  // ball slots; end2 = wall index when `wall`
                bool wall = false, gone1 = false, gone2 = false;
                uint64_t g1 = 0, g2 = 0;
                Vec2 f1{0.0, 0.0};
                double m1 = 0.0, m2 = 0.0;
                Vec2 v1{0.0, 0.0}, v2{0.0, 0.0};
                double w1 = 0.0, w2 = 0.0;
            };
            std::vector<Exchange> exchange;
        } groups;
    } m_books;

    // --- guard state: findings aggregated into one warning per kind (bookkeeping.cpp reports).
    struct GuardState {
        int64_t underresolved = 0;
        std::string underresolved_first;
        int64_t energy_gain = 0;
        std::string energy_gain_first;
        int64_t stiffness_lies = 0;
        std::string stiffness_lies_first;
        int64_t placed = 0;  // contacts that started overlapping, since the last report
        double placed_energy = 0.0;
        std::string placed_first;
        // Run-level balance check: the snapshot at the last check that passed (the window a
        // finding names opens there), the peak mechanical energy, and the error last reported (a
        // finding is reported again only when it grows by another tolerance).
        struct BalanceWatch {
            EnergyTotals open;
            int64_t open_step = 0;
            double peak = 0.0;
            double reported = 0.0;
            int64_t findings = 0;
            std::string first, last;
        } balance;
    } m_guard_state;

    // --- hooks and events
    struct Hook {
        int handle;
        int64_t every;
        std::function<void(Model&)> fn;
    };
    std::vector<Hook> m_hooks;
    int m_next_hook = 1;
    int m_hooks_running = 0;
    std::vector<Event> m_events;
    bool m_contact_events = false;
    std::function<void(const Event&)> m_event_handler;
    std::function<void(const std::string&)> m_warning_handler;
    std::vector<std::string> m_group_names;

    Profile m_profile;
    std::function<void(const Model&)> m_step_observer;  // setStepObserver
    FdBlock m_fd_template{};
};

}  // namespace talus
