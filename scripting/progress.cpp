// SPDX-License-Identifier: MIT
// The progress line (progress.hpp).
#include "progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "talus/model.hpp"

namespace talus::lua {

namespace {

bool g_enabled = false;
bool g_shown = false;  // a line is on the terminal now
pid_t g_owner = 0;     // the process that enabled it: a talus.map worker (a fork) never draws

// Wait this long before the first line (a short run shows nothing) and between redraws.
constexpr double kFirstDraw = 1.0;  // [s]
constexpr double kRedraw = 0.2;     // [s]

std::string grouped(int64_t n) {
    std::string digits = std::to_string(n < 0 ? -n : n), out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return n < 0 ? "-" + out : out;
}

std::string clockText(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0) return "?";
    const auto s = static_cast<long long>(std::llround(seconds));
    char buf[48];
    if (s >= 3600)
        std::snprintf(buf, sizeof buf, "%lld:%02lld:%02lld", s / 3600, s / 60 % 60, s % 60);
    else
        std::snprintf(buf, sizeof buf, "%lld:%02lld", s / 60, s % 60);
    return buf;
}

int terminalWidth() {
    winsize w{};
    if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &w) == 0 && w.ws_col > 10) return w.ws_col;
    return 80;
}

}  // namespace

void setProgressEnabled(bool on) {
    g_enabled = on;
    g_owner = ::getpid();
}

bool progressEnabled() { return g_enabled && ::getpid() == g_owner; }

void clearProgressLine() {
    if (!g_shown) return;
    // "\r" to the start, "ESC [ K" erases to the end of the line.
    std::fputs("\r\033[K", stderr);
    std::fflush(stderr);
    g_shown = false;
}

ProgressLine::ProgressLine(const Model& m, const ProgressTarget& target)
    : m_target(target),
      m_step0(m.step()),
      m_time0(m.time()),
      m_start(Clock::now()),
      m_last_draw(m_start),
      m_last_check(m_start) {}

ProgressLine::~ProgressLine() { clearProgressLine(); }

void ProgressLine::update(const Model& m) {
    // Reading the clock costs ~20 ns; a small model's step costs a few microseconds. Read it
    // every m_stride steps, with the stride adapted so that it happens ~20 times a second.
    if (--m_countdown > 0) return;
    const Clock::time_point now = Clock::now();
    const double since = std::chrono::duration<double>(now - m_last_check).count();
    m_last_check = now;
    if (since < 0.025)
        m_stride = std::min<int64_t>(m_stride * 2, 1 << 20);
    else if (since > 0.1 && m_stride > 1)
        m_stride /= 2;
    m_countdown = m_stride;
    const double elapsed = std::chrono::duration<double>(now - m_start).count();
    if (elapsed < kFirstDraw) return;
    if (g_shown && std::chrono::duration<double>(now - m_last_draw).count() < kRedraw) return;
    m_last_draw = now;
    draw(m, elapsed);
}

void ProgressLine::draw(const Model& m, double elapsed) {
    const int64_t done = m.step() - m_step0;
    const double simulated = m.time() - m_time0;
    const double rate = elapsed > 0 ? done / elapsed : 0.0;  // steps per wall-clock second
    // "step 41,200/100,000 (41%)  t = 0.824 s  12,310 steps/s  left 0:05"; for solve{time}:
    // "step 41,200  t = 0.824 s (0.3/0.5 s, 60%)  12,310 steps/s  left 0:03"
    char buf[96];
    std::string line = "step " + grouped(m.step());
    double fraction = -1.0;
    if (m_target.steps > 0) {
        fraction = static_cast<double>(done) / static_cast<double>(m_target.steps);
        line += "/" + grouped(m_step0 + m_target.steps);
        std::snprintf(buf, sizeof buf, " (%.0f%%)", 100.0 * std::min(fraction, 1.0));
        line += buf;
    }
    std::snprintf(buf, sizeof buf, "  t = %.4g s", m.time());
    line += buf;
    if (m_target.time > 0) {
        fraction = simulated / m_target.time;
        std::snprintf(buf, sizeof buf, " (%.4g/%.4g s, %.0f%%)", simulated, m_target.time,
                      100.0 * std::min(fraction, 1.0));
        line += buf;
    }
    line += "  " + grouped(static_cast<int64_t>(std::llround(rate))) + " steps/s";
    // Time left: the part still to go at the average rate so far (wall clock per step for
    // cycle(n), wall clock per simulated second for solve{time}).
    if (fraction > 0 && fraction < 1)
        line += "  left " + clockText(elapsed * (1 - fraction) / fraction);
    const std::size_t width = static_cast<std::size_t>(terminalWidth() - 1);
    if (line.size() + 16 <= width) line += "  (Ctrl-C stops)";
    if (line.size() > width) line.resize(width);  // a wrapped line could not be rewritten
    std::fprintf(stderr, "\r%s\033[K", line.c_str());
    std::fflush(stderr);
    g_shown = true;
}

}  // namespace talus::lua
