// SPDX-License-Identifier: MIT
//
// talus_model_accuracy: restitution error against run time as the step varies, for the linear,
// hertz, ng and hysdamp contact models (a first work-precision measurement). Not a test: it prints
// markdown tables; scripts/bench/model_accuracy.sh builds and runs it, and docs/models/<model>.md
// quote its output.
//
// Scene: the impact rig (core/include/talus/impact_rig.hpp), a unit-thickness disk R = 0.1 m,
// 2600 kg/m^3 (81.7 kg) hitting a wall at v0 = 1 m/s. For each step setting, `phases` impacts
// whose initial gap is drawn uniformly over 20 contact durations of travel, so that the phase of
// first touch within a step is random even at the coarsest step (about 3 steps per contact).
// Error = |e - e_exact| / e_exact, e_exact from the closed forms (docs/models/*.md),
// or, for the damped Hertz law, from an RK4 integration of the same ODE at 200000 steps per
// contact. Time = median wall time of runImpact (model set-up included) per impact.
//
// Step settings: the stability rule alone (resolution = 0) at safety 0.9 ... 0.05, and the
// resolution rule at 5 ... 100 steps per contact duration (safety 0.8). For the Hertz-type laws
// a third set emulates a stability rule that sees the contact before it exists (the step capped
// at safety t_c / pi, i.e. the stiffness m* (pi/t_c)^2): see docs/models/hertz.md.
//
// Usage: talus_model_accuracy [--phases N] [--model NAME]... [--seed S]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "../plugins/contact_law_support.hpp"
#include "talus/errors.hpp"
#include "talus/impact_rig.hpp"

using namespace talus;
using talus::lawtest::Rng;

