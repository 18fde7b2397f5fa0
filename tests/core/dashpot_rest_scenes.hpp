// SPDX-License-Identifier: MIT
//
// Persistent-contact scenes for the dashpot's equilibrium tests, shared by the
// linear model's tests (tests/core/test_restitution.cpp) and every other model with a dashpot
// (tests/plugins/test_hertz.cpp). Each scene is run with the engine's automatic step and read
// out after the transient has decayed; the closed forms are in the test files.
//
//  - a ball resting on a floor: the floor reaction must equal the weight, the dashpot force must
//    vanish (the spring carries the load) and no dashpot work may be booked while nothing moves;
//  - a column of balls on a floor: the bottom reaction is the total weight and every contact's
//    spring carries the weight above it;
//  - a disk sliding down an inclined wall: steady sliding, acceleration and slip rate against the
//    rigid-body closed forms.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "talus/model.hpp"

namespace talus::restscene {

constexpr double kGravity = 9.81;

struct RestResult {
    double weight = 0.0;          ///< total weight of the balls [N]
    double reaction_error = 0.0;  ///< (floor reaction - weight) / weight
    double spring_error = 0.0;    ///< worst |normal force - dashpot force - load| / weight
    double dashpot_force = 0.0;   ///< worst |dashpot normal force| / weight
    double dashpot_growth = 0.0;  ///< dashpot work booked over the last `hold` steps [J]
    double strain = 0.0;          ///< strain energy stored at the end [J] (scale of the above)
    double kinetic = 0.0;         ///< kinetic energy at the end [J]
};

/// `n` balls of radius r stacked on a floor (n = 1: a resting ball), released a small gap apart,
/// settled for `settle` seconds and then held for `hold` steps. `dp_fn` names the model's normal
/// dashpot force property.
inline RestResult restingColumn(const std::string& model, const std::vector<PropValue>& props,
                                int n, double settle, int64_t hold,
                                const std::string& dp_fn = "dp_fn") {
    ModelDef def;
    def.gravity = Vec2(0.0, -kGravity);
    Model m(def);
    m.setDefaultContactModel(model, props);
    WallDef floor;
    floor.points = {Vec2(-1.0, 0.0), Vec2(1.0, 0.0)};
    const WallId w = m.createWall(floor);
    const double r = 0.1, gap = 1e-4;
    std::vector<BallId> balls;
    RestResult out;
    for (int i = 0; i < n; ++i) {
        BallDef b;
        b.pos = Vec2(0.0, r + i * 2.0 * r + (i + 1) * gap);
        b.radius = r;
        b.density = 1000.0;
        balls.push_back(m.createBall(b));
        out.weight += m.ballMass(balls.back()) * kGravity;
    }
    m.setEnergyTracing(true);
    m.solveTime(settle);
    const double dashpot_before = m.energies().dashpot;
    m.cycle(hold);
    const EnergyTotals e = m.energies();
    out.dashpot_growth = e.dashpot - dashpot_before;
    out.strain = e.strain;
    out.kinetic = e.kinetic;
    out.reaction_error = (-m.wallForce(w).y() - out.weight) / out.weight;
    for (const ContactInfo& c : m.contacts()) {
        // The load on a contact is the weight of the balls above it: above the floor, all of
        // them; above the contact between balls i and i+1, the n - i - 1 upper ones.
        // Of two balls the lower id, the lower ball, is end 1.
        int above = n;
        if (c.ball2.valid())
            for (int i = 0; i < n; ++i)
                if (balls[static_cast<std::size_t>(i)] == c.ball1) above = n - i - 1;
        const double load = out.weight * above / n;
        const double dp = m.contactProp(c.key, dp_fn);
        out.dashpot_force = std::max(out.dashpot_force, std::fabs(dp) / out.weight);
        out.spring_error =
            std::max(out.spring_error, std::fabs(c.normal_force - dp - load) / out.weight);
    }
    return out;
}

struct SlideResult {
    double accel = 0.0;       ///< acceleration of the centre along the slope [m/s^2]
    double spin_accel = 0.0;  ///< angular acceleration, clockwise positive [rad/s^2]
    double slip = 0.0;        ///< slip speed of the contact point down the slope at the end [m/s]
    double mass = 0.0, radius = 0.0;
    double lever = 0.0;  ///< centre to contact point, r - overlap/2 (narrowphase.hpp) [m]
};

/// A disk (radius 0.1 m, density 1000) released on a wall inclined at `theta` [rad], sliding
/// down it; accelerations measured between t = settle and t = settle + measure. Leapfrog
/// integrates a constant acceleration exactly for any step sequence, and a velocity read after a
/// step dt belongs to the time t - dt/2, so the difference quotient is exact.
inline SlideResult slidingDisk(const std::string& model, const std::vector<PropValue>& props,
                               double theta, double settle, double measure) {
    ModelDef def;
    def.gravity = Vec2(0.0, -kGravity);
    Model m(def);
    m.setDefaultContactModel(model, props);
    const Vec2 down(std::cos(theta), -std::sin(theta));   // down the slope
    const Vec2 normal(std::sin(theta), std::cos(theta));  // out of the slope
    WallDef slope;
    slope.points = {-1.0 * down, 40.0 * down};
    m.createWall(slope);
    SlideResult out;
    out.radius = 0.1;
    BallDef b;
    b.pos = (out.radius + 1e-5) * normal;
    b.radius = out.radius;
    b.density = 1000.0;
    const BallId id = m.createBall(b);
    out.mass = m.ballMass(id);
    m.solveTime(settle);
    const double t1 = m.time() - 0.5 * m.lastTimestep();
    const double v1 = m.ballVel(id).dot(down), w1 = m.ballSpin(id);
    m.solveTime(measure);
    const double t2 = m.time() - 0.5 * m.lastTimestep();
    const double v2 = m.ballVel(id).dot(down), w2 = m.ballSpin(id);
    out.accel = (v2 - v1) / (t2 - t1);
    out.spin_accel = -(w2 - w1) / (t2 - t1);
    // Contact point velocity down the slope: v + spin x (-r n); spin counter-clockwise positive.
    const std::vector<ContactInfo> cs = m.contacts();
    out.lever = out.radius - (cs.empty() ? 0.0 : 0.5 * cs.front().overlap);
    out.slip = v2 + m.ballSpin(id) * out.lever;
    return out;
}

}  // namespace talus::restscene
