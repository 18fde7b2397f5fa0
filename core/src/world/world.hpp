// SPDX-License-Identifier: MIT
//
// The world: everything a model is, as plain data (Box2D v3's b2World). `Model`
// (talus/model.hpp) is the facade scripts and tests talk to; it owns one World and nothing
// else. The phases of a step (step.hpp) and the operations behind the facade are free
// functions over the world, so that a helper added to a phase recompiles the engine, not its
// users. Not installed.
//
//   World
//    |- bodies      BodyStore: balls, clumps, walls, group names         (body_store.hpp)
//    |- contacts    ContactStore: pairs, rules, broadphase, loop scratch (contact_store.hpp)
//    |- settings    what the user set: gravity, time step, guard, damping, threads
//    |- clock       time, step number, the last steps and their window
//    |- stepping    the automatic step's state: its rule, its limits
//    |- books       energy books (docs/physics/energy.md)
//    |- guard_state the guard's aggregated findings (docs/physics/guard.md)
//    |- callbacks   cycle hooks, events, warning and step observers
//    |- trackers    per-body records taken every step                    (trackers.hpp)
//    |- servos      walls moved to hold a target, set every step          (servo_store.hpp)
//    `- profile     time per phase
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include "talus/energy.hpp"
#include "talus/model.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/profile.hpp"
#include "world/barriers.hpp"
#include "world/body_store.hpp"
#include "world/contact_store.hpp"
#include "world/servo_store.hpp"
#include "world/trackers.hpp"
#include "world/types.hpp"

