// SPDX-License-Identifier: MIT
//
// Helpers shared by the core engine tests: a fixed-seed PRNG, closed forms of single impacts
// (each cites its source), scene builders,
// a byte hash, statistics and an opt-in report printer.
//
// Set TALUS_TEST_REPORT=1 to print the measured numbers (worst/mean errors, orders, residuals)
// that the tests assert on; ctest runs stay quiet.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "talus/errors.hpp"
#include "talus/impact_rig.hpp"
#include "talus/model.hpp"
#include "talus/splitmix.hpp"

namespace talus::test {

// ------------------------------------------------------------------ reporting

inline bool reportOn() {
    static const bool on = [] {
        const char* v = std::getenv("TALUS_TEST_REPORT");
        return v && *v && std::strcmp(v, "0") != 0;
    }();
    return on;
}

/// printf to stdout when TALUS_TEST_REPORT is set.
#if defined(__GNUC__)
__attribute__((format(printf, 1, 2)))
#endif
inline void
report(const char* fmt, ...) {
    if (!reportOn()) return;
    va_list ap;
    va_start(ap, fmt);
    std::vprintf(fmt, ap);
    va_end(ap);
    std::fflush(stdout);
}

// ------------------------------------------------------------------ PRNG

/// The fixed-seed generator of the scenes (talus/splitmix.hpp).
using Rng = SplitMix64;

// ------------------------------------------------------------------ statistics

struct Stats {
    double worst = 0.0;
    double sum = 0.0;
    int n = 0;
    void add(double v) {
        worst = std::max(worst, std::fabs(v));
        sum += std::fabs(v);
        ++n;
    }
    double mean() const { return n ? sum / n : 0.0; }
};

// ------------------------------------------------------------------ closed forms

/// Linear spring-dashpot restitution when the dashpot may pull (the closed form of a linear
/// spring-dashpot).
inline double restitutionFull(double beta) {
    return std::exp(-M_PI * beta / std::sqrt(1.0 - beta * beta));
}

/// Same with the total normal force clipped at zero (the closed form of a linear spring-dashpot,
/// no-tension variant). The derivation holds for every beta < 1: the separation time is the first
/// zero of k delta + c delta', (pi - 2 asin beta)/omega_d, and there |delta'| = v0 exp(-gamma t_s).
inline double restitutionNoTension(double beta) {
    return std::exp(-beta * (M_PI - 2.0 * std::asin(beta)) / std::sqrt(1.0 - beta * beta));
}

/// Inverse of restitutionFull (the closed form of a linear spring-dashpot).
inline double betaForRestitution(double e) {
    const double l = std::log(e);
    return -l / std::sqrt(M_PI * M_PI + l * l);
}

/// Inverse of restitutionNoTension by bisection (the function decreases with beta).
inline double betaForRestitutionNoTension(double e) {
    double lo = 0.0, hi = 1.0 - 1e-12;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (restitutionNoTension(mid) > e ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

/// Contact duration (overlap back to zero) of a linear spring-dashpot, pi / omega_d.
inline double linearDuration(double m_eff, double kn, double beta = 0.0) {
    return M_PI / (std::sqrt(kn / m_eff) * std::sqrt(1.0 - beta * beta));
}

/// Maximum overlap of a linear spring-dashpot impact (the closed form of a linear spring-dashpot).
inline double linearMaxOverlap(double m_eff, double kn, double v0, double beta = 0.0) {
    const double w0 = std::sqrt(kn / m_eff);
    if (beta == 0.0) return v0 / w0;
    const double s = std::sqrt(1.0 - beta * beta);
    return v0 / w0 * std::exp(-(beta / s) * std::atan(s / beta));
}

/// Disk and sphere masses (PFC2D's documentation).
inline double diskMass(double rho, double r) { return rho * M_PI * r * r; }
inline double sphereMass(double rho, double r) { return rho * 4.0 / 3.0 * M_PI * r * r * r; }

// ------------------------------------------------------------------ scenes

/// A model with gravity `g` and the linear model with `props` as its default.
inline std::unique_ptr<Model> makeModel(const Vec2& g, const std::vector<PropValue>& props) {
    ModelDef def;
    def.gravity = g;
    auto m = std::make_unique<Model>(def);
    m->setDefaultContactModel("linear", props);
    return m;
}

inline std::vector<PropValue> linearProps(double kn, double ks = 0.0, double fric = 0.0,
                                          double dp_nratio = 0.0, double dp_sratio = 0.0,
                                          int dp_mode = 0) {
    return {{"kn", kn},
            {"ks", ks},
            {"fric", fric},
            {"dp_nratio", dp_nratio},
            {"dp_sratio", dp_sratio},
            {"dp_mode", static_cast<double>(dp_mode)}};
}

/// Timestep settings for a fixed step.
inline TimestepSettings fixedStep(double dt) {
    TimestepSettings t;
    t.automatic = false;
    t.fixed = dt;
    return t;
}

/// Collects warnings instead of printing them.
struct WarningLog {
    std::vector<std::string> texts;
    void attach(Model& m) {
        m.setWarningHandler([this](const std::string& w) { texts.push_back(w); });
    }
    bool any(const std::string& needle) const {
        for (const auto& t : texts)
            if (t.find(needle) != std::string::npos) return true;
        return false;
    }
};

inline BallDef ballAt(const Vec2& pos, double radius, double density,
                      const Vec2& vel = Vec2::Zero()) {
    BallDef b;
    b.pos = pos;
    b.radius = radius;
    b.density = density;
    b.vel = vel;
    return b;
}

inline WallDef wallOf(std::vector<Vec2> points, bool closed = false) {
    WallDef w;
    w.points = std::move(points);
    w.closed = closed;
    return w;
}

/// What one ball did during one contact episode (any number of contacts).
struct Episode {
    bool touched = false, ended = false;
    Vec2 v_in{0.0, 0.0}, v_out{0.0, 0.0};
    double spin_in = 0.0, spin_out = 0.0;
    double peak_force = 0.0;             ///< largest |total contact force| on the ball [N]
    std::size_t max_contacts = 0;        ///< largest number of active contacts at once
    int64_t steps = 0;                   ///< steps with a non-zero contact force
    double t_first = 0.0, t_last = 0.0;  ///< times of the first and last loaded step [s]
    std::vector<Vec2> normals;           ///< contact normals seen (first step of each new count)
};

/// Cycles until the ball has been loaded and is free again (no active contact), at most
/// max_steps. Velocities are read before the first loaded step and after the last.
inline Episode runEpisode(Model& m, BallId ball, int64_t max_steps = 1000000) {
    Episode ep;
    ep.v_in = m.ballVel(ball);
    ep.spin_in = m.ballSpin(ball);
    for (int64_t i = 0; i < max_steps; ++i) {
        m.cycle(1);
        const auto cs = m.contacts();
        std::size_t n = 0;
        for (const auto& c : cs)
            if (c.ball1 == ball || c.ball2 == ball) {
                ++n;
                if (n > ep.max_contacts) ep.normals.push_back(c.normal);
            }
        const double f = m.ballForce(ball).norm();
        if (!ep.touched) {
            if (n == 0) {
                ep.v_in = m.ballVel(ball);
                ep.spin_in = m.ballSpin(ball);
                continue;
            }
            ep.touched = true;
            ep.t_first = m.time();
        }
        ep.max_contacts = std::max(ep.max_contacts, n);
        ep.peak_force = std::max(ep.peak_force, f);
        if (f > 0.0) ++ep.steps, ep.t_last = m.time();
        if (n == 0) {
            m.cycle(1);  // the last force acts in the next velocity update
            ep.ended = true;
            break;
        }
    }
    ep.v_out = m.ballVel(ball);
    ep.spin_out = m.ballSpin(ball);
    return ep;
}

// ------------------------------------------------------------------ hashing

/// FNV-1a over raw bytes.
class Hash {
public:
    void bytes(const void* p, std::size_t n) {
        const auto* c = static_cast<const unsigned char*>(p);
        for (std::size_t i = 0; i < n; ++i) m_h = (m_h ^ c[i]) * 0x100000001B3ull;
    }
    void add(double v) { bytes(&v, sizeof v); }
    void add(const Vec2& v) { add(v.x()), add(v.y()); }
    uint64_t value() const { return m_h; }

private:
    uint64_t m_h = 0xCBF29CE484222325ull;
};

/// Hash of every live ball's position, velocity, spin and angle, in id order.
inline uint64_t stateHash(const Model& m) {
    Hash h;
    for (BallId id : m.ballIds()) {
        h.add(m.ballPos(id));
        h.add(m.ballVel(id));
        h.add(m.ballSpin(id));
        h.add(m.ballAngle(id));
    }
    return h.value();
}

// ------------------------------------------------------------------ misc

/// Observed order of convergence from errors at step h and h/2.
inline double observedOrder(double e_h, double e_half) { return std::log2(e_h / e_half); }

/// Least-squares slope of log(err) against log(h).
inline double fittedOrder(const std::vector<double>& h, const std::vector<double>& err) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double n = static_cast<double>(h.size());
    for (std::size_t i = 0; i < h.size(); ++i) {
        const double x = std::log(h[i]), y = std::log(err[i]);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace talus::test
