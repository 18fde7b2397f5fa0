// SPDX-License-Identifier: MIT
//
// Model, the facade: construction, group names, the cycle driver (cycle, solveTime) and
// warnings. What it faces is split by file (docs/architecture.md, "where things are"):
//   model_bodies.cpp    the ball and wall API (create, delete, read and set state)
//   model_contacts.cpp  contact-model rules and the contact queries
// The data lives in the two stores (body_store.hpp, contact_store.hpp); the phases of a cycle
// are in timestep.cpp, law_of_motion.cpp, contact_detection.cpp, force_displacement.cpp and
// bookkeeping.cpp.
#include "talus/model.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "body_store.hpp"
#include "broadphase.hpp"
#include "contact_store.hpp"
#include "engine.hpp"
#include "model_internal.hpp"
#include "narrowphase.hpp"
#include "props.hpp"
#include "talus/errors.hpp"
#include "talus/run_control.hpp"

namespace talus {

namespace {
using WallClock = std::chrono::steady_clock;
}  // namespace

const char* stepRuleName(StepRule r) {
    switch (r) {
        case StepRule::Fixed:
            return "fixed";
        case StepRule::Stability:
            return "stability";
        case StepRule::Resolution:
            return "resolution";
        case StepRule::Approach:
            return "approach";
        case StepRule::Kinematic:
            return "kinematic";
        case StepRule::Max:
            return "max";
        case StepRule::Growth:
            return "growth";
        case StepRule::Idle:
            return "idle";
        case StepRule::Damping:
            return "damping";
    }
    return "?";
}

std::string vecText(const Vec2& v) {
    return "(" + messageNumber(v.x()) + ", " + messageNumber(v.y()) + ")";
}

std::string messageNumber(double v, int digits) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

// ------------------------------------------------------------------------ construction

Model::Model(const ModelDef& def, PluginRegistry& registry)
    : m_world(std::make_unique<World>(*this, registry)) {
    World& world = *m_world;
    if (!std::isfinite(def.gravity.x()) || !std::isfinite(def.gravity.y()))
        throw InputError("model: gravity must be finite");
    world.settings.gravity = def.gravity;
    world.settings.mass_mode = def.mass_mode;
    // Rule 0 is the default; until set it is "none" (no contacts are created).
    auto none = std::make_unique<Rule>();
    none->model_name = "";
    world.contacts.rules.push_back(std::move(none));
    world.contacts.fd_template.size = sizeof(FdBlock);
    world.contacts.fd_template.version = TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR;
    world.callbacks.warning_handler = [](const std::string& text) {
        std::cerr << "warning: " << text << "\n";
    };
}

Model::~Model() {
    for (auto& p : m_world->contacts.pairs) {
        if (p.model) {
            p.model->Destroy();
            p.rule->pool->release(p.model);
        }
    }
}

World& worldOf(Model& model) { return *model.m_world; }
const World& worldOf(const Model& model) { return *model.m_world; }

int Model::groupIndex(const std::string& name, bool create) {
    return talus::groupIndex(*m_world, name, create);
}

int groupIndex(World& world, const std::string& name, bool create) {
    for (std::size_t i = 0; i < world.bodies.group_names.size(); ++i)
        if (world.bodies.group_names[i] == name) return static_cast<int>(i);
    if (!create) return -1;
    if (world.bodies.group_names.size() >= 64)
        throw InputError("group '" + name + "': a model holds at most 64 group names");
    world.bodies.group_names.push_back(name);
    if (world.books.on) openGroupBooks(world);  // the new group's books start empty
    return static_cast<int>(world.bodies.group_names.size() - 1);
}

const std::vector<std::string>& Model::groupNames() const { return m_world->bodies.group_names; }
double Model::broadphaseMargin() const { return m_world->contacts.margin; }

double Model::time() const { return m_world->clock.time; }
int64_t Model::step() const { return m_world->clock.step; }
double Model::lastTimestep() const { return m_world->clock.dt; }
StepRule Model::lastStepRule() const { return m_world->stepping.rule; }
TimestepSettings& Model::timestep() { return m_world->settings.timestep; }
GuardSettings& Model::guard() { return m_world->settings.guard; }
DampingSettings& Model::damping() { return m_world->settings.damping; }
Vec2& Model::gravity() { return m_world->settings.gravity; }
MassMode Model::massMode() const { return m_world->settings.mass_mode; }
bool Model::energyTracing() const { return m_world->books.on; }
Profile& Model::profile() { return m_world->profile; }
const Profile& Model::profile() const { return m_world->profile; }
void Model::setSortInterval(int64_t every) { m_world->settings.sort_every = every; }
bool Model::batchedLaw() const { return m_world->settings.batched_law; }
bool Model::lanes() const { return m_world->settings.lanes; }

void Model::setEventHandler(std::function<void(const Event&)> fn) {
    m_world->callbacks.event_handler = std::move(fn);
}
void Model::enableContactCreatedEvents(bool on) { m_world->callbacks.contact_events = on; }
void Model::setWarningHandler(std::function<void(const std::string&)> fn) {
    m_world->callbacks.warning_handler = std::move(fn);
}
void Model::setStepObserver(std::function<void(const Model&)> fn) {
    m_world->callbacks.step_observer = std::move(fn);
}
void Model::warn(const std::string& text) { talus::warn(*m_world, text); }

// ------------------------------------------------------------------------ the cycle

void prepareRun(World& world) {
    // Ctrl-C came before this run call (run_control.hpp): take no step.
    if (stopRequested())
        throw Interrupted("interrupted (Ctrl-C) before step " +
                              std::to_string(world.clock.step + 1) +
                              " (t = " + messageNumber(world.clock.time) + " s)",
                          true);
    if (!world.contacts.broadphase_ready) initBroadphase(world);
    const TimestepSettings& t = world.settings.timestep;
    if (t.automatic != world.stepping.last_settings.automatic ||
        t.safety != world.stepping.last_settings.safety ||
        t.resolution != world.stepping.last_settings.resolution)
        world.stepping.limits_stale = true;
    world.stepping.last_settings = t;
    for (auto& r : world.contacts.rules)
        if (r->prototype) {
            PropBlock pb = emptyPropBlock();
            if (const char* err = r->prototype->PreCycle(pb))
                throw InputError("contact model '" + r->model_name + "': " + err);
        }
    if (!world.contacts.rules[0]->prototype && world.contacts.rules.size() == 1 &&
        world.facade.ballCount() > 0 && !world.guard_state.warned_no_model) {
        world.guard_state.warned_no_model = true;
        talus::warn(
            world,
            "no contact model is set (contact_model{...}): bodies will pass through each other");
    }
}

void runSteps(World& world, int64_t steps) {
    using std::chrono::duration;
    const bool prof = world.profile.enabled;
    for (int64_t i = 0; i < steps; ++i) {
        // The PFC cycle (seed digest section 1), each phase timed into world.profile.
        WallClock::time_point t0, t1;
        if (prof) t0 = WallClock::now();
        computeTimestep(world);
        if (prof)
            t1 = WallClock::now(), world.profile.timestep += duration<double>(t1 - t0).count(),
            t0 = t1;
        // Servo walls set their velocity from the last force loop and this step's dt.
        if (world.bodies.servos_on) servoWalls(world);
        lawOfMotion(world);
        moveWalls(world);
        if (prof)
            t1 = WallClock::now(), world.profile.motion += duration<double>(t1 - t0).count(),
            t0 = t1;
        detectContacts(world);
        if (prof)
            t1 = WallClock::now(), world.profile.detection += duration<double>(t1 - t0).count(),
            t0 = t1;
        forceDisplacement(world);
        if (prof)
            t1 = WallClock::now(),
            world.profile.force_displacement += duration<double>(t1 - t0).count(), t0 = t1;
        bookkeeping(world);
        if (prof)
            t1 = WallClock::now(), world.profile.bookkeeping += duration<double>(t1 - t0).count();
        ++world.profile.cycles;
        if (world.callbacks.step_observer) world.callbacks.step_observer(world.facade);
        // Ctrl-C (run_control.hpp): the step is complete, so the model is consistent here. One
        // relaxed atomic load per step: nothing next to a step's cost.
        if (stopRequested())
            throw Interrupted("interrupted (Ctrl-C) at step " + std::to_string(world.clock.step) +
                                  " (t = " + messageNumber(world.clock.time) + " s)",
                              false);
    }
}

void Model::cycle(int64_t steps) {
    World& world = *m_world;
    if (steps < 0) throw InputError("cycle: number of steps must be >= 0");
    prepareRun(world);
    try {
        runSteps(world, steps);
    } catch (...) {
        flushWarnings(world);
        throw;
    }
    flushWarnings(world);
}

void requireReachableTime(const World& world, double duration) {
    if (!(duration >= 0.0) || !std::isfinite(duration))
        throw InputError("solve: time must be >= 0 (got " + messageNumber(duration) + ")");
    // A duration no run can reach is refused rather than cycled for ever with no sign of life
    // (issue 6, item 12): beyond 1e9 s (32 years), and beyond 1e12 steps at a fixed step.
    if (duration > 1e9)
        throw InputError("solve: time " + messageNumber(duration) +
                         " s cannot be reached in a sane number of steps (at most 1e9 s per "
                         "solve; call solve repeatedly for longer runs)");
    if (!world.settings.timestep.automatic && world.settings.timestep.fixed > 0.0 &&
        duration / world.settings.timestep.fixed > 1e12)
        throw InputError("solve: time " + messageNumber(duration) + " s needs " +
                         messageNumber(duration / world.settings.timestep.fixed) +
                         " steps of the fixed step " +
                         messageNumber(world.settings.timestep.fixed) + " s (more than 1e12)");
}

void Model::solveTime(double duration) {
    // solve{time} alone lands exactly on the end time (solve.cpp).
    SolveSpec spec;
    spec.time = duration;
    solve(spec);
}

std::string Model::lastStepReason() const {
    const World& world = *m_world;
    std::string s = std::string(stepRuleName(world.stepping.rule)) +
                    " rule, dt = " + messageNumber(world.clock.dt) + " s";
    std::string where;
    switch (world.stepping.where.kind) {
        case StepWhere::Ball:
            if (world.stepping.where.index < ballCount())
                where = world.bodies.describeBall(world.stepping.where.index);
            break;
        case StepWhere::Pair:
            if (const Pair* p = world.contacts.pairByKey(ContactKey{world.stepping.where.key}))
                where = describePair(world, *p);
            break;
        case StepWhere::Wall:
            where = "wall " + std::to_string(world.stepping.where.index + 1);
            break;
        case StepWhere::None:
            break;
    }
    if (!where.empty()) s += " (" + where + ")";
    return s;
}

void warn(World& world, const std::string& text) {
    if (world.callbacks.warning_handler) world.callbacks.warning_handler(text);
}

void throwNonFinite(const World& world, const std::string& what) {
    throw NumericalError("non-finite state at step " + std::to_string(world.clock.step) +
                         " (t = " + messageNumber(world.clock.time) + " s): " + what);
}

}  // namespace talus
