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
#include <string>

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

SolveStop Model::solve(const SolveSpec& s) {
    World& world = *m_world;
    const bool has_time = !std::isnan(s.time);
    const bool has_ratio = !std::isnan(s.ratio);
    const bool has_max_time = !std::isnan(s.max_time);
    if (!has_time && s.steps < 0 && !has_ratio && !s.until && s.max_steps < 0 && !has_max_time)
        throw InputError(
            "solve: give at least one of time, steps, ratio, until, max_steps, max_time");
    if (has_time) requireReachableTime(world, s.time);
    // A ratio below the rounding of the force sums (about 1e-16 of a contact force per body)
    // may never be reached, and a wall-clock cap beyond any run is none: refused, as a time no
    // run can reach is (solveTime), rather than cycled for ever.
    if (has_ratio && !(s.ratio >= 1e-15 && std::isfinite(s.ratio)))
        throw InputError(
            "solve: ratio must be >= 1e-15 and finite (mean unbalanced over mean contact force; "
            "rounding leaves about 1e-16; got " +
            messageNumber(s.ratio) + ")");
    if (has_max_time && !(s.max_time > 0.0 && s.max_time <= 1e9))
        throw InputError(
            "solve: max_time must be > 0 and at most 1e9 [s of wall-clock time] (got " +
            messageNumber(s.max_time) + ")");
    const RunLock lock(world, "solve");
    requireMemory(world, world.bodies.balls.size(), "solve");
    world.guard_state.memory_counted_balls = world.bodies.balls.size();
    prepareRun(world);
    const auto clock_start = std::chrono::steady_clock::now();
    const int64_t first = world.clock.step;
    const double end = has_time ? world.clock.time + s.time : 0.0;
    double last_ratio = std::numeric_limits<double>::quiet_NaN();
    SolveStop stop = SolveStop::Time;
    try {
        for (;;) {
            const int64_t taken = world.clock.step - first;
            // Targets. Ratio and until are judged on a state this run produced (a step taken).
            if (has_time && reached(world, end)) {
                stop = SolveStop::Time;
                break;
            }
            if (s.steps >= 0 && taken >= s.steps) {
                stop = SolveStop::Steps;
                break;
            }
            if (taken > 0 && has_ratio) {
                last_ratio = unbalanced().ratio;
                if (last_ratio <= s.ratio) {
                    stop = SolveStop::Ratio;
                    break;
                }
            }
            if (taken > 0 && s.until && s.until(*this)) {
                stop = SolveStop::Until;
                break;
            }
            if (s.interrupted && s.interrupted()) {
                stop = SolveStop::Interrupted;
                break;
            }
            // Caps.
            if (s.max_steps >= 0 && taken >= s.max_steps) {
                stop = SolveStop::MaxSteps;
                break;
            }
            if (has_max_time &&
                std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start)
                        .count() >= s.max_time) {
                stop = SolveStop::MaxTime;
                break;
            }
            if (has_time) world.stepping.cap = end - world.clock.time;
            runSteps(world, 1);
        }
    } catch (...) {
        world.stepping.cap = 0.0;
        flushWarnings(world);
        throw;
    }
    world.stepping.cap = 0.0;
    if (stop == SolveStop::MaxSteps || stop == SolveStop::MaxTime) {
        // A cap ends the run before its target: say so, with where the run got to.
        std::string text = "solve: stopped by the cap " +
                           (stop == SolveStop::MaxSteps
                                ? "max_steps = " + std::to_string(s.max_steps)
                                : "max_time = " + messageNumber(s.max_time) + " s (wall clock)") +
                           " after " + std::to_string(world.clock.step - first) +
                           " steps (t = " + messageNumber(world.clock.time) + " s)";
        std::string missed;
        if (has_ratio)
            missed += " ratio " + messageNumber(s.ratio) + " (now " +
                      messageNumber(std::isnan(last_ratio) ? unbalanced().ratio : last_ratio) + ")";
        if (has_time)
            missed +=
                std::string(missed.empty() ? "" : ",") + " time " + messageNumber(s.time) + " s";
        if (s.steps >= 0)
            missed += std::string(missed.empty() ? "" : ",") + " steps " + std::to_string(s.steps);
        if (s.until) missed += std::string(missed.empty() ? "" : ",") + " the until function";
        if (!missed.empty()) text += " before reaching" + missed;
        talus::warn(world, text);
    }
    flushWarnings(world);
    return stop;
}

}  // namespace talus
