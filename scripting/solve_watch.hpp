// SPDX-License-Identifier: MIT
//
// The watch on m:solve{ratio = r} (docs/lua-api.md, "Running"): a scene that never settles runs
// such a solve for ever, silently, in a batch job. The watch samples the unbalanced-force ratio
// about once a second of wall clock and, at the first check (one minute into the run) and then
// every five minutes, compares the best (lowest) ratio of the last stretch with the best of
// the stretch before (at the first check: the first half of the minute against the second). A
// best ratio that fell by less than a tenth is "not getting closer", and the model's warning
// channel says so (m:on_warning sees it; the default prints it on stderr), with the ratio now,
// its trend, the step and the simulated time. The run goes on: the user decides.
// TALUS_STALL_FIRST and TALUS_STALL_EVERY (seconds) change the two intervals.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

namespace talus {
class Model;
}

namespace talus::lua {

class SolveWatch {
public:
    /// `target`: the ratio the solve aims at; `say`: where a finding goes (the model's warning).
    SolveWatch(double target, std::function<void(const std::string&)> say);
    /// After every step (the model's step observer): cheap unless a sample or a check is due.
    void update(const Model& m);

private:
    using Clock = std::chrono::steady_clock;
    void check(const Model& m, double elapsed, double ratio);

    double m_target;
    std::function<void(const std::string&)> m_say;
    double m_first;   // [s] first check
    double m_every;   // [s] later checks
    double m_sample;  // [s] between samples of the ratio
    Clock::time_point m_start;
    double m_next_sample = 0.0;
    double m_next_check;
    double m_window_start = 0.0;  // [s] start of the stretch being watched
    double m_best_before;         // best ratio of the stretch before (NaN: none yet)
    double m_before_len = 0.0;    // [s] length of the stretch before
    double m_best_now;            // best ratio of this stretch
    double m_best_half;           // first check only: best of the first half
    int64_t m_countdown = 1;
    int64_t m_stride = 1;
    Clock::time_point m_last_read;
};

}  // namespace talus::lua
