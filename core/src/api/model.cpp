// SPDX-License-Identifier: MIT
//
// The facade, the model itself: construction, settings, group names, running (cycle, solveTime),
// callbacks and warnings, and the performance settings (threads, the memory order, the
// profile). The other things it faces have a file each in api/ (balls, walls, clumps, contacts,
// bonds, energy, measure, solve, save); the world it holds is world/world.hpp, the step it runs
// step/step.cpp.
#include "talus/model.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "api/first_call.hpp"
#include "api/operations.hpp"
#include "force/force.hpp"
#include "props.hpp"
#include "step/group_energy.hpp"
#include "step/narrowphase.hpp"
#include "step/step.hpp"
#include "talus/errors.hpp"
#include "talus/run_control.hpp"
#include "world/body_store.hpp"
#include "world/broadphase.hpp"
#include "world/capacity.hpp"
#include "world/contact_store.hpp"
#include "world/messages.hpp"
#include "world/types.hpp"

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

// ------------------------------------------------------------------------ construction

Model::Model(const ModelDef& def, PluginRegistry& registry)
    : m_world(std::make_unique<World>(*this, registry)) {
    mapLargeBlocks();
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
    ContactStore& cs = m_world->contacts;
    for (std::size_t i = 0; i < cs.pairs.size(); ++i) {
        if (ContactModel* model = cs.pairs[i].model) {
            model->Destroy();
            cs.ruleOf(cs.pairs[i]).pool->release(model);
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
bool Model::setPlacementWarning(bool on) {
    const bool was = m_world->guard_state.placement_warning;
    m_world->guard_state.placement_warning = on;
    return was;
}
bool Model::placementWarning() const { return m_world->guard_state.placement_warning; }
DampingSettings& Model::damping() { return m_world->settings.damping; }
Vec2& Model::gravity() { return m_world->settings.gravity; }
MassMode Model::massMode() const { return m_world->settings.mass_mode; }
bool Model::energyTracing() const { return m_world->books.on; }
Profile& Model::profile() { return m_world->profile; }
const Profile& Model::profile() const { return m_world->profile; }
void Model::setSortInterval(int64_t every) {
    if (every < kSortAuto)
        throw InputError("sort interval: expected steps >= 0, or automatic (got " +
                         std::to_string(every) + ")");
    m_world->settings.sort_every = every;
}
int64_t Model::sortInterval() const { return m_world->settings.sort_every; }

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
// ------------------------------------------------------------------------ the cycle

RunLock::RunLock(World& world, const char* what) : m_world(world) {
    if (world.clock.running)
        throw InputError(std::string(what) +
                         ": the model is already running (called from a callback, at step " +
                         std::to_string(world.clock.step) +
                         " of a cycle or solve call): a callback may read and change the model "
                         "but not run it; stop the run (solve{[\"until\"] = fn}) and run again "
                         "after it");
    world.clock.running = true;
}

void Model::cycle(int64_t steps) {
    World& world = *m_world;
    if (steps < 0) throw InputError("cycle: number of steps must be >= 0");
    const RunLock lock(world, "cycle");
    requireMemory(world, world.bodies.balls.size(), "cycle");
    world.guard_state.memory_counted_balls = world.bodies.balls.size();
    prepareRun(world);
    try {
        firstCallsAtPlacement(world);
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
    // (beyond 1e9 s, 32 years, and beyond 1e12 steps at a fixed step).
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

int Model::addCycleHook(int64_t every, std::function<void(Model&)> fn) {
    World& world = *m_world;
    if (every <= 0) throw InputError("hook: 'every' must be >= 1");
    world.callbacks.hooks.push_back(Hook{world.callbacks.next_hook, every, std::move(fn)});
    return world.callbacks.next_hook++;
}

void Model::removeCycleHook(int handle) {
    World& world = *m_world;
    for (std::size_t i = 0; i < world.callbacks.hooks.size(); ++i)
        if (world.callbacks.hooks[i].handle == handle) {
            if (world.callbacks.hooks_running > 0)
                world.callbacks.hooks[i].every = 0;  // erased after the hooks of this step have run
            else
                world.callbacks.hooks.erase(world.callbacks.hooks.begin() +
                                            static_cast<std::ptrdiff_t>(i));
            return;
        }
}

std::string Profile::report(std::size_t balls) const {
    std::ostringstream os;
    const double tot = total();
    auto line = [&](const char* name, double t) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "  %-20s %10.4f s  %5.1f%%  %8.2f ns/ball-step\n", name, t,
                      tot > 0 ? 100.0 * t / tot : 0.0,
                      (cycles > 0 && balls > 0) ? 1e9 * t / double(cycles) / double(balls) : 0.0);
        os << buf;
    };
    os << "profile over " << cycles << " cycles:\n";
    line("timestep", timestep);
    line("law of motion", motion);
    line("contact detection", detection);
    line("force-displacement", force_displacement);
    line("bookkeeping", bookkeeping);
    line("total", tot);
    os << "  broadphase re-insertions " << proxy_moves << ", pairs created " << pairs_created
       << ", contacts created " << contacts_created << ", kernel steps " << kernel_steps
       << " (declined " << kernel_declined << ")"
       << ", threaded steps " << threaded_steps << ", memory sorts " << sorts << "\n";
    return os.str();
}

void Model::setThreads(int n, int grain) {
    World& world = *m_world;
    if (n < 1 || n > 1024)
        throw InputError("threads: the thread count must be from 1 to 1024 (got " +
                         std::to_string(n) + ")");
    if (grain < 1)
        throw InputError("threads: the grain (fewest pairs per thread) must be >= 1 (got " +
                         std::to_string(grain) + ")");
    world.settings.threads = n;
    world.settings.thread_grain = grain;
}

int Model::threads() const {
    const World& world = *m_world;
    if (world.settings.threads > 0) return world.settings.threads;
    // TALUS_THREADS (talus run --threads N sets it): a bad value is the CLI's to refuse; here
    // it falls back to one thread.
    const char* env = std::getenv("TALUS_THREADS");
    if (!env || !*env) return 1;
    char* end = nullptr;
    const long n = std::strtol(env, &end, 10);
    return (*end == '\0' && n >= 1 && n <= 1024) ? static_cast<int>(n) : 1;
}

int Model::threadGrain() const {
    const World& world = *m_world;
    if (world.settings.thread_grain > 0) return world.settings.thread_grain;
    // TALUS_THREAD_GRAIN: for tests that run small scenes on threads (stress suite).
    const char* env = std::getenv("TALUS_THREAD_GRAIN");
    if (!env || !*env) return kDefaultThreadGrain;
    char* end = nullptr;
    const long g = std::strtol(env, &end, 10);
    return (*end == '\0' && g >= 1 && g <= 1000000000) ? static_cast<int>(g) : kDefaultThreadGrain;
}

void Model::singleThreadedProcess() { setSingleThreadedProcess(); }

bool Model::threadingAvailable() {
#ifdef TALUS_HAVE_OPENMP
    return true;
#else
    return false;
#endif
}

}  // namespace talus
