// SPDX-License-Identifier: MIT
//
// Phase 2 for clumps (docs/physics/clumps.md, "Law of motion"). A clump is integrated exactly as a
// ball is by the general loop of law_of_motion.cpp (same central-difference update, same local
// and viscous damping, same fixity rule, same energy snapshot), with
//   F = sum over pebbles of their contact forces (+ the clump's applied force),
//   M = sum over pebbles of (pebble moment + (x_s - x_c) x F_s) (+ the applied moment),
// and m, I the clump's mass and its scalar inertia about the centroid. In 2D the angular
// velocity is a scalar and I does not change with the orientation, so Euler's equations reduce
// to I dw/dt = M: no gyroscopic term. The pebbles then follow
// rigidly: x_s = x_c + R(theta) r_s, v_s = v_c + w x (x_s - x_c), w_s = w.
//
// The operation order matches the ball loop's, so a clump of one pebble at its centroid (arm 0)
// moves bit for bit as the same ball (tests/core/test_clumps.cpp).
#include <cmath>

#include "step/body_damping.hpp"
#include "step/group_energy.hpp"
#include "step/step.hpp"
#include "world/body_store.hpp"
#include "world/types.hpp"

namespace talus {

void sumPebbleForces(const World& world, const ClumpData& c, Vec2& force, double& moment) {
    const auto& b = world.bodies.balls;
    Vec2 f = Vec2::Zero();
    double m = 0.0;
    for (std::size_t k = 0; k < c.pebbles.size(); ++k) {
        const uint32_t s = world.bodies.pebbleSlot(c, k);
        f += b.force[s];
        m += b.moment[s] + cross(b.pos[s] - c.pos, b.force[s]);
    }
    force = f;
    moment = m;
}

void gatherClumpForces(World& world) {
    for (ClumpData& c : world.bodies.clumps)
        if (c.alive) sumPebbleForces(world, c, c.force, c.moment);
}

void placePebbles(World& world, const ClumpData& c) {
    auto& b = world.bodies.balls;
    const double ca = std::cos(c.angle), sa = std::sin(c.angle);
    for (std::size_t k = 0; k < c.pebbles.size(); ++k) {
        const uint32_t s = world.bodies.pebbleSlot(c, k);
        const Vec2& o = c.offset[k];
        const Vec2 r(ca * o.x() - sa * o.y(), sa * o.x() + ca * o.y());
        b.pos[s] = c.pos + r;
        b.vel[s] = c.vel + spinCross(c.spin, r);
        b.spin[s] = c.spin;
        b.angle[s] = c.angle + c.angle_offset[k];
    }
}

void moveClumps(World& world, const StepContext& step, double& kinetic, double& body,
                double& damping, double& driven) {
    gatherClumpForces(world);
    const double dt = step.dt;
    const double w = step.window;
    const Vec2 g = world.settings.gravity;
    const double alpha = world.settings.damping.local;
    const double c = world.settings.damping.viscous;
    const double keep = (1.0 - 0.5 * c * w) / (1.0 + 0.5 * c * w);
    const double gain = w / (1.0 + 0.5 * c * w);
    const bool energy = step.energy;
    const double lead = w > 0.0 ? 0.5 * step.dt_prev / w : 0.0;
    for (ClumpData& cl : world.bodies.clumps) {
        if (!cl.alive) continue;
        const Vec2 v_old = cl.vel;
        const double w_old = cl.spin;
        const uint8_t fix = cl.fixity;
        const Vec2 f = cl.force + cl.fapp;
        const double mom = cl.moment + cl.mapp;
        Vec2 fd = Vec2::Zero();
        double md = 0.0;
        if (alpha > 0.0) {
            // PFC's per-component rule on the unbalanced force including gravity, as for balls.
            const Vec2 unbalanced = f + cl.mass * g;
            fd = Vec2(localDamping(alpha, unbalanced.x(), v_old.x()),
                      localDamping(alpha, unbalanced.y(), v_old.y()));
            md = localDamping(alpha, mom, w_old);
        }
        const Vec2 acc = (f + fd) * cl.inv_mass + g;
        const double ang = (mom + md) * cl.inv_inertia;
        Vec2 v = keep * v_old + gain * acc;
        double om = keep * w_old + gain * ang;
        double cx = c, cy = c, cw = c;
        if (fix) {
            if (fix & kFixX) v.x() = v_old.x(), fd.x() = 0.0, cx = 0.0;
            if (fix & kFixY) v.y() = v_old.y(), fd.y() = 0.0, cy = 0.0;
            if (fix & kFixSpin) om = w_old, md = 0.0, cw = 0.0;
        }
        cl.vel = v;
        cl.spin = om;
        cl.pos += v * dt;
        cl.angle += om * dt;
        if (energy) {
            // The clump's energy terms, in one place (per-group books route them by cl.groups):
            // kinetic 1/2 (m v^2 + I w^2) at the whole step, body work (m g + F_app) . v dt +
            // M_app w dt, damping work, fixity reactions -> boundary; the same expressions as
            // the ball loop's (law_of_motion.cpp, docs/physics/energy.md).
            const double m = cl.mass;
            const double inertia = cl.inertia;
            const Vec2 v_now = v_old + (v - v_old) * lead;
            const double om_now = w_old + (om - w_old) * lead;
            const double ke = 0.5 * (m * v_now.squaredNorm() + inertia * om_now * om_now);
            const double work = ((m * g + cl.fapp).dot(v) + cl.mapp * om) * dt;
            kinetic += ke;
            body += work;
            // As for a ball (body_damping.hpp).
            const Vec2 v_mid = 0.5 * (v_old + v);
            const double om_mid = 0.5 * (w_old + om);
            const double damp =
                dampingWork(w, fd, md, v_now, om_now, v_mid, om_mid, m, inertia, cx, cy, cw);
            damping += damp;
            double react = 0.0;
            if (fix) {
                const Vec2 load = f + m * g;
                if (fix & kFixX) react -= load.x() * v.x();
                if (fix & kFixY) react -= load.y() * v.y();
                if (fix & kFixSpin) react -= mom * om;
                driven += react * w;
            }
            // A clump is one body of its groups (its pebbles are not counted on their own).
            if (world.books.groups.on)
                bookBodyToGroups(world, cl.groups, ke, work, damp, react * w);
        }
        placePebbles(world, cl);
    }
}

}  // namespace talus
