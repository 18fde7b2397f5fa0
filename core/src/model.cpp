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
#include "model_internal.hpp"
#include "narrowphase.hpp"
#include "props.hpp"
#include "talus/errors.hpp"
#include "talus/run_control.hpp"

namespace talus {

namespace {
using Clock = std::chrono::steady_clock;
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
    : m_bodies(std::make_unique<BodyStore>()),
      m_contacts(std::make_unique<ContactStore>()),
      m_registry(registry),
      m_gravity(def.gravity),
      m_mass_mode(def.mass_mode) {
    if (!std::isfinite(def.gravity.x()) || !std::isfinite(def.gravity.y()))
        throw InputError("model: gravity must be finite");
    // Rule 0 is the default; until set it is "none" (no contacts are created).
    auto none = std::make_unique<Rule>();
    none->model_name = "";
    m_contacts->rules.push_back(std::move(none));
    m_fd_template.size = sizeof(FdBlock);
    m_fd_template.version = TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR;
    m_warning_handler = [](const std::string& w) { std::cerr << "warning: " << w << "\n"; };
}

Model::~Model() {
    for (auto& p : m_contacts->pairs) {
        if (p.model) {
            p.model->Destroy();
            p.rule->pool->release(p.model);
        }
    }
}

int Model::groupIndex(const std::string& name, bool create) {
    for (std::size_t i = 0; i < m_group_names.size(); ++i)
        if (m_group_names[i] == name) return static_cast<int>(i);
    if (!create) return -1;
    if (m_group_names.size() >= 64)
        throw InputError("group '" + name + "': a model holds at most 64 group names");
    m_group_names.push_back(name);
    if (m_books.on) openGroupBooks();  // the new group's books start empty
    return static_cast<int>(m_group_names.size() - 1);
}

const Model::BallArrays& Model::balls() const { return m_bodies->balls; }
double Model::broadphaseMargin() const { return m_contacts->margin; }

// ------------------------------------------------------------------------ the cycle

void Model::prepareRun() {
    // Ctrl-C came before this run call (run_control.hpp): take no step.
    if (stopRequested())
        throw Interrupted("interrupted (Ctrl-C) before step " + std::to_string(m_step + 1) +
                              " (t = " + messageNumber(m_time) + " s)",
                          true);
    if (!m_contacts->broadphase_ready) initBroadphase();
    const TimestepSettings& t = m_timestep;
    if (t.automatic != m_last_settings.automatic || t.safety != m_last_settings.safety ||
        t.resolution != m_last_settings.resolution)
        m_limits_stale = true;
    m_last_settings = t;
    for (auto& r : m_contacts->rules)
        if (r->prototype) {
            PropBlock pb = emptyPropBlock();
            if (const char* err = r->prototype->PreCycle(pb))
                throw InputError("contact model '" + r->model_name + "': " + err);
        }
    if (!m_contacts->rules[0]->prototype && m_contacts->rules.size() == 1 && ballCount() > 0 &&
        !m_warned_no_model) {
        m_warned_no_model = true;
        warn("no contact model is set (contact_model{...}): bodies will pass through each other");
    }
}

void Model::runSteps(int64_t steps) {
    using std::chrono::duration;
    const bool prof = m_profile.enabled;
    for (int64_t i = 0; i < steps; ++i) {
        // The PFC cycle (seed digest section 1), each phase timed into m_profile.
        Clock::time_point t0, t1;
        if (prof) t0 = Clock::now();
        computeTimestep();
        if (prof)
            t1 = Clock::now(), m_profile.timestep += duration<double>(t1 - t0).count(), t0 = t1;
        // Servo walls set their velocity from the last force loop and this step's dt.
        if (m_servos_on) servoWalls();
        lawOfMotion();
        moveWalls();
        if (prof) t1 = Clock::now(), m_profile.motion += duration<double>(t1 - t0).count(), t0 = t1;
        detectContacts();
        if (prof)
            t1 = Clock::now(), m_profile.detection += duration<double>(t1 - t0).count(), t0 = t1;
        forceDisplacement();
        if (prof)
            t1 = Clock::now(), m_profile.force_displacement += duration<double>(t1 - t0).count(),
            t0 = t1;
        bookkeeping();
        if (prof) t1 = Clock::now(), m_profile.bookkeeping += duration<double>(t1 - t0).count();
        ++m_profile.cycles;
        if (m_step_observer) m_step_observer(*this);
        // Ctrl-C (run_control.hpp): the step is complete, so the model is consistent here. One
        // relaxed atomic load per step: nothing next to a step's cost.
        if (stopRequested())
            throw Interrupted("interrupted (Ctrl-C) at step " + std::to_string(m_step) +
                                  " (t = " + messageNumber(m_time) + " s)",
                              false);
    }
}

void Model::cycle(int64_t steps) {
    if (steps < 0) throw InputError("cycle: number of steps must be >= 0");
    prepareRun();
    try {
        runSteps(steps);
    } catch (...) {
        flushWarnings();
        throw;
    }
    flushWarnings();
}

void Model::requireReachableTime(double duration) const {
    if (!(duration >= 0.0) || !std::isfinite(duration))
        throw InputError("solve: time must be >= 0 (got " + messageNumber(duration) + ")");
    // A duration no run can reach is refused rather than cycled for ever with no sign of life
    // (issue 6, item 12): beyond 1e9 s (32 years), and beyond 1e12 steps at a fixed step.
    if (duration > 1e9)
        throw InputError("solve: time " + messageNumber(duration) +
                         " s cannot be reached in a sane number of steps (at most 1e9 s per "
                         "solve; call solve repeatedly for longer runs)");
    if (!m_timestep.automatic && m_timestep.fixed > 0.0 && duration / m_timestep.fixed > 1e12)
        throw InputError("solve: time " + messageNumber(duration) + " s needs " +
                         messageNumber(duration / m_timestep.fixed) + " steps of the fixed step " +
                         messageNumber(m_timestep.fixed) + " s (more than 1e12)");
}

void Model::solveTime(double duration) {
    // solve{time} alone lands exactly on the end time (solve.cpp).
    SolveSpec spec;
    spec.time = duration;
    solve(spec);
}

std::string Model::lastStepReason() const {
    std::string s =
        std::string(stepRuleName(m_dt_rule)) + " rule, dt = " + messageNumber(m_dt) + " s";
    std::string where;
    switch (m_dt_where.kind) {
        case StepWhere::Ball:
            if (m_dt_where.index < ballCount()) where = describeBall(m_dt_where.index);
            break;
        case StepWhere::Pair:
            if (const Pair* p = pairByKey(ContactKey{m_dt_where.key})) where = describePair(*p);
            break;
        case StepWhere::Wall:
            where = "wall " + std::to_string(m_dt_where.index + 1);
            break;
        case StepWhere::None:
            break;
    }
    if (!where.empty()) s += " (" + where + ")";
    return s;
}

void Model::warn(const std::string& text) {
    if (m_warning_handler) m_warning_handler(text);
}

void Model::throwNonFinite(const std::string& what) const {
    throw NumericalError("non-finite state at step " + std::to_string(m_step) +
                         " (t = " + messageNumber(m_time) + " s): " + what);
}

}  // namespace talus
