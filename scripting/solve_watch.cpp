// SPDX-License-Identifier: MIT
// The watch on m:solve{ratio =} (solve_watch.hpp).
#include "solve_watch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "progress.hpp"
#include "talus/model.hpp"

namespace talus::lua {

namespace {

// A best ratio that fell by less than this fraction over a stretch is not getting closer: at
// that pace two decades take more than 40 stretches (over three hours of five minutes).
constexpr double kCloser = 0.9;

std::string ratioText(double r) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", r);
    return buf;
}

}  // namespace

SolveWatch::SolveWatch(double target, std::function<void(const std::string&)> say)
    : m_target(target),
      m_say(std::move(say)),
      m_first(envSeconds("TALUS_STALL_FIRST", 60.0)),
      m_every(envSeconds("TALUS_STALL_EVERY", 300.0)),
      m_sample(std::min(1.0, m_first / 20.0)),
      m_start(Clock::now()),
      m_next_check(m_first),
      m_best_before(std::numeric_limits<double>::quiet_NaN()),
      m_best_now(std::numeric_limits<double>::infinity()),
      m_best_half(std::numeric_limits<double>::infinity()),
      m_last_read(m_start) {}

void SolveWatch::update(const Model& m) {
    // The clock is read about fifty times a second (the stride adapts to the step's cost), the
    // ratio (a pass over the bodies and contacts) about once a second.
    if (--m_countdown > 0) return;
    const Clock::time_point now = Clock::now();
    const double since = std::chrono::duration<double>(now - m_last_read).count();
    m_last_read = now;
    if (since < 0.01)
        m_stride = std::min<int64_t>(m_stride * 2, 1 << 20);
    else if (since > 0.05 && m_stride > 1)
        m_stride /= 2;
    m_countdown = m_stride;
    const double elapsed = std::chrono::duration<double>(now - m_start).count();
    if (elapsed < m_next_sample) return;
    m_next_sample = elapsed + m_sample;
    const double r = m.unbalanced().ratio;
    // The first stretch is judged on its two halves; later ones against the stretch before.
    double& best = std::isnan(m_best_before) && elapsed < m_first / 2 ? m_best_half : m_best_now;
    if (r < best) best = r;  // NaN (no body) never counts
    if (elapsed >= m_next_check) check(m, elapsed, r);
}

void SolveWatch::check(const Model& m, double elapsed, double ratio) {
    const bool first = std::isnan(m_best_before);
    const double before = first ? m_best_half : m_best_before;
    const double before_len = first ? m_first / 2 : m_before_len;
    const double now_len = first ? elapsed - m_first / 2 : elapsed - m_window_start;
    const double best = m_best_now;
    // Closer: the best ratio of this stretch is below a tenth under the one before (a first
    // finite ratio after none also counts: contacts began to carry force).
    const bool closer = best < kCloser * before || (std::isinf(before) && std::isfinite(best));
    if (!closer) {
        std::string trend;
        if (std::isinf(best)) {
            trend = "no contact carries a force (the ratio is infinite)";
        } else {
            char buf[64];
            std::snprintf(buf, sizeof buf, "%+.0f%%", 100.0 * (best / before - 1.0));
            trend = "the best of the last " + clockText(now_len) + " is " + ratioText(best) +
                    " against " + ratioText(before) + " in the " + clockText(before_len) +
                    " before (" + buf + ")";
        }
        char where[96];
        std::snprintf(where, sizeof where, "t = %.6g s", m.time());
        m_say("solve: the unbalanced-force ratio is not getting closer to its target " +
              ratioText(m_target) + ": " + ratioText(ratio) + " now; " + trend + "; at step " +
              groupedDigits(m.step()) + ", " + where + " after " + clockText(elapsed) +
              " of running. The run goes on (Ctrl-C stops it; max_time = or max_steps = cap a "
              "solve): a scene that keeps moving (a flow, a rolling body, no damping) never "
              "settles");
    }
    m_best_before = best;
    m_before_len = now_len;
    m_best_now = std::numeric_limits<double>::infinity();
    m_window_start = elapsed;
    m_next_check = elapsed + m_every;
}

}  // namespace talus::lua
