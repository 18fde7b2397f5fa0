// SPDX-License-Identifier: MIT
//
// One step of the PFC cycle (Itasca's PFC2D manual; docs/architecture.md), read top to bottom:
// the time step first, since every phase after it needs the step's length, then a StepContext
// with what the step is fixed to, then the phases in order, each timed into world.profile.
#include "step/step.hpp"

#include <chrono>
#include <string>

#include "props.hpp"
#include "step/barriers.hpp"
#include "step/detection.hpp"
#include "step/script_work.hpp"
#include "talus/errors.hpp"
#include "talus/run_control.hpp"
#include "world/messages.hpp"

namespace talus {

namespace {
using WallClock = std::chrono::steady_clock;
}  // namespace

StepContext beginStep(const World& world) {
    StepContext step;
    step.dt = world.clock.dt;
    // On the very first cycle the given velocities are values at t, not at t - dt/2: the
    // velocity update spans dt/2 (law_of_motion.cpp). After an idle step computeTimestep has
    // set dt_prev = 0 for the same fresh start.
    step.dt_prev = world.clock.first_cycle ? 0.0 : world.clock.dt_prev;
    step.window = 0.5 * (step.dt_prev + step.dt);
    step.automatic = world.settings.timestep.automatic;
    step.energy = world.books.on;
    step.groups = world.books.on && world.books.groups.on;
    const GuardSettings& g = world.settings.guard;
    step.guard = g.energy != GuardAction::Off || g.resolution != GuardAction::Off ||
                 g.stiffness != GuardAction::Off;
    return step;
}

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
        WallClock::time_point t0, t1;
        if (prof) t0 = WallClock::now();
        computeTimestep(world);
        if (prof)
            t1 = WallClock::now(), world.profile.timestep += duration<double>(t1 - t0).count(),
            t0 = t1;
        const StepContext step = beginStep(world);
        // What the script changed since the last step, before the law of motion takes it.
        if (step.energy) bookScriptWork(world, step);
        // Servo walls set their velocity from the last force loop and this step's dt.
        if (world.bodies.servos_on) servoWalls(world, step);
        if (world.servos.on) runServos(world, step);
        if (!world.barriers.list.empty()) recordBodyStarts(world);
        lawOfMotion(world, step);
        moveWalls(world, step);
        if (prof)
            t1 = WallClock::now(), world.profile.motion += duration<double>(t1 - t0).count(),
            t0 = t1;
        detectContacts(world, step);
        if (prof)
            t1 = WallClock::now(), world.profile.detection += duration<double>(t1 - t0).count(),
            t0 = t1;
        forceDisplacement(world, step);
        if (prof)
            t1 = WallClock::now(),
            world.profile.force_displacement += duration<double>(t1 - t0).count(), t0 = t1;
        bookkeeping(world, step);
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

}  // namespace talus