namespace {

constexpr double kR = 0.1, kRho = 2600.0, kV0 = 1.0;
const double kMass = kRho * M_PI * kR * kR;

struct Config {
    std::string model;  // plugin
    std::string label;  // row group title
    std::vector<PropValue> props;
    double e_exact;
    double duration;  // closed-form contact duration at kV0 [s] (for the gap range)
    bool hertz_like;  // zero stiffness at touch: add the capped-stability rows
};

struct Setting {
    std::string rule;  // "stability", "resolution", "stability+cap"
    double value;      // safety or steps per contact
};

struct Row {
    Setting setting;
    double mean_err = 0.0, worst_err = 0.0, steps = 0.0, micros = 0.0;
    int failed = 0;  // impacts that did not separate or threw
    std::string first_failure;
};

double linearE(double beta, int mode) {
    if (beta == 0.0) return 1.0;
    const double s = std::sqrt(1.0 - beta * beta);
    // the closed form of a linear spring-dashpot: dashpot may pull (mode 0), or total force clipped
    // at zero (mode 1)
    return mode == 0 ? std::exp(-M_PI * beta / s)
                     : std::exp(-beta * (M_PI - 2.0 * std::asin(beta)) / s);
}

/// Restitution of m u'' = -(K u^1.5 + c0 u^0.25 u') (clipped at zero in mode 1), RK4.
double hertzDampedE(double e_star, double beta, int mode, double tc) {
    const double K = 4.0 / 3.0 * e_star * std::sqrt(kR);
    const double c0 = 2.0 * beta * std::sqrt(kMass * 2.0 * e_star * std::sqrt(kR));
    auto force = [&](double u, double v) {
        if (u <= 0.0) return 0.0;
        const double f = K * std::pow(u, 1.5) + c0 * std::pow(u, 0.25) * v;
        return mode == 1 ? std::max(0.0, f) : f;
    };
    return lawtest::referenceRestitution(kMass, kV0, tc, force, [](double u, double) { return u; });
}

std::vector<Config> configs() {
    std::vector<Config> out;
    const double kn = 1e8;
    const double tc_lin = M_PI * std::sqrt(kMass / kn);
    out.push_back({"linear", "linear, elastic (kn = 1e8 N/m)", {{"kn", kn}}, 1.0, tc_lin, false});
    for (double beta : {0.2, 0.5})
        for (int mode : {0, 1}) {
            char label[96];
            std::snprintf(label, sizeof label, "linear, dp_nratio = %.1f, dp_mode = %d", beta,
                          mode);
            out.push_back({"linear",
                           label,
                           {{"kn", kn}, {"dp_nratio", beta}, {"dp_mode", double(mode)}},
                           linearE(beta, mode),
                           tc_lin / std::sqrt(1.0 - beta * beta),
                           false});
        }
    // Lac du Bonnet granite (Nejati 2008), rigid wall: E* = 2G/(1-nu).
    const double G = 27.4e9, nu = 0.26, es = 2.0 * G / (1.0 - nu);
    const double tc_hz = lawtest::hertzImpact(kMass, kR, es, kV0).tc;
    out.push_back({"hertz",
                   "hertz, elastic (G = 27.4 GPa, nu = 0.26)",
                   {{"hz_shear", G}, {"hz_poiss", nu}},
                   1.0,
                   tc_hz,
                   true});
    for (int mode : {0, 1}) {
        char label[96];
        std::snprintf(label, sizeof label, "hertz, dp_nratio = 0.2, dp_mode = %d", mode);
        out.push_back(
            {"hertz",
             label,
             {{"hz_shear", G}, {"hz_poiss", nu}, {"dp_nratio", 0.2}, {"dp_mode", double(mode)}},
             hertzDampedE(es, 0.2, mode, tc_hz),
             tc_hz,
             true});
    }
    // ng: the literal formula counts the wall as the same material, E = G/(1-nu) (form 0).
    for (int form : {0, 1}) {
        const double e_ng = (form ? 1.5 : 1.0) * G / (1.0 - nu);
        out.push_back({"ng",
                       form ? "ng, secant (ng_form = 1)" : "ng, tangent (ng_form = 0)",
                       {{"ng_shear", G}, {"ng_poiss", nu}, {"ng_form", double(form)}},
                       1.0,
                       lawtest::hertzImpact(kMass, kR, e_ng, kV0).tc,
                       true});
    }
    for (auto [d, tension] : {std::pair<double, bool>{0.5, false}, {0.1, false}, {0.6, true}}) {
        const double k1 = 2.0 * d * kn / (1.0 + d), k2 = 2.0 * kn / (1.0 + d);
        double tf = 0.5 * M_PI * (std::sqrt(kMass / k1) + std::sqrt(kMass / k2));
        if (tension) tf += std::asin((1.0 - d) / std::sqrt(d)) * std::sqrt(kMass / k1);
        char label[96];
        std::snprintf(label, sizeof label, "hysdamp, kn_m = 1e8 N/m, d = %.1f, tension = %d", d,
                      tension ? 1 : 0);
        out.push_back({"hysdamp",
                       label,
                       {{"kn_m", kn}, {"d", d}, {"tension", tension ? 1.0 : 0.0}},
                       lawtest::hysdampRestitution(d, tension),
                       tf,
                       false});
    }
    return out;
}

Row measure(const Config& c, const Setting& st, int phases, uint64_t seed) {
    Row row;
    row.setting = st;
    Rng rng(seed);
    double sum_err = 0.0, sum_steps = 0.0;
    std::vector<double> times;
    int n = 0;
    for (int i = 0; i < phases; ++i) {
        ImpactSetup s;
        s.model = c.model;
        s.props = c.props;
        s.radius = kR;
        s.density = kRho;
        s.normal_speed = kV0;
        s.guard.energy =
            GuardAction::Off;  // we measure what happens, warnings would only repeat it
        s.guard.resolution = GuardAction::Off;
        s.max_steps = 200000;
        if (st.rule == "resolution") {
            s.timestep.resolution = st.value;
        } else {
            s.timestep.resolution = 0.0;
            s.timestep.safety = st.value;
            if (st.rule == "stability+cap") s.timestep.max = st.value * c.duration / M_PI;
        }
        s.gap = 1e-6 + rng.uniform() * 20.0 * kV0 * c.duration;
        const auto t0 = std::chrono::steady_clock::now();
        ImpactResult r;
        try {
            r = runImpact(s);
        } catch (const Error& e) {
            if (row.failed++ == 0) row.first_failure = e.what();
            continue;
        }
        const auto t1 = std::chrono::steady_clock::now();
        if (!r.separated) {
            if (row.failed++ == 0) row.first_failure = "no separation";
            continue;
        }
        const double err = std::fabs(r.restitution - c.e_exact) / c.e_exact;
        sum_err += err;
        row.worst_err = std::max(row.worst_err, err);
        sum_steps += static_cast<double>(r.steps_in_contact);
        times.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
        ++n;
    }
    if (n > 0) {
        row.mean_err = sum_err / n;
        row.steps = sum_steps / n;
        // Median: robust against a busy machine (the builds of others share the cores).
        std::sort(times.begin(), times.end());
        row.micros = times[times.size() / 2];
    }
    return row;
}

std::string percent(double v) {
    char buf[32];
    if (v >= 0.1)
        std::snprintf(buf, sizeof buf, "%.3g", v * 100.0);
    else
        std::snprintf(buf, sizeof buf, "%.2g", v * 100.0);
    return std::string(buf) + " %";
}

}  // namespace

