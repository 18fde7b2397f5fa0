// SPDX-License-Identifier: MIT
//
// Phase 2: the law of motion. Central differences (leapfrog) with velocities at half steps:
//   v(t + dt/2) = v(t - dt/2) + (F/m + g) w,   x(t + dt) = x(t) + v(t + dt/2) dt,
// where w = (dt_prev + dt)/2 is the time between the two half steps. With that window a
// constant acceleration is integrated exactly for any sequence of steps (free flight costs no
// accuracy). On the very first cycle the given velocities are taken as values at t, so w = dt/2.
//
// Damping options (docs/physics/damping.md):
//  - PFC local damping: F_i <- F_i - alpha |F_i| sign(v_i) per degree of freedom
//    (accuracy-reference 3.4).
//  - Mass-proportional viscous damping c [1/s], implicit at the time level of the forces
//    (thesis B eq. 2.41): v+ = ((1 - c w/2) v- + a w) / (1 + c w/2).
//
// Energy (only when traced): the kinetic energy at whole step t is taken as
// (1/2) m v(t - dt/2).v(t + dt/2); with that definition a leapfrog step satisfies the
// work-energy theorem exactly for trapezoidal work (docs/physics/energy.md).
#include <cmath>

#include "model_internal.hpp"

namespace talus {

namespace {

inline double localDamping(double alpha, double force, double vel) {
    if (vel == 0.0) return 0.0;
    return -alpha * std::fabs(force) * (vel > 0.0 ? 1.0 : -1.0);
}

}  // namespace

void Model::lawOfMotion() {
    auto& b = *m_balls;
    const std::size_t n = b.size();
    const double dt = m_dt;
    const double w = m_first_cycle ? 0.5 * dt : 0.5 * (m_dt_prev + dt);
    const double alpha = m_damping.local;
    const double c = m_damping.viscous;
    const double keep = (1.0 - 0.5 * c * w) / (1.0 + 0.5 * c * w);
    const double gain = w / (1.0 + 0.5 * c * w);
    const bool energy = m_energy_on;

    double kinetic = 0.0, body = 0.0, damping = 0.0;
    for (std::size_t s = 0; s < n; ++s) {
        const Vec2 v_old = b.vel[s];
        const double w_old = b.spin[s];
        const uint8_t fix = b.fixity[s];
        Vec2 f = b.force[s] + b.fapp[s];
        double mom = b.moment[s] + b.mapp[s];
        Vec2 fd = Vec2::Zero();
        double md = 0.0;
        if (alpha > 0.0) {
            // PFC applies the damping to the unbalanced force including gravity.
            const Vec2 unbalanced = f + b.mass[s] * m_gravity;
            fd = Vec2(localDamping(alpha, unbalanced.x(), v_old.x()),
                      localDamping(alpha, unbalanced.y(), v_old.y()));
            md = localDamping(alpha, mom, w_old);
        }
        const Vec2 acc = (f + fd) * b.inv_mass[s] + m_gravity;
        const double ang = (mom + md) * b.inv_inertia[s];
        Vec2 v = v_old;
        double spin = w_old;
        if (c > 0.0) {
            if (!(fix & kFixX)) v.x() = keep * v.x() + gain * acc.x();
            if (!(fix & kFixY)) v.y() = keep * v.y() + gain * acc.y();
            if (!(fix & kFixSpin)) spin = keep * spin + gain * ang;
        } else {
            if (!(fix & kFixX)) v.x() += acc.x() * w;
            if (!(fix & kFixY)) v.y() += acc.y() * w;
            if (!(fix & kFixSpin)) spin += ang * w;
        }
        b.vel[s] = v;
        b.spin[s] = spin;
        b.pos[s] += v * dt;
        b.angle[s] += spin * dt;
        if (!std::isfinite(b.pos[s].x() + b.pos[s].y() + v.x() + v.y() + spin))
            throwNonFinite(describeBall(static_cast<uint32_t>(s)) + ": velocity (" +
                           std::to_string(v.x()) + ", " + std::to_string(v.y()) + "), spin " +
                           std::to_string(spin) + ", contact force (" +
                           std::to_string(b.force[s].x()) + ", " + std::to_string(b.force[s].y()) +
                           ")");
        if (energy) {
            const double m = b.mass[s];
            kinetic += 0.5 * (m * v_old.dot(v) + b.inertia[s] * w_old * spin);
            body += (m * m_gravity + b.fapp[s]).dot(v) * dt + b.mapp[s] * spin * dt;
            // Work of the damping impulse on the half-step kinetic energy.
            Vec2 dmp = fd;
            if (c > 0.0) dmp -= c * m * 0.5 * (v_old + v);
            damping -= w * (dmp.dot(0.5 * (v_old + v)) + md * 0.5 * (w_old + spin));
        }
    }
    if (energy) {
        // Snapshot at the whole step t (before this step's work is added).
        m_energy = m_energy_acc;
        m_energy.kinetic = kinetic;
        m_energy_acc.body += body;
        m_energy_acc.damping += damping;
    }
    m_first_cycle = false;
    m_time += dt;
    ++m_step;
}

void Model::moveWalls() {
    const double dt = m_dt;
    for (std::size_t i = 0; i < m_walls.size(); ++i) {
        WallData& w = m_walls[i];
        if (!w.alive || (w.vel.squaredNorm() == 0.0 && w.spin == 0.0)) continue;
        if (m_energy_on)
            // Work done on the balls: minus the force they exert on the wall times its motion.
            m_energy_acc.boundary -= (w.force.dot(w.vel) + w.moment * w.spin) * dt;
        const Vec2 shift = w.vel * dt;
        const double ca = std::cos(w.spin * dt), sa = std::sin(w.spin * dt);
        for (uint32_t k = 0; k < w.vertex_count; ++k) {
            Vec2& p = m_vertices[w.first_vertex + k];
            const Vec2 r = p - w.center;
            p = w.center + Vec2(ca * r.x() - sa * r.y(), sa * r.x() + ca * r.y()) + shift;
        }
        w.center += shift;
    }
}

}  // namespace talus
