// SPDX-License-Identifier: MIT
//
// The plain data a Model is built and asked with: the ...Def structs that create bodies, the
// settings (time step, guard, damping, servo, bonds), and what queries return (contacts,
// measurements, events). The Model facade is in talus/model.hpp.
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
#include "talus/vec.hpp"

namespace talus {

class Model;

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

/// Wall servo (PFC "wall servo"; core/src/step/wall_servo.cpp, docs/lua-api.md "Servo walls").
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

/// A measurement region (PFC measurement circle; core/src/api/measure.cpp).
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

/// Unbalanced force (PFC's mechanical ratio; core/src/api/measure.cpp).
struct UnbalancedForce {
    double mean_unbalanced = 0.0;  ///< mean |net force| over the free bodies [N]
    double max_unbalanced = 0.0;
    double mean_contact = 0.0;  ///< mean |contact force| over the contacts that carry one [N]
    double ratio = 0.0;         ///< mean_unbalanced / mean_contact (inf: no contact force)
    int64_t bodies = 0, contacts = 0;
};

/// m:solve's criteria (Model::solve, core/src/api/solve.cpp). Unset ones (NaN, -1, empty) are off;
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

/// m:bond{...} (core/src/api/bonds.cpp; docs/lua-api.md, "Bonds"): one property of the bond
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
    /// per contact duration at the stiffness the model reported (An 2006: 10-20 per impact).
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
    /// Severe findings, which no sound run makes (docs/physics/guard.md, "Severe findings"): a
    /// check set to Warn stops the run with its error at once when its finding passes these
    /// (`severe = Warn` reports them as warnings). Energy created above `severe_created` of the
    /// throughput (the balance check, while tracing) or of the scene's energy (a contact that
    /// gave back more than it took), a contact with fewer than `severe_min_steps` steps per
    /// duration.
    GuardAction severe = GuardAction::Error;
    double severe_created = 0.1;
    int severe_min_steps = 3;
    /// The memory a model may take [bytes]; 0: what the machine has (MemAvailable in
    /// /proc/meminfo), checked before a model grows (docs/physics/guard.md, "Memory").
    double memory_limit = 0.0;

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
    double local = 0.0;  ///< PFC local damping coefficient alpha (the PFC2D manual)
    /// Mass-proportional viscous damping [1/s]: F = -viscous m v, integrated implicitly at the
    /// time level of the contact forces (Nejati 2008, eq. 2.41).
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
    /// Bond breaks: the bond's half width [m] (its radius: a crack across it is 2 radius long),
    /// read from the model as the bond broke: its property `bond_radius`, `pb_rad` (a parallel
    /// bond) or `fj_radius` (a flat joint), the first it has (docs/plugin-abi.md, "Bonds"); NaN
    /// when it has none (a contact bond has no size of its own). Not saved: NaN for an event
    /// still queued at a save.
    double radius = std::numeric_limits<double>::quiet_NaN();
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

// ------------------------------------------------------------------ trackers

/// What a tracker counts as an impact (TrackerDef::impacts).
enum class TrackImpacts { Off, Walls, Bodies, Any };

/// A line a tracked body's centre may cross (TrackerDef::lines). A crossing is a step that takes
/// the centre from the left of the directed line from -> to to its right (the side its
/// right-hand normal points to), the crossing point within the segment; every such step counts.
struct TrackLine {
    Vec2 from{0.0, 0.0}, to{0.0, 0.0};
    /// Deliver the crossing as a TrackerEvent during the step, before the rest of the step's
    /// sample is taken, so that the handler can change the body's motion or stop the tracker.
    bool event = false;
};

/// A per-body tracker (Model::createTracker; docs/lua-api.md, "Trackers"): what the engine
/// records about one ball or clump at every step, so that a script need not look at every
/// contact and every body each step. Unset parts cost nothing.
struct TrackerDef {
    /// Impacts: a touch begins at the first step the body touches something of the kind
    /// (positive overlap) after touching nothing of it; it ends at the first step it touches
    /// nothing of it again.
    TrackImpacts impacts = TrackImpacts::Off;
    double impact_min_speed = 0.0;  ///< [m/s] touches approaching slower are not recorded
    std::vector<TrackLine> lines;
    /// Rest: the kinetic energy (translation and rotation) below `rest_energy`, or the centre's
    /// speed below `rest_speed`, for `rest_time` seconds; the tracker then ends. NaN: off.
    double rest_energy = kNotSet;  ///< [J]
    double rest_speed = kNotSet;   ///< [m/s]
    double rest_time = 0.0;        ///< [s]
    /// The tracker ends ("exit") at the first step the centre is outside [lo, hi].
    bool region = false;
    Vec2 region_lo{0.0, 0.0}, region_hi{0.0, 0.0};
    /// The tracker ends ("time") at the first step at or after this time [s].
    double end_time = std::numeric_limits<double>::infinity();
    /// Envelope: per bin k of x in [x0 + k dx, x0 + (k + 1) dx), the greatest height of the
    /// centre above the polyline `ground` (x not decreasing) and the greatest kinetic energy.
    std::vector<Vec2> ground;
    double envelope_x0 = 0.0, envelope_dx = 0.0;
    int32_t envelope_bins = 0;  ///< 0: no envelope
    int64_t path_every = 0;     ///< > 0: the centre every so many samples
};

/// Where a tracker is: still tracking, or why it ended.
enum class TrackerState { Tracking, Rest, Exit, Time, Deleted, Stopped };
const char* trackerStateName(TrackerState s);

/// The state of a tracked body at one sample (the end of a step): time, centre, velocity at the
/// half step (as the body reports it), spin.
struct TrackedState {
    double time = 0.0;
    Vec2 pos{0.0, 0.0};
    Vec2 vel{0.0, 0.0};
    double spin = 0.0;
};

/// A touch (TrackerDef::impacts). `start` is the body at the first step of the touch, its
/// velocity the incoming one (the contact's first force acts on the next step); `end` at the
/// first step without a touch (`ended`), or at the tracker's last sample when it ended first.
struct TrackedImpact {
    TrackedState start;
    Vec2 normal{0.0, 0.0};  ///< unit, from what was hit toward the body
    double approach = 0.0;  ///< -vel . normal [m/s], > 0 when approaching
    Vec2 point{0.0, 0.0};   ///< the contact point
    WallId wall;            ///< what was hit: a wall segment ...
    int32_t segment = -1;
    BallId ball;          ///< ... or a ball (a pebble: `clump` is its clump)
    ClumpId clump;        ///<
    uint64_t groups = 0;  ///< group bits of what was hit (Model::groupNames)
    bool closed = false;  ///< `end` is set: the touch ended, or the tracker ended first
    bool ended = false;   ///< the touch ended (the body touched nothing of the kind)
    TrackedState end;
};

/// A line crossing (TrackerDef::lines), interpolated within the step: the path between two
/// samples is the parabola of constant acceleration through both (gravity in free flight,
/// else the change of the velocity over the step).
struct TrackedCrossing {
    int32_t line = 0;
    double time = 0.0;
    Vec2 pos{0.0, 0.0};
    Vec2 vel{0.0, 0.0};
    double spin = 0.0;
    double ke_trans = 0.0, ke_rot = 0.0;  ///< [J]
};

/// A barrier (Model::createBarrier; docs/rockfall.md, "Barriers"): a segment with an energy
/// capacity, such as a rockfall fence or net. A body (a free ball or a clump) is judged at the
/// first crossing of its centre over the segment's line from left to right (looking from `from` to
/// `to`) above the foot; it is caught if its equivalent disk touches the segment there (the
/// crossing point within its radius of the segment; higher, it passes over the top): with more
/// kinetic energy than `energy` it goes on with `energy` taken from it (velocity and spin scaled by
/// sqrt((KE - energy) / KE)); otherwise it is stopped (velocity and spin zero, fixed in x, y and
/// rotation). What it loses is the energy item `barrier`.
struct BarrierDef {
    std::string name;
    Vec2 from{0.0, 0.0}, to{0.0, 0.0};
    double energy = 0.0;  ///< capacity [J]
};

/// A barrier's record: what it caught (Model::barrierInfo).
struct BarrierInfo {
    BarrierDef def;
    int64_t passed = 0;     ///< bodies slowed that went on
    int64_t stopped = 0;    ///< bodies stopped
    double absorbed = 0.0;  ///< the kinetic energy it took, as the crossings' states give it [J]
};

/// A point of a tracker's path (TrackerDef::path_every).
struct TrackedPoint {
    double time = 0.0;
    Vec2 pos{0.0, 0.0};
};

/// A tracker's summary: its body, its state, where and when it ended, the rest it detected.
struct TrackerStatus {
    BallId ball;  ///< the tracked ball, or
    ClumpId clump;
    TrackerState state = TrackerState::Tracking;
    int64_t samples = 0;
    TrackedState last;            ///< the last sample taken
    double rest_since = kNotSet;  ///< [s] start of the slow spell that ended it (or is running)
};

/// Delivered to the tracker handler (Model::setTrackerHandler) during the step's bookkeeping.
struct TrackerEvent {
    enum Kind { Crossing, End } kind = Crossing;
    int tracker = 0;
    int32_t line = -1;  ///< Crossing: TrackerDef::lines index; its record is the last one
    TrackerState state = TrackerState::Tracking;  ///< End: why
};

}  // namespace talus
