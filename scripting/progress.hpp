// SPDX-License-Identifier: MIT
//
// The progress line of a long cycle/solve (docs/output.md, "Progress line"):
//
//   step 41,200/100,000 (41%)  t = 0.8240 s  12,310 steps/s  left 0:05
//
// On a terminal: one line on stderr, rewritten in place ("\r" + erase to end of line), once the
// run has lasted a second (short runs never flicker); cleared when the run returns and before
// anything the script prints, so it never mixes with the script's own output. When stderr is a
// file or a pipe (a batch job): the same text as a line of its own, "talus: progress: ...",
// every minute (TALUS_PROGRESS_INTERVAL seconds) of runs longer than that, so a log shows that
// a long run is alive and where it is. `talus run --quiet` turns both off.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace talus {
class Model;
}

namespace talus::lua {

/// What a run call aims at, for "time left" (both unset: unknown, e.g. solve{ratio =}).
struct ProgressTarget {
    int64_t steps = -1;   ///< total steps of this call (cycle(n): n), or -1
    double time = -1.0;   ///< simulated seconds of this call (solve{time = t}: t), or -1
    double ratio = -1.0;  ///< solve{ratio = r}: r (the line shows the ratio now), or -1
};

/// How progress is shown: not at all, a line rewritten in place on a terminal, or a line of its
/// own every TALUS_PROGRESS_INTERVAL seconds in a log.
enum class ProgressStyle { Off, Terminal, Log };
/// Process-wide setting (main.cpp; Off unless set).
void setProgressStyle(ProgressStyle style);
/// The style in this process (Off in a talus.map worker, a fork: only the caller shows it).
ProgressStyle progressStyle();
/// Seconds between the lines of the Log style: TALUS_PROGRESS_INTERVAL, default 60. Throws
/// ScriptError naming the variable when it is not a positive number.
double progressLogInterval();
/// A positive number of seconds from environment variable `name`, else `fallback`; throws
/// ScriptError naming the variable when it is set to anything else.
double envSeconds(const char* name, double fallback);
/// 1234567 -> "1,234,567".
std::string groupedDigits(int64_t n);
/// Seconds as "m:ss" or "h:mm:ss" ("?" when not a time).
std::string clockText(double seconds);
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
    std::string text(const Model& m, double elapsed) const;
    void draw(const Model& m, double elapsed);

    ProgressStyle m_style;
    double m_log_interval = 60.0;  // [s] Log style
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
