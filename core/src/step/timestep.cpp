// SPDX-License-Identifier: MIT
//
// Phase 1: the time step (docs/physics/timestep.md).
//
// A stable step is not an accurate one (docs/physics/integration.md): PFC's
// 0.8 x critical step resolves an isolated impact in about four steps and misses its restitution
// by tens of percent. So in automatic mode the step is the smallest of
//   stability   safety * sqrt(m / k_tran), safety * sqrt(I / k_rot) per ball, with k summed over
//               its contacts' current tangent stiffnesses (knest + ksest, ksest r^2 + krest);
//   resolution  duration / N per contact (N = `resolution`, 30 by default), duration the model's
//               ContactDuration at touch or pi sqrt(m*/knest), whichever is shorter;
//   approach    for a pair not yet touching: it must not close more than half its gap in a step
//               unless the step already meets its resolution and stability limits, so every
//               impact starts at the resolved step;
//   kinematic   no body may leave its broadphase fat box within a step (then no contact can form
//               that the pairs above did not foresee);
//   damping     at most 1/c with mass-proportional viscous damping c;
//   growth      at most `growth` times the previous step; and `max`.
// A step no rule limits (nothing moves, accelerates or touches) is idle: bounded by the step the
// scene's pairs would need, never more than the previous one, and the step after it restarts
// the integrator (computeTimestep).
// Central differences integrate free flight under gravity exactly for any step sequence, so the
// large steps between impacts cost no accuracy.
// The stiffness and pair limits are gathered by the force loop of the previous cycle
// (force/loop.cpp), so this phase costs one pass over the balls and walls.
#include <algorithm>
#include <cmath>
#include <limits>

#include "force/force.hpp"
#include "step/detection.hpp"
#include "step/narrowphase.hpp"
#include "step/step.hpp"
#include "step/step_limits.hpp"
#include "talus/errors.hpp"
#include "world/body_store.hpp"
#include "world/contact_store.hpp"
#include "world/lanes.hpp"
#include "world/types.hpp"

