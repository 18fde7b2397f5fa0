// SPDX-License-Identifier: MIT
//
// Model::solve: PFC's ways to stop a run (solve ratio / step / time / fishhalt, plus caps).
// After every step the criteria are checked in a fixed order, targets before caps:
// time, steps, ratio, until, interrupted, max_steps, max_time; the first one reached ends the
// run and is returned. The unbalanced force is computed only when a ratio is asked for, and the
// `until` function is called only when given: solveTime is a solve with time alone.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "api/first_call.hpp"
#include "api/operations.hpp"
#include "step/step.hpp"
#include "talus/errors.hpp"
#include "world/messages.hpp"
#include "world/types.hpp"

namespace talus {

const char* solveStopName(SolveStop s) {
    switch (s) {
        case SolveStop::Time:
            return "time";
        case SolveStop::Steps:
            return "steps";
        case SolveStop::Ratio:
            return "ratio";
        case SolveStop::Until:
            return "until";
        case SolveStop::MaxSteps:
            return "max_steps";
        case SolveStop::MaxTime:
            return "max_time";
        case SolveStop::Interrupted:
            return "interrupted";
    }
    return "?";
}

namespace {

bool given(double v) { return !std::isnan(v); }

void checkSpec(const World& world, const SolveSpec& s) {
    if (!given(s.time) && s.steps < 0 && !given(s.ratio) && !s.until && s.max_steps < 0 &&
        !given(s.max_time))
        throw InputError(
            "solve: give at least one of time, steps, ratio, until, max_steps, max_time");
    if (given(s.time)) requireReachableTime(world, s.time);
    // A ratio below the rounding of the force sums (about 1e-16 of a contact force per body)
    // may never be reached, and a wall-clock cap beyond any run is none: refused, as a time no
    // run can reach is (solveTime), rather than cycled for ever.
    if (given(s.ratio) && !(s.ratio >= 1e-15 && std::isfinite(s.ratio)))
        throw InputError(
            "solve: ratio must be >= 1e-15 and finite (mean unbalanced over mean contact force; "
            "rounding leaves about 1e-16; got " +
            messageNumber(s.ratio) + ")");
    if (given(s.max_time) && !(s.max_time > 0.0 && s.max_time <= 1e9))
        throw InputError(
            "solve: max_time must be > 0 and at most 1e9 [s of wall-clock time] (got " +
            messageNumber(s.max_time) + ")");
}

/// A run of Model::solve: where it started and what it has seen.
struct SolveRun {
    std::chrono::steady_clock::time_point clock_start = std::chrono::steady_clock::now();
    int64_t first = 0;  // the step it started at
    double end = 0.0;   // the time it ends at (with a time)
    double last_ratio = std::numeric_limits<double>::quiet_NaN();
};

/// The first criterion reached, in the fixed order (targets, then caps), or none. Ratio and
/// until are judged on a state this run produced (a step taken).
std::optional<SolveStop> reachedStop(Model& model, const World& world, const SolveSpec& s,
                                     SolveRun& run) {
    const int64_t taken = world.clock.step - run.first;
    if (given(s.time) && reached(world, run.end)) return SolveStop::Time;
    if (s.steps >= 0 && taken >= s.steps) return SolveStop::Steps;
    if (taken > 0 && given(s.ratio)) {
        run.last_ratio = model.unbalanced().ratio;
        if (run.last_ratio <= s.ratio) return SolveStop::Ratio;
    }
    if (taken > 0 && s.until && s.until(model)) return SolveStop::Until;
    if (s.interrupted && s.interrupted()) return SolveStop::Interrupted;
    if (s.max_steps >= 0 && taken >= s.max_steps) return SolveStop::MaxSteps;
    if (given(s.max_time) &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - run.clock_start).count() >=
            s.max_time)
        return SolveStop::MaxTime;
    return std::nullopt;
}

/// A cap ends the run before its target: says so, with where the run got to.
void warnCap(World& world, Model& model, const SolveSpec& s, const SolveRun& run, SolveStop stop) {
    std::string text = "solve: stopped by the cap " +
                       (stop == SolveStop::MaxSteps
                            ? "max_steps = " + std::to_string(s.max_steps)
                            : "max_time = " + messageNumber(s.max_time) + " s (wall clock)") +
                       " after " + std::to_string(world.clock.step - run.first) +
                       " steps (t = " + messageNumber(world.clock.time) + " s)";
    std::string missed;
    if (given(s.ratio))
        missed +=
            " ratio " + messageNumber(s.ratio) + " (now " +
            messageNumber(std::isnan(run.last_ratio) ? model.unbalanced().ratio : run.last_ratio) +
            ")";
    if (given(s.time))
        missed += std::string(missed.empty() ? "" : ",") + " time " + messageNumber(s.time) + " s";
    if (s.steps >= 0)
        missed += std::string(missed.empty() ? "" : ",") + " steps " + std::to_string(s.steps);
    if (s.until) missed += std::string(missed.empty() ? "" : ",") + " the until function";
    if (!missed.empty()) text += " before reaching" + missed;
    talus::warn(world, text);
}

}  // namespace

SolveStop Model::solve(const SolveSpec& s) {
    World& world = *m_world;
    checkSpec(world, s);
    const RunLock lock(world, "solve");
    requireMemory(world, world.bodies.balls.size(), "solve");
    world.guard_state.memory_counted_balls = world.bodies.balls.size();
    prepareRun(world);
    SolveRun run;
    run.first = world.clock.step;
    run.end = given(s.time) ? world.clock.time + s.time : 0.0;
    std::optional<SolveStop> stop;
    try {
        firstCallsAtPlacement(world);
        while (!(stop = reachedStop(*this, world, s, run))) {
            if (given(s.time)) world.stepping.cap = run.end - world.clock.time;
            runSteps(world, 1);
        }
    } catch (...) {
        world.stepping.cap = 0.0;
        flushWarnings(world);
        throw;
    }
    world.stepping.cap = 0.0;
    if (*stop == SolveStop::MaxSteps || *stop == SolveStop::MaxTime)
        warnCap(world, *this, s, run, *stop);
    flushWarnings(world);
    return *stop;
}

}  // namespace talus
