// SPDX-License-Identifier: MIT
//
// The progress line of a long cycle/solve on a terminal (docs/output.md, "Progress line"):
//
//   step 41,200/100,000 (41%)  t = 0.8240 s  12,310 steps/s  left 0:05
//
// One line on stderr, rewritten in place ("\r" + erase to end of line), drawn only when stderr
// is a terminal, `talus run --quiet` was not given, and the run has lasted a second (short
// runs never flicker). Cleared when the run returns, and before anything the script prints,
// so it never mixes with the script's own output.
#pragma once

#include <chrono>
#include <cstdint>

namespace talus {
class Model;
}

namespace talus::lua {

/// What a run call aims at, for "time left" (both unset: unknown, e.g. solve{ratio =}).
struct ProgressTarget {
    int64_t steps = -1;  ///< total steps of this call (cycle(n): n), or -1
    double time = -1.0;  ///< simulated seconds of this call (solve{time = t}: t), or -1
};

/// Process-wide settings (main.cpp): whether a progress line may be drawn at all.
void setProgressEnabled(bool on);
bool progressEnabled();
/// Erases the line if one is shown (before other output). Cheap when none is.
void clearProgressLine();

/// One run call's progress: construct at its start, call `update` after every step (the model's
/// step observer), destroy at its end (erases the line).
class ProgressLine {
public:
    ProgressLine(const Model& m, const ProgressTarget& target);
    ~ProgressLine();
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;

    void update(const Model& m);

private:
    using Clock = std::chrono::steady_clock;
    void draw(const Model& m, double elapsed);

    ProgressTarget m_target;
    int64_t m_step0;
    double m_time0;
    Clock::time_point m_start;
    Clock::time_point m_last_draw;
    int64_t m_countdown = 1;  // steps until the clock is read again
    int64_t m_stride = 1;     // steps between clock reads, adapted to ~20 reads a second
    Clock::time_point m_last_check;
};

}  // namespace talus::lua
