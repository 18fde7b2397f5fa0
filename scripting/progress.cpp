// SPDX-License-Identifier: MIT
// The progress line (progress.hpp).
#include "progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "lua_runtime.hpp"
#include "talus/model.hpp"

namespace talus::lua {

namespace {

ProgressStyle g_style = ProgressStyle::Off;
bool g_shown = false;  // a line is on the terminal now
pid_t g_owner = 0;     // the process that set the style: a talus.map worker (a fork) never draws

// Wait this long before the first line (a short run shows nothing) and between redraws.
constexpr double kFirstDraw = 1.0;  // [s]
constexpr double kRedraw = 0.2;     // [s]

int terminalWidth() {
    winsize w{};
    if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &w) == 0 && w.ws_col > 10) return w.ws_col;
    return 80;
}

}  // namespace

std::string groupedDigits(int64_t n) {
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

void setProgressStyle(ProgressStyle style) {
    g_style = style;
    g_owner = ::getpid();
}

ProgressStyle progressStyle() { return ::getpid() == g_owner ? g_style : ProgressStyle::Off; }

double envSeconds(const char* name, double fallback) {
    const char* env = std::getenv(name);
    if (!env || !*env) return fallback;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(env, &end);
    if (errno != 0 || end == env || *end != '\0' || !(v > 0.0) || !std::isfinite(v))
        throw ScriptError(std::string(name) + " must be a positive number of seconds (got '" + env +
                          "')");
    return v;
}

double progressLogInterval() { return envSeconds("TALUS_PROGRESS_INTERVAL", 60.0); }

void clearProgressLine() {
    if (!g_shown) return;
    // "\r" to the start, "ESC [ K" erases to the end of the line.
    std::fputs("\r\033[K", stderr);
    std::fflush(stderr);
    g_shown = false;
}

ProgressLine::ProgressLine(const Model& m, const ProgressTarget& target)
    : m_style(progressStyle()),
      m_log_interval(m_style == ProgressStyle::Log ? progressLogInterval() : 60.0),
      m_target(target),
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
    if (m_style == ProgressStyle::Log) {
        // A line of its own every interval, the first after one interval: runs shorter than
        // that leave nothing in the log.
        if (std::chrono::duration<double>(now - m_last_draw).count() < m_log_interval) return;
        m_last_draw = now;
        std::fflush(stdout);
        std::fprintf(stderr, "talus: progress: %s  (running %s)\n", text(m, elapsed).c_str(),
                     clockText(elapsed).c_str());
        std::fflush(stderr);
        return;
    }
    if (elapsed < kFirstDraw) return;
    if (g_shown && std::chrono::duration<double>(now - m_last_draw).count() < kRedraw) return;
    m_last_draw = now;
    draw(m, elapsed);
}

std::string ProgressLine::text(const Model& m, double elapsed) const {
    const int64_t done = m.step() - m_step0;
    const double simulated = m.time() - m_time0;
    const double rate = elapsed > 0 ? done / elapsed : 0.0;  // steps per wall-clock second
    // "step 41,200/100,000 (41%)  t = 0.824 s  12,310 steps/s  left 0:05"; for solve{time}:
    // "step 41,200  t = 0.824 s (0.3/0.5 s, 60%)  12,310 steps/s  left 0:03"
    char buf[96];
    std::string line = "step " + groupedDigits(m.step());
    double fraction = -1.0;
    if (m_target.steps > 0) {
        fraction = static_cast<double>(done) / static_cast<double>(m_target.steps);
        line += "/" + groupedDigits(m_step0 + m_target.steps);
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
    if (m_target.ratio > 0) {
        // solve{ratio =}: where the criterion is (computed at each drawing only).
        std::snprintf(buf, sizeof buf, "  ratio %.3g (target %.3g)", m.unbalanced().ratio,
                      m_target.ratio);
        line += buf;
    }
    line += "  " + groupedDigits(static_cast<int64_t>(std::llround(rate))) + " steps/s";
    // Time left: the part still to go at the average rate so far (wall clock per step for
    // cycle(n), wall clock per simulated second for solve{time}).
    if (fraction > 0 && fraction < 1)
        line += "  left " + clockText(elapsed * (1 - fraction) / fraction);
    return line;
}

void ProgressLine::draw(const Model& m, double elapsed) {
    std::string line = text(m, elapsed);
    const std::size_t width = static_cast<std::size_t>(terminalWidth() - 1);
    if (line.size() + 16 <= width) line += "  (Ctrl-C stops)";
    if (line.size() > width) line.resize(width);  // a wrapped line could not be rewritten
    std::fprintf(stderr, "\r%s\033[K", line.c_str());
    std::fflush(stderr);
    g_shown = true;
}

}  // namespace talus::lua
