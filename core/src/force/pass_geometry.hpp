// SPDX-License-Identifier: MIT
//
// Pass 1 of the force loop: a pair's narrowphase geometry and, for a contact, the kinematic
// inputs of its law (FdBlock's u_n, u_dot_n, u_dot_s, t_dot_rel at the half step). No side
// effects: what the pair is this step (PairStep) decides what the next passes do. Not
// installed.
//
// Frame: n from end 1 to end 2, t = perp(n); rates are end 2's contact point relative to end 1's.
#pragma once

#include <cmath>
#include <cstddef>

#include "force/view.hpp"
#include "step/detection.hpp"
#include "step/narrowphase.hpp"

namespace talus {

/// A contact's law inputs into a block with FdBlock's names (its FdBlock, or a kernel's
/// KernelFd): the step's constants, pass 1's rates and their increments over the step, the law's
/// forces of the last step.
template <class Fd>
__attribute__((always_inline)) inline void fillLawInputs(const ForceView& v, const Pair& p,
                                                         double overlap, double u_dot_n,
                                                         double u_dot_s, double t_dot_rel, Fd& fd) {
    fd.flags = v.fd_template.flags;
    fd.tdel = v.dt;
    fd.time = v.fd_template.time;
    fd.u_n = overlap;
    fd.u_dot_n = u_dot_n;
    fd.u_dot_s = u_dot_s;
    fd.t_dot_rel = t_dot_rel;
    fd.du_n = fd.u_dot_n * v.dt;
    fd.du_s = fd.u_dot_s * v.dt;
    fd.dtheta = fd.t_dot_rel * v.dt;
    fd.n_force = p.n_force;
    fd.s_force = p.s_force;
    fd.moment = p.moment;
}

/// A contact's FdBlock from its geometry. Only what changes from contact to contact is written:
/// the rest is the step's template (the thread's copy).
template <class Features>
__attribute__((always_inline)) inline void fillFd(const ForceView& v, std::size_t i, double overlap,
                                                  double u_dot_n, double u_dot_s, double t_dot_rel,
                                                  FdBlock& fd) {
    const PairCold& c = v.cold[i];
    fillLawInputs(v, v.pairs[i], overlap, u_dot_n, u_dot_s, t_dot_rel, fd);
    fd.status = 0;
    fd.mass_eff = c.mass_eff;
    fd.inv_mass_eff_s = c.inv_mass_eff_s;
    fd.knest = fd.ksest = fd.krest = 0.0;
    if constexpr (Features::kEnergy)
        for (double& en : fd.energy) en = 0.0;
}

/// The geometry of pair i into `e` and, for a contact, the law's inputs: into `fd` when given,
/// else into `e` (a lane block's pass 1).
template <class Features>
__attribute__((always_inline)) inline PairStep geometryPass(const ForceView& v, std::size_t i,
                                                            PairEntry& e, FdBlock* fd) {
    const Pair& p = v.pairs[i];
    const uint32_t s1 = p.end1;
    const Vec2 x1 = v.pos[s1];
    const double r1 = v.radius[s1];
    const double dt = v.dt;
    ContactGeometry& g = e.g;
    Vec2 v2c;
    double spin2;
    double shear_mid = 0.0;  // ball-ball: the shear rate's half-step correction (below)
    if (!p.wall) {
        const uint32_t s2 = p.end2;
        const Vec2 x2 = v.pos[s2];
        const Vec2 d = x2 - x1;
        const double rsum = r1 + v.radius[s2];
        const double dist2 = d.squaredNorm();
        const double reach = rsum + v.rule(p).activity;  // (a pair apart has its rule's)
        if (!p.active && dist2 >= reach * reach) return PairStep::Apart;
        const double dist = std::sqrt(dist2);
        g.normal = dist > 0.0 ? Vec2(d * (1.0 / dist)) : Vec2(0.0, 1.0);
        g.overlap = rsum - dist;
        g.point = x1 + (r1 - 0.5 * g.overlap) * g.normal;
        e.x2 = x2;
        v2c = v.vel[s2] + spinCross(v.spin[s2], g.point - x2);
        spin2 = v.spin[s2];
        // The shear rate at the half step. The centre line's sweep dv . t, seen from the new
        // normal, is |d_old| sin(dphi) / dt (the chord of the step), while the spin terms use
        // the new arms, which sum to |d_new|. When the distance changes as the line turns (a
        // rotating bonded cluster breathing under its centripetal load), the difference
        // (|d_old| - |d_new|) dphi / dt feeds the normal motion into the shear spring: a
        // one-sided coupling that does net work over each oscillation and pumps energy in at a
        // rate O(dt) (a spinning bonded ring of three balls blew up). Both at the half step,
        // mean length (|d_old| + |d_new|) / 2 and mean arms, cancel it to second order:
        // u_dot_s += -(q/2) (dv.t / |d_old| + (w1 + w2) / 2) with q = |d_old| - |d_new|
        // (docs/plugin-abi.md, u_dot_s).
        const Vec2 dv = v.vel[s2] - v.vel[s1];
        const double dist_old = (d - dv * dt).norm();
        if (dist_old > 0.0) {
            const double q = dist_old - dist;
            shear_mid =
                -0.5 * q * (dv.dot(perp(g.normal)) / dist_old + 0.5 * (v.spin[s1] + v.spin[s2]));
        }
    } else {
        // The ball is in a neighbouring segment's region: that segment holds the contact.
        if (!segmentGeometry(v.world, p.end2, x1, r1, g))
            return p.active ? PairStep::HandOver : PairStep::Elsewhere;
        const WallData& wall = v.walls[v.segments[p.end2].wall];
        e.x2 = wall.center;
        v2c = wall.vel + spinCross(wall.spin, g.point - wall.center);
        spin2 = wall.spin;
        // The spin part of the shear rate at the half step, as for two balls (above): the lever
        // arm to the contact point shrinks by du_n / 2 over the step, and the arm at the new
        // overlap alone lets a contact that breathes under load while the ball rocks pump energy
        // through its shear spring (a bonded ball in a V lost -2.7% of its input). The mean arm
        // adds (du_n / 4) (w1 + w2) / dt.
        shear_mid = -0.25 * (v.vel[s1] - v2c).dot(g.normal) * dt * (v.spin[s1] + spin2);
        if (!p.active && g.overlap <= -v.rule(p).activity) return PairStep::Apart;
    }
    const Vec2 v1c = v.vel[s1] + spinCross(v.spin[s1], g.point - x1);
    const Vec2 vrel = v2c - v1c;
    e.vrel = vrel;
    const double u_dot_n = -vrel.dot(g.normal);
    const double u_dot_s = vrel.dot(perp(g.normal)) + shear_mid;
    const double t_dot_rel = spin2 - v.spin[s1];
    if (fd) {
        fillFd<Features>(v, i, g.overlap, u_dot_n, u_dot_s, t_dot_rel, *fd);
    } else {
        e.u_dot_n = u_dot_n;
        e.u_dot_s = u_dot_s;
        e.t_dot_rel = t_dot_rel;
    }
    return p.active ? PairStep::Contact : PairStep::Touch;
}

}  // namespace talus