namespace talus {

/// What the user set (m:gravity, m:timestep, m:guard, m:damping, m:threads, ...).
struct Settings {
    Vec2 gravity{0.0, 0.0};
    MassMode mass_mode = MassMode::Disk;
    TimestepSettings timestep;
    GuardSettings guard;
    DampingSettings damping;
    int64_t sort_every = Model::kSortAuto;  // re-order the balls every N steps (0: never)
    // The host's kernels of the shipped models' laws (force/runners.hpp); off (tests and
    // measurements only: testing/force_switches.hpp) runs their FDlaw.
    bool kernels = true;
    int threads = 0;       // 0 = TALUS_THREADS or 1
    int thread_grain = 0;  // 0 = TALUS_THREAD_GRAIN or Model::kDefaultThreadGrain
};

/// Simulated time and the steps that led to it.
struct Clock {
    double time = 0.0;
    int64_t step = 0;
    double dt = 0.0;       // step taken by the last cycle
    double dt_prev = 0.0;  // step before it (for the velocity update window)
    double window = 0.0;   // time between the two half-step velocities of the last update
    bool first_cycle = true;
    int threads = 1;  // threads of the last force loop; the law of motion takes as many
    // A cycle or solve call is under way (api/model.cpp, RunLock): a callback that runs the
    // model again is refused, as Box2D locks its world during callbacks.
    bool running = false;
};

/// What set the last step; turned into words only when asked (Model::lastStepReason).
struct StepWhere {
    enum Kind { None, Ball, Pair, Wall } kind = None;
    uint32_t index = 0;
    uint64_t key = 0;
};

/// The automatic step's state (timestep.cpp).
struct Stepping {
    StepRule rule = StepRule::Fixed;
    StepWhere where;
    TimestepSettings last_settings;
    bool limits_stale = true;       // the scene changed outside a cycle: survey first
    Vec2 limits_gravity{0.0, 0.0};  // gravity the step limits were gathered with
    bool idle = false;              // the last step was idle: nothing moved or accelerated
    double cap = 0.0;               // solveTime: upper bound for the next step (0 = none)
    StepLimits limits;              // for the next automatic step, from the force loop
    bool guard_was_on = true;       // the guard's per-contact checks ran at the last step
    // The contacts' cold estimates (PairCold::knest, ksest) were not kept by the last force loop
    // (a fixed step): the next survey asks the models.
    bool estimates_stale = false;
};

/// A body's motion as the law of motion takes it from between two steps: what the next energy
/// snapshot books for it follows from this, the gravity and the damping (step/script_work.cpp).
struct BodyMotion {
    double mass = 0.0, inv_mass = 0.0, inertia = 0.0, inv_inertia = 0.0;
    Vec2 vel{0.0, 0.0};
    double spin = 0.0;
    Vec2 force{0.0, 0.0};  // contact force of the last force loop plus the applied force
    double moment = 0.0;   // likewise
    uint8_t fixity = 0;
    uint64_t groups = 0;
};

/// A body the script changed since the last step, as it was before (ScriptChanges).
struct ScriptBody {
    uint32_t index = 0;       // a ball's handle index, or a clump's index
    uint32_t generation = 0;  // a ball's generation
    bool clump = false;
    bool existed = false;  // it was there before the change (not added since)
    bool deleted = false;  // deleted since: `gone` is its motion then
    bool barrier = false;  // changed by a barrier (step/barriers.cpp): booked as `barrier`
    BodyMotion before, gone;
};

/// Energy books (docs/physics/energy.md). Every energy sum of the model is accumulated here:
/// body, damping, boundary and kinetic by the law of motion (law_of_motion.cpp), the contact
/// items by the force loop (force/loop.cpp), the snapshot and the balance check by the
/// bookkeeping (bookkeeping.cpp). Per-group books belong next to `acc`.
struct EnergyBooks {
    bool on = false;
    EnergyTotals acc;       // running sums
    EnergyTotals snapshot;  // at the last whole step (law_of_motion.cpp)
    // Contact dashpot work of the last force loop, split at the next snapshot like the damping
    // impulse (its impulse spans the window around the force's time level).
    double dashpot_pending = 0.0;
    // Tracing was switched on while contacts were loaded: the next force loop books what they
    // hold as initial_strain. (Not set since the books open as `opening` says; kept for the
    // force loop's path that reads it.)
    bool strain_baseline_pending = false;
    // Tracing was just switched on (api/energy.cpp). The books open at a whole step where the
    // kinetic energy and what the contacts hold are both known (law_of_motion.cpp, openBooks):
    // 1: at the next snapshot (no contact was active); 2: at the one after, once the contacts'
    // models have reported what they hold (the next snapshot waits: it books nothing).
    // 0: open.
    int opening = 0;
    // What the last snapshot did with the impulses that span it: booked their part before it
    // (Open), only the part after it (Opened: the books opened there), or nothing (Waiting: the
    // books open at the next one; group_energy.cpp and the energy contract's check read it).
    enum class Stage : uint8_t { Open, Opened, Waiting } stage = Stage::Open;
    // Placement energy of the contact the force loop just activated (notePlacement), for the
    // group shares.
    double last_placed = 0.0;
    // What the script changed since the last step (step/script_work.cpp): each body as it was
    // before its first change, and the gravity and damping the last step used. Booked as
    // `script` at the start of the next step, when the step's length is known.
    struct ScriptChanges {
        std::vector<ScriptBody> bodies;
        std::unordered_map<uint64_t, std::size_t> index;  // body key -> entry in `bodies`
        bool seen = false;  // gravity and damping below are the last step's
        Vec2 gravity{0.0, 0.0};
        DampingSettings damping;
    } script;
    // Per-group books (group_energy.cpp), sized to the group table while tracing is on and at
    // least one group exists; empty and never touched otherwise.
    struct GroupBooks {
        bool on = false;
        uint64_t traced = 0;  // mask of the groups with books
        // One record per group, all its sums together (one base pointer in the loops).
        struct Group {
            EnergyTotals acc, snapshot;
            double dashpot_pending = 0.0, exchanged_pending = 0.0;       // split at the snapshot
            double strain_now = 0.0, bond_now = 0.0, held_before = 0.0;  // force-loop scratch
            double step_kinetic = 0.0, step_body = 0.0, step_damping = 0.0,
                   step_driven = 0.0;  // law-of-motion scratch
        };
        std::vector<Group> g;
        // A contact between ends of different groups (or with a moving wall), pushed by the
        // force loop and consumed by the next law of motion: the force on end 1 (end 2 gets
        // -f1), the moments about each end's centre, the masks, and the end rates before the
        // update (gatherExchangeStart). A ball deleted in between (a hook) marks its end `gone`
        // (its force is never applied).
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
};

/// The guard's findings, aggregated into one warning per kind (bookkeeping.cpp reports them).
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
    bool warned_no_model = false;
    // Contacts that gave back more than `energy_tolerance` of what they took, found at their
    // end in the force loop; judged at the step's end against the scene's energy
    // (bookkeeping.cpp, judgeEnergyGains), then cleared.
    struct EnergyGain {
        double gained = 0.0;  // [J]
        std::string what;
    };
    std::vector<EnergyGain> energy_gains;
    // Off while a routine overlaps bodies on purpose (Model::setPlacementWarning): contacts that
    // start overlapping are booked as placement but not reported. Not saved (a run-time switch).
    bool placement_warning = true;
    // Balls whose memory (their contacts' included) the last check counted (api/memory.cpp):
    // the balls added since are the ones a run has yet to make room for. Not saved.
    std::size_t memory_counted_balls = 0;
    // Run-level balance check: the snapshot at the last check that passed (the window a finding
    // names opens there), the peak mechanical energy, and the error last reported (a finding is
    // reported again only when it grows by another tolerance).
    struct BalanceWatch {
        EnergyTotals open;
        int64_t open_step = 0;
        double peak = 0.0;
        double reported = 0.0;
        int64_t findings = 0;
        std::string first, last;
    } balance;
};

/// A function run every `every` steps in the bookkeeping phase (Model::addCycleHook).
struct Hook {
    int handle;
    int64_t every;
    std::function<void(Model&)> fn;
};

/// What the world calls back: hooks, event and warning handlers, the step observer.
struct Callbacks {
    std::vector<Hook> hooks;
    int next_hook = 1;
    int hooks_running = 0;
    std::vector<Event> events;
    bool contact_events = false;
    std::function<void(const Event&)> event_handler;
    std::function<void(const std::string&)> warning_handler;
    std::function<void(const Model&)> step_observer;
};

struct World {
    World(Model& facade, PluginRegistry& registry) : facade(facade), registry(registry) {}
    World(const World&) = delete;
    World& operator=(const World&) = delete;

    Model& facade;  // the Model that owns this world: hooks and observers receive it
    PluginRegistry& registry;
    BodyStore bodies;
    ContactStore contacts;
    Settings settings;
    Clock clock;
    Stepping stepping;
    EnergyBooks books;
    GuardState guard_state;
    Callbacks callbacks;
    Trackers trackers;
    ServoStore servos;
    Barriers barriers;
    Profile profile;
};

/// The world behind a facade (for the engine's own files and its white-box tests).
World& worldOf(Model& model);
const World& worldOf(const Model& model);

}  // namespace talus
