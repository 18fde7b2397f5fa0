// SPDX-License-Identifier: MIT
//
// What a contact adds to the next automatic step, every step (timestep.cpp has the rules;
// docs/physics/timestep.md): here, inline, because the force loop calls it for every contact and
// a call into another file per contact cost more than the work (the 5 000-ball UCS benchmark). Not
// installed.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "world/world.hpp"

namespace talus {

void noteApproach(const World& world, const Pair& p, const PairCold& c, double gap,
                  const Vec2& vrel, double accel, const Vec2& normal, StepLimits& limits);
/// For a pair with a pebble end off its clump's centroid: the lower bound of the true effective
/// mass over the pair's (clump) effective mass, <= 1; 1 otherwise (timestep.cpp).
double pebbleMassRatio(const World& world, const Pair& p);

/// One limit of StepLimits: the smaller value, the lower pair on a tie (the first in pair order).
inline void takeStepLimit(double& value, uint64_t& key, uint32_t& pair, double v, uint64_t k,
                          uint32_t i) {
    if (v < value || (v == value && i < pair)) value = v, key = k, pair = i;
}

/// The half period pi sqrt(m*/knest) of a contact's tangent stiffness, which includes the
/// dashpot allowance the model reports; infinite without a stiffness.
inline double tangentHalfPeriod(double knest, double mass_eff) {
    return knest > 0.0 ? M_PI * std::sqrt(mass_eff / knest)
                       : std::numeric_limits<double>::infinity();
}

inline void noteContactLimits(const World& world, const Pair& p, const PairCold& c, double kn,
                              double mass_eff, StepLimits& limits) {
    // Every active contact, bonded or not, gets the impact rules below (docs/models/cbond.md,
    // "Time-step contract"): a contact bonded as it touches is an impact all the same (
    // item 6: with the stability rule alone it took 4-5 steps and created up to 38% energy). A
    // quasi-static bonded specimen turns resolution off (`resolution = 0`). The duration: the
    // model's estimate at touch, never more than the tangent's half period.
    double duration = std::min(c.duration, tangentHalfPeriod(kn, mass_eff));
    if (world.bodies.hasClumps()) {
        // Off-centre pebble: the duration with the lower bound of the effective mass. It scales
        // as sqrt(m) for a linear law and as m^(2/5) for Hertz; sqrt(ratio) <= ratio^(2/5) for
        // ratio <= 1, so scaling by sqrt is never less strict.
        const double ratio = pebbleMassRatio(world, p);
        if (ratio != 1.0) duration *= std::sqrt(ratio);
    }
    // A law whose tangent stiffness starts at zero (Hertz) would let the stability rule take
    // large steps early in an impact: bound the step by `safety` of the impact's time scale.
    const auto i = static_cast<uint32_t>(world.contacts.pairIndex(p));
    takeStepLimit(limits.stability, limits.stability_key, limits.stability_pair,
                  world.settings.timestep.safety * duration / M_PI, c.key, i);
    if (world.settings.timestep.resolution > 0.0)
        takeStepLimit(limits.resolution, limits.resolution_key, limits.resolution_pair,
                      duration / world.settings.timestep.resolution, c.key, i);
}

inline void noteContact(World& world, const Pair& p, const PairCold& c, double kn, double ks,
                        double kr, double arm1_sq, double arm2_sq, double mass_eff) {
    auto& b = world.bodies.balls;
    b.k_tran[p.end1] += kn + ks;
    b.k_rot[p.end1] += ks * arm1_sq + kr;
    if (!p.wall) {
        b.k_tran[p.end2] += kn + ks;
        b.k_rot[p.end2] += ks * arm2_sq + kr;
    }
    noteContactLimits(world, p, c, kn, mass_eff, world.stepping.limits);
}

}  // namespace talus