namespace talus {

namespace {

/// Largest idle step [s]: nothing moves, so any step is exact, but simulated time should advance
/// at a pace a user can follow (and the first step after the scene wakes up is bounded anyway).
constexpr double kIdleStepCap = 1e-3;

/// Largest dt with  a/2 dt^2 + b dt <= c  (a, b, c >= 0).
double stepForDisplacement(double a, double b, double c) {
    if (c <= 0.0) return 0.0;
    if (a <= 0.0) return b > 0.0 ? c / b : std::numeric_limits<double>::infinity();
    return 2.0 * c / (b + std::sqrt(b * b + 2.0 * a * c));
}

/// Duration the resolution rule assumes: the model's estimate at this approach speed (skipped when
/// approach < 0), never more than the half period pi sqrt(m*/knest) of the tangent stiffness,
/// which includes the dashpot allowance the model reports.
double contactDuration(const ContactModel& model, double knest, double mass_eff, double approach) {
    double d = approach >= 0.0 ? model.ContactDuration(mass_eff, approach)
                               : std::numeric_limits<double>::infinity();
    // NaN or <= 0 breaks the ABI: refused, naming the model, at touch (activate).
    if (!(d > 0.0)) d = std::numeric_limits<double>::infinity();
    return std::min(d, tangentHalfPeriod(knest, mass_eff));
}

/// Duration of the contact a pair not yet touching is about to make, closing at speed v0 with
/// acceleration a. A nonlinear law's duration depends on the speed of the impact (Hertz:
/// v^-1/5), and the speed the bodies will have in the contact includes what the acceleration
/// adds over the contact's own time scale: D = dur(v0 + a D / pi), with dur the model's estimate
/// (contactDuration). For a body released at rest (v0 = 0) this is the quasi-static time scale of
/// the law under the load m a: for a linear spring a D / pi = a sqrt(m/k) is exactly the largest
/// speed of a mass released at touch; for Hertz the fixed point's speed is within 3% of
/// sqrt(1.2 a u_s), the largest speed of the oscillation about the static overlap u_s (the
/// speed at touch, v0 ~ 0, would give an infinite duration and no limit at all).
/// The fixed point is found by one secant step on ln dur(d) against ln d, exact for any power-law
/// duration (every shipped nonlinear law); the result min(D, dur(D)) is never above the fixed
/// point for a duration that does not grow with the speed, whatever the secant's error.
double approachDuration(const Pair& p, const PairCold& c, double m_eff, double v0, double a,
                        double start) {
    const auto dur = [&](double d) {
        return contactDuration(*p.model, c.knest, m_eff, v0 + a * d / M_PI);
    };
    const double d0 = dur(0.0);
    if (!(a > 0.0)) return d0;
    // Start at the duration at v0 or, when that is infinite (at rest), at `start`: the secant
    // step is exact for a power law from any start.
    const double x0 = std::log(d0 < std::numeric_limits<double>::infinity() ? d0 : start);
    const double d1 = dur(std::exp(x0));
    if (!(d1 > 0.0) || !(d1 < std::numeric_limits<double>::infinity())) return d1;
    const double x1 = std::log(d1);
    double x = x1;
    const double d2 = dur(d1);
    if (x1 != x0 && d2 > 0.0 && d2 < std::numeric_limits<double>::infinity()) {
        // ln dur is a line of slope s <= 0 in ln d through (x0, x1) and (x1, ln d2); its fixed
        // point. s is clamped to <= 0 (round-off) so the division is by >= 1.
        const double s = std::min(0.0, (std::log(d2) - x1) / (x1 - x0));
        x = (x1 - s * x0) / (1.0 - s);
    }
    const double d = std::exp(x);
    return std::min(d, dur(d));
}

/// The step a contact about to form will need: `safety` of its own time scale (sqrt(m/k) of its
/// stiffness, and duration / pi, which also covers laws with no stiffness at touch), and
/// duration / resolution. Infinite when the law gives neither (Hertz at rest, no load).
double contactStepLimit(const PairCold& c, double m_min, double duration,
                        const TimestepSettings& ts) {
    double lim = ts.safety *
                 std::min(std::sqrt(m_min / std::max(c.knest + c.ksest, 1e-300)), duration / M_PI);
    if (ts.resolution > 0.0) lim = std::min(lim, duration / ts.resolution);
    return lim;
}

double roomInside(const Box& fat, const Box& box) {
    return std::min(std::min(box.lo.x() - fat.lo.x(), fat.hi.x() - box.hi.x()),
                    std::min(box.lo.y() - fat.lo.y(), fat.hi.y() - box.hi.y()));
}

}  // namespace

double pebbleMassRatio(const World& world, const Pair& p) {
    // A contact on pebble s acts along a normal through the pebble's centre, so its arm about
    // the clump's centroid, (x_s - x_c) x n, is at most d_s = |x_s - x_c|, and the effective
    // mass of the clump at the contact, 1 / (1/m + ((x_s - x_c) x n)^2 / I), is at least
    // 1 / (1/m + d_s^2 / I). The pair's mass_eff uses m (PFC's choice, kept for the dashpots);
    // the time-step rules use this lower bound, so an off-centre impact is resolved as well as
    // a central one (docs/physics/clumps.md, "Time step").
    const auto& b = world.bodies.balls;
    bool off = false;
    auto lower = [&](uint32_t s) {
        const uint32_t k = b.clump[s];
        if (k == kNoClump) return b.mass[s];
        const ClumpData& c = world.bodies.clumps[k];
        const double d2 = (b.pos[s] - c.pos).squaredNorm();
        if (d2 == 0.0) return b.mass[s];
        off = true;
        return 1.0 / (c.inv_mass + d2 * c.inv_inertia);
    };
    const double m1 = lower(p.end1);
    const double m2 = p.wall ? 0.0 : lower(p.end2);
    if (!off) return 1.0;
    const double m_eff = p.wall ? m1 : m1 * m2 / (m1 + m2);
    return std::min(1.0, m_eff / world.contacts.coldOf(p).mass_eff);
}

void StepLimits::merge(const StepLimits& o) {
    takeStepLimit(stability, stability_key, stability_pair, o.stability, o.stability_key,
                  o.stability_pair);
    takeStepLimit(resolution, resolution_key, resolution_pair, o.resolution, o.resolution_key,
                  o.resolution_pair);
    takeStepLimit(approach, approach_key, approach_pair, o.approach, o.approach_key,
                  o.approach_pair);
}

void noteApproach(const World& world, const Pair& p, const PairCold& c, double gap,
                  const Vec2& vrel, double accel, const Vec2& normal, StepLimits& limits) {
    // A pair not yet touching may not close more than half its gap in one step (bounded with
    // the relative acceleration, so that bodies at rest are covered too), unless that step
    // already meets the limits the contact will have once it exists.
    const double t_free = stepForDisplacement(accel, vrel.norm(), 0.5 * std::max(gap, 0.0));
    // (a pair with this bound cannot lower the limit; a tie is settled by the pair index below)
    if (t_free > limits.approach) return;
    const auto& b = world.bodies.balls;
    const double m1 = b.mass[p.end1];
    const double m2 = p.wall ? 0.0 : b.mass[p.end2];
    double m_eff = p.wall ? m1 : m1 * m2 / (m1 + m2);
    double m_min = p.wall ? m1 : std::min(m1, m2);
    if (world.bodies.hasClumps()) {
        const double ratio = pebbleMassRatio(world, p);
        if (ratio != 1.0) m_eff *= ratio, m_min *= ratio;
    }
    // The impact's duration at the speed the bodies will have in it (approachDuration); the
    // relative acceleration's norm bounds its closing component.
    const double approach = std::max(0.0, -vrel.dot(normal));
    const double duration = approachDuration(p, c, m_eff, approach, accel,
                                             world.clock.dt > 0.0 ? world.clock.dt : 1e-3);
    const double d =
        std::max(t_free, contactStepLimit(c, m_min, duration, world.settings.timestep));
    takeStepLimit(limits.approach, limits.approach_key, limits.approach_pair, d, c.key,
                  static_cast<uint32_t>(world.contacts.pairIndex(p)));
}

void surveyPairs(World& world) {
    // The limits the force loop gathers, from the stored state, for a first step or after the
    // user changed the scene between runs.
    auto& b = world.bodies.balls;
    std::fill(b.k_tran.begin(), b.k_tran.end(), 0.0);
    std::fill(b.k_rot.begin(), b.k_rot.end(), 0.0);
    world.stepping.limits = StepLimits{};
    const bool ask = world.stepping.estimates_stale;
    world.stepping.estimates_stale = false;
    for (std::size_t i = 0; i < world.contacts.pairs.size(); ++i) {
        Pair& p = world.contacts.pairs[i];
        PairCold& cold = world.contacts.cold[i];
        if (ask && p.active) {
            // The last force loops ran with a fixed step and kept no estimates: the model's
            // own for its present state (its object brought up to date from its lane first).
            syncLane(world.contacts, p);
            cold.knest = p.model->KnEstimate();
            cold.ksest = p.model->KsEstimate();
        }
        const Vec2 x1 = b.pos[p.end1];
        ContactGeometry g;
        Vec2 v2(0.0, 0.0), x2(0.0, 0.0);
        double accel;
        if (p.wall) {
            if (!segmentGeometry(world, p.end2, x1, b.radius[p.end1], g)) continue;
            const WallData& w = world.bodies.walls[world.bodies.segments[p.end2].wall];
            x2 = w.center;
            v2 = w.vel + spinCross(w.spin, g.point - x2);
            accel =
                ((b.force[p.end1] + b.fapp[p.end1]) * b.inv_mass[p.end1] + world.settings.gravity)
                    .norm();
        } else {
            x2 = b.pos[p.end2];
            const Vec2 d = x2 - x1;
            const double dist = d.norm();
            g.normal = dist > 0.0 ? Vec2(d / dist) : Vec2(0.0, 1.0);
            g.overlap = b.radius[p.end1] + b.radius[p.end2] - dist;
            g.point = x1 + (b.radius[p.end1] - 0.5 * g.overlap) * g.normal;
            v2 = b.vel[p.end2];
            accel = ((b.force[p.end2] + b.fapp[p.end2]) * b.inv_mass[p.end2] -
                     (b.force[p.end1] + b.fapp[p.end1]) * b.inv_mass[p.end1])
                        .norm();
        }
        const Vec2 vrel = v2 - b.vel[p.end1];
        const double m1 = b.mass[p.end1];
        const double m_eff = p.wall ? m1 : m1 * b.mass[p.end2] / (m1 + b.mass[p.end2]);
        if (p.active || g.overlap > -cold.activity) {
            if (!p.active)
                cold.duration = p.model->ContactDuration(m_eff, std::max(0.0, -vrel.dot(g.normal)));
            noteContact(world, p, cold, cold.knest, cold.ksest, cold.krest,
                        (g.point - x1).squaredNorm(), p.wall ? 0.0 : (g.point - x2).squaredNorm(),
                        m_eff);
        } else {
            noteApproach(world, p, cold, -g.overlap, vrel, accel, g.normal, world.stepping.limits);
        }
    }
    world.stepping.limits_stale = false;
}

namespace {

/// The step the rules choose: the smallest so far, the rule that set it and where.
struct StepChoice {
    double dt = std::numeric_limits<double>::infinity();
    StepRule rule = StepRule::Max;
    StepWhere where;
    void take(double d, StepRule r, const StepWhere& w) {
        if (d < dt) dt = d, rule = r, where = w;
    }
};

/// The fixed step (or solveTime's cap on it).
void fixedStep(World& world) {
    world.stepping.idle = false;
    if (!(world.settings.timestep.fixed > 0.0) || !std::isfinite(world.settings.timestep.fixed))
        throw InputError("timestep: fixed step must be > 0 (got " +
                         std::to_string(world.settings.timestep.fixed) + ")");
    world.clock.dt = world.settings.timestep.fixed;
    world.stepping.rule = StepRule::Fixed;
    world.stepping.where = StepWhere{};
    if (world.stepping.cap > 0.0 && world.stepping.cap < world.clock.dt)
        world.clock.dt = world.stepping.cap;
}

void checkAutomaticSettings(const TimestepSettings& t) {
    if (!(t.safety > 0.0)) throw InputError("timestep: safety must be > 0");
    if (!(t.resolution >= 0.0)) throw InputError("timestep: resolution must be >= 0");
    if (!(t.growth > 1.0)) throw InputError("timestep: growth must be > 1");
    if (!(t.max > 0.0)) throw InputError("timestep: max must be > 0");
}

/// Stability, per ball, from the stiffness sums of the last force loop; and per clump
/// (docs/physics/clumps.md, "Time step"): the clump's mass over the sum of its pebbles'
/// translational stiffnesses, and its inertia over an upper bound of the rotational stiffness
/// about the centroid: a contact on pebble s at distance d_s from the centroid has the arm
/// d_s + r_s n, and kn (arm x n)^2 + ks (arm . t)^2 <= (kn + ks)(d_s^2 + 2 d_s r_s) + ks r_s^2, so
/// sum (k_rot[s] + k_tran[s] d_s (d_s + 2 r_s)) bounds it (exact at d_s = 0: a one-pebble clump
/// gets the ball's step).
void stabilityOfBodies(const World& world, StepChoice& choice) {
    const auto& b = world.bodies.balls;
    const double safety = world.settings.timestep.safety;
    const auto ball = [](uint32_t s) { return StepWhere{StepWhere::Ball, s, 0}; };
    for (std::size_t s = 0; s < b.size(); ++s) {
        const auto slot = static_cast<uint32_t>(s);
        if (b.k_tran[s] > 0.0)
            choice.take(safety * std::sqrt(b.mass[s] / b.k_tran[s]), StepRule::Stability,
                        ball(slot));
        if (b.k_rot[s] > 0.0)
            choice.take(safety * std::sqrt(b.inertia[s] / b.k_rot[s]), StepRule::Stability,
                        ball(slot));
    }
    if (!world.bodies.hasClumps()) return;
    for (const ClumpData& c : world.bodies.clumps) {
        if (!c.alive) continue;
        double kt = 0.0, kr = 0.0;
        for (std::size_t k = 0; k < c.pebbles.size(); ++k) {
            const uint32_t s = world.bodies.pebbleSlot(c, k);
            const double d = (b.pos[s] - c.pos).norm();
            kt += b.k_tran[s];
            kr += b.k_rot[s] + b.k_tran[s] * d * (d + 2.0 * b.radius[s]);
        }
        const uint32_t s0 = world.bodies.pebbleSlot(c, 0);
        if (kt > 0.0) choice.take(safety * std::sqrt(c.mass / kt), StepRule::Stability, ball(s0));
        if (kr > 0.0)
            choice.take(safety * std::sqrt(c.inertia / kr), StepRule::Stability, ball(s0));
    }
}

/// Stability, resolution and approach, per pair (gathered by the force loop).
void pairLimits(const World& world, StepChoice& choice) {
    const StepLimits& l = world.stepping.limits;
    const auto pair = [](uint64_t key) { return StepWhere{StepWhere::Pair, 0, key}; };
    choice.take(l.stability, StepRule::Stability, pair(l.stability_key));
    choice.take(l.resolution, StepRule::Resolution, pair(l.resolution_key));
    choice.take(l.approach, StepRule::Approach, pair(l.approach_key));
}

/// Kinematic: stay inside the fat boxes. Half the room, to leave the acceleration estimate
/// (contact forces change within the step) a factor of two.
void kinematicOfBalls(World& world, StepChoice& choice) {
    const auto& b = world.bodies.balls;
    const double half_prev = 0.5 * world.clock.dt_prev;
    for (std::size_t s = 0; s < b.size(); ++s) {
        const Vec2 acc = (b.force[s] + b.fapp[s]) * b.inv_mass[s] + world.settings.gravity;
        const double a = acc.norm(), v = b.vel[s].norm();
        if (a == 0.0 && v == 0.0) continue;
        const double room = roomInside(b.fat[s], ballBox(world, static_cast<uint32_t>(s)));
        // A ball already outside its box was moved or grown by the script between cycles
        // (b.radius, b.pos): this cycle's detection, after the motion, boxes it again and finds
        // its pairs. Limiting the step by a room of zero stopped the run ("automatic step became
        // 0 (kinematic rule)", met by material.lua's radius expansion).
        if (room <= 0.0) continue;
        choice.take(stepForDisplacement(a, v + a * half_prev, 0.5 * room), StepRule::Kinematic,
                    StepWhere{StepWhere::Ball, static_cast<uint32_t>(s), 0});
    }
    if (!world.bodies.hasClumps()) return;
    // A pebble accelerates with its clump: a_s = a_c + alpha x r - w^2 r, |a_s| <= |a_c| +
    // (|alpha| + w^2) d_s (the ball loop above used the pebble's own force only).
    gatherClumpForces(world);
    for (const ClumpData& c : world.bodies.clumps) {
        if (!c.alive) continue;
        const double ac = ((c.force + c.fapp) * c.inv_mass + world.settings.gravity).norm();
        const double al = std::fabs((c.moment + c.mapp) * c.inv_inertia);
        for (std::size_t k = 0; k < c.pebbles.size(); ++k) {
            const uint32_t s = world.bodies.pebbleSlot(c, k);
            const double dist = (b.pos[s] - c.pos).norm();
            const double a = ac + (al + c.spin * c.spin) * dist;
            const double v = b.vel[s].norm();
            if (a == 0.0 && v == 0.0) continue;
            const double room = roomInside(b.fat[s], ballBox(world, s));
            if (room <= 0.0) continue;  // re-boxed by this cycle's detection (above)
            choice.take(stepForDisplacement(a, v + a * half_prev, 0.5 * room), StepRule::Kinematic,
                        StepWhere{StepWhere::Ball, s, 0});
        }
    }
}

/// Kinematic, for the moving walls' segments (a servo's at its vmax: it sets its velocity after
/// this phase, wall_servo.cpp).
void kinematicOfWalls(const World& world, StepChoice& choice) {
    for (std::size_t w = 0; w < world.bodies.walls.size(); ++w) {
        const WallData& wd = world.bodies.walls[w];
        const double servo_v = wd.has_servo && wd.servo.settings.on ? wd.servo.settings.vmax : 0.0;
        if (!wd.alive || (wd.vel.squaredNorm() == 0.0 && wd.spin == 0.0 && servo_v == 0.0))
            continue;
        double reach = 0.0;
        for (uint32_t k = 0; k < wd.vertex_count; ++k)
            reach =
                std::max(reach, (world.bodies.vertices[wd.first_vertex + k] - wd.center).norm());
        const double v = wd.vel.norm() + servo_v + std::fabs(wd.spin) * reach;
        for (uint32_t k = 0; k < wd.segment_count; ++k) {
            const uint32_t sg = wd.first_segment + k;
            const double room = roomInside(world.bodies.segments[sg].fat, segmentBox(world, sg));
            choice.take(stepForDisplacement(0.0, v, 0.5 * std::max(room, 0.0)), StepRule::Kinematic,
                        StepWhere{StepWhere::Wall, static_cast<uint32_t>(w), 0});
        }
    }
}

/// Idle: no rule limits the step. No body moves or accelerates, no wall moves, nothing touches
/// with a stiffness. Any step is exact then, but the step must stay on the scene's own time
/// scales (doubling by the growth rule reached 6e26 s, then t = inf). It is the smallest step
/// the scene's pairs would need at their present closing speeds (the approach rule's limit),
/// never more than the previous step, and kept while the scene stays idle; at most 1 ms (a lone
/// body, or Hertz-type pairs that nothing presses, whose duration at zero closing speed is
/// unbounded: an idle ng pack took 3.5e149 s steps from it).
void idleStep(const World& world, double dt_last, bool surveyed, StepChoice& choice) {
    const auto& b = world.bodies.balls;
    choice.dt = dt_last > 0.0 ? dt_last : std::numeric_limits<double>::infinity();
    choice.rule = StepRule::Idle;
    choice.where = world.stepping.rule == StepRule::Idle ? world.stepping.where : StepWhere{};
    if (surveyed || !world.stepping.idle) {
        for (std::size_t i = 0; i < world.contacts.pairs.size(); ++i) {
            const Pair& p = world.contacts.pairs[i];
            const double m1 = b.mass[p.end1];
            const double m2 = p.wall ? 0.0 : b.mass[p.end2];
            const double m_eff = p.wall ? m1 : m1 * m2 / (m1 + m2);
            const double m_min = p.wall ? m1 : std::min(m1, m2);
            const PairCold& c = world.contacts.cold[i];
            const double d = contactStepLimit(
                c, m_min, approachDuration(p, c, m_eff, 0.0, 0.0, 1.0), world.settings.timestep);
            if (d < choice.dt) choice.dt = d, choice.where = StepWhere{StepWhere::Pair, 0, c.key};
        }
    }
    choice.dt = std::min(choice.dt, kIdleStepCap);
}

/// The bounds on any automatic step: mass-proportional viscous damping's own time scale 1/c (the
/// implicit update keeps (1 - c w/2) / (1 + c w/2) of the velocity per step, which turns
/// negative past c w = 2: a ball creeping at nm/s in free flight otherwise takes 1e5 s steps from
/// the kinematic rule, stress suite seeds 74, 397, 401), `max`, `growth` and solveTime's cap.
void boundStep(const World& world, bool idle, StepChoice& choice) {
    const double c = world.settings.damping.viscous;
    if (!idle && c > 0.0 && 1.0 / c < choice.dt) choice = {1.0 / c, StepRule::Damping, {}};
    if (world.settings.timestep.max < choice.dt)
        choice = {world.settings.timestep.max, StepRule::Max, {}};
    const double grown = world.settings.timestep.growth * world.clock.dt_prev;
    if (!idle && world.clock.dt_prev > 0.0 && choice.dt > grown)
        choice = {grown, StepRule::Growth, {}};
    if (world.stepping.cap > 0.0 && world.stepping.cap < choice.dt) choice.dt = world.stepping.cap;
}

}  // namespace

void computeTimestep(World& world) {
    // The previous step: the growth rule's base. After an idle step (nothing moved and nothing
    // accelerated, see below) the half-step velocities are the velocities at this instant, so
    // the integrator starts afresh as at the first cycle (window dt/2, law_of_motion.cpp): what
    // appeared since (gravity, an applied force, a velocity) acts from now, not over half an
    // idle step before it.
    const double dt_last = world.clock.dt;
    world.clock.dt_prev = world.stepping.idle ? 0.0 : world.clock.dt;
    if (!world.settings.timestep.automatic) return fixedStep(world);
    checkAutomaticSettings(world.settings.timestep);
    // The approach limits were gathered with the accelerations of the last force loop: a change
    // of gravity (or of an applied force, setBallAppliedForce) since then needs a new survey.
    const bool surveyed =
        world.stepping.limits_stale || world.settings.gravity != world.stepping.limits_gravity;
    if (surveyed) surveyPairs(world);
    world.stepping.limits_gravity = world.settings.gravity;

    StepChoice choice;
    stabilityOfBodies(world, choice);
    pairLimits(world, choice);
    if (world.contacts.broadphase_ready) {
        kinematicOfBalls(world, choice);
        kinematicOfWalls(world, choice);
    }
    bool idle = false;
    if (!(choice.dt < std::numeric_limits<double>::infinity())) {
        idle = true;
        idleStep(world, dt_last, surveyed, choice);
    }
    boundStep(world, idle, choice);
    if (!(choice.dt > 0.0) || !(choice.dt < std::numeric_limits<double>::infinity()))
        throw NumericalError("timestep: the automatic step became " + std::to_string(choice.dt) +
                             " (" + std::string(stepRuleName(choice.rule)) + " rule)");
    // The next step restarts the integrator only if this one was idle in rotation too (no
    // moment: a spin changing under an applied moment keeps its half-step history).
    const auto& b = world.bodies.balls;
    if (idle)
        for (std::size_t s = 0; s < b.size() && idle; ++s) idle = b.moment[s] + b.mapp[s] == 0.0;
    if (idle)
        for (const ClumpData& c : world.bodies.clumps) idle = idle && (!c.alive || c.mapp == 0.0);
    world.stepping.idle = idle;
    world.clock.dt = choice.dt;
    world.stepping.rule = choice.rule;
    world.stepping.where = choice.where;
}

}  // namespace talus