int main(int argc, char** argv) {
    int phases = 50;
    uint64_t seed = 20261122;
    std::vector<std::string> only;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--phases") && i + 1 < argc)
            phases = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--model") && i + 1 < argc)
            only.push_back(argv[++i]);
        else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc)
            seed = std::strtoull(argv[++i], nullptr, 10);
        else {
            std::fprintf(stderr, "usage: %s [--phases N] [--model NAME]... [--seed S]\n", argv[0]);
            return 2;
        }
    }
    if (phases < 1) phases = 1;

    std::vector<Setting> settings;
    for (double s : {0.9, 0.6, 0.4, 0.2, 0.1, 0.05}) settings.push_back({"stability", s});
    for (double n : {5.0, 10.0, 20.0, 30.0, 50.0, 100.0}) settings.push_back({"resolution", n});

    std::printf(
        "Restitution error |e - e_exact| / e_exact over %d random phases of first touch;\n"
        "disk R = 0.1 m, 2600 kg/m^3, on a wall at 1 m/s. Time: median per impact,\n"
        "including the rig's set-up (one Model per impact). Seed %llu.\n\n",
        phases, static_cast<unsigned long long>(seed));
    for (const Config& c : configs()) {
        if (!only.empty() && std::find(only.begin(), only.end(), c.model) == only.end()) continue;
        std::vector<Setting> rows = settings;
        if (c.hertz_like)
            for (double s : {0.9, 0.4, 0.1}) rows.push_back({"stability+cap", s});
        std::printf("### %s (e_exact = %.6f)\n\n", c.label.c_str(), c.e_exact);
        std::printf(
            "| step rule | setting | steps in contact | mean error | worst error | time per impact "
            "|\n");
        std::printf("|---|---|---|---|---|---|\n");
        for (const Setting& st : rows) {
            const Row r = measure(c, st, phases, seed);
            const char* what = st.rule == "resolution" ? "steps per contact" : "safety";
            if (r.failed == phases) {
                std::printf("| %s | %s %g | - | failed | failed | - |\n", st.rule.c_str(), what,
                            st.value);
                std::fprintf(stderr, "%s, %s %g: %s\n", c.label.c_str(), st.rule.c_str(), st.value,
                             r.first_failure.c_str());
                continue;
            }
            const std::string note = r.failed ? " " + std::to_string(r.failed) + " failed" : "";
            std::printf("| %s | %s %g | %.1f | %s | %s | %.0f us |%s\n", st.rule.c_str(), what,
                        st.value, r.steps, percent(r.mean_err).c_str(),
                        percent(r.worst_err).c_str(), r.micros, note.c_str());
        }
        std::printf("\n");
    }
    return 0;
}
