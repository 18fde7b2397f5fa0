// SPDX-License-Identifier: MIT
//
// Barriers (docs/rockfall.md, "Barriers"): a segment with an energy capacity E, as a rockfall
// fence or net is rated (its maximum energy level; EOTA 2018). A body is caught at the
// first step its centre crosses the barrier's line from its left to its right (looking from
// `from` to `to`: a barrier from its foot up to its top catches bodies moving toward +x) with its
// equivalent disk on the segment (the crossing point within its radius of it). A body is judged
// once, at its first crossing above the foot: one that passes over the top is never caught. Its
// kinetic energy there, KE, is that of the state at the line (step/crossing.hpp), with the
// trackers' acceleration: gravity for a body in free flight over the step (no contact force before
// it, no overlap after it, only gravity acting), else the change of the half-step velocity over the
// step. So a tracker's line on the barrier reports the KE the barrier used, to the bit. With KE > E
// the barrier takes E: velocity and spin are scaled by f = sqrt((KE - E) / KE), which takes E from
// translation and rotation in proportion; otherwise the body stops: velocity and spin zero, fixed
// in x, y and rotation, where it is.
//
// The change acts on the half-step velocity, as a script's would, so the energy books take it as
// they take a script's (step/script_work.cpp): exactly what the next snapshot books for the body
// less what it would have booked, as the item `barrier` (whole model and groups). In free flight
// with no gravity that is E (or KE) exactly; under gravity it differs from E by the work of
// gravity over the part of the step after the line.
#include "step/barriers.hpp"

#include <algorithm>
#include <cmath>

#include "step/crossing.hpp"
#include "step/detection.hpp"  // pairGeometry
#include "step/script_work.hpp"
#include "world/body_store.hpp"

namespace talus {

namespace {

/// The radius of the disk a clump is taken as at a barrier: of its area (mass / density) when it
/// has a density, else of the smallest circle about its centroid holding its pebbles.
double clumpRadius(const World& world, const ClumpData& c) {
    if (c.density > 0.0) return std::sqrt(c.mass / (c.density * M_PI));
    double r = 0.0;
    const auto& b = world.bodies.balls;
    for (std::size_t k = 0; k < c.pebbles.size(); ++k) {
        const uint32_t s = world.bodies.pebbleSlot(c, k);
        r = std::max(r, (b.pos[s] - c.pos).norm() + b.radius[s]);
    }
    return r;
}

/// Whether a contact of the body (ball slot, or any pebble of clump `clump`) overlaps now.
bool touchingNow(const World& world, bool clump, uint32_t at) {
    const auto& b = world.bodies.balls;
    const auto mine = [&](uint32_t slot) { return clump ? b.clump[slot] == at : slot == at; };
    for (const Pair& p : world.contacts.pairs) {
        if (!p.active || !(mine(p.end1) || (!p.wall && mine(p.end2)))) continue;
        Vec2 normal, point;
        double overlap = 0.0;
        if (pairGeometry(world, p, normal, overlap, point) && overlap > 0.0) return true;
    }
    return false;
}

/// Whether only gravity moves the body between contacts (no fixity, applied load or damping).
bool gravityOnly(const World& world, uint8_t fixity, const Vec2& fapp, double mapp) {
    const DampingSettings& d = world.settings.damping;
    return fixity == 0 && fapp.x() == 0.0 && fapp.y() == 0.0 && mapp == 0.0 && d.local == 0.0 &&
           d.viscous == 0.0;
}

bool pushedBy(const BallArrays& b, uint32_t s) {
    return b.force[s].x() != 0.0 || b.force[s].y() != 0.0 || b.moment[s] != 0.0;
}

struct Moving {
    bool clump = false;
    uint32_t at = 0;  // ball slot or clump index
    uint64_t key = 0;
    const BodyStart* start = nullptr;
    Vec2 pos, vel;
    double spin = 0.0, mass = 0.0, inertia = 0.0, radius = 0.0;
    uint8_t fixity = 0;
    bool gravity_only = false;
};

/// Barrier k catches the body (crossed this step): slows or stops it.
void catchBody(World& world, Barrier& br, const Moving& m, double ke) {
    world.barriers.acted.push_back(BarrierActed{m.key, m.vel, m.spin, m.fixity});
    noteBarrierChange(world, m.clump, m.at);
    const double cap = br.info.def.energy;
    const bool passes = ke > cap;
    const double f = passes ? std::sqrt((ke - cap) / ke) : 0.0;
    const uint8_t all = kFixX | kFixY | kFixSpin;
    if (passes) {
        // The step's kinematic limit follows the velocities (a stopped body's older, larger
        // velocity only keeps the next limit on the safe side).
        world.stepping.limits_stale = true;
        ++br.info.passed;
        br.info.absorbed += cap;
    } else {
        ++br.info.stopped;
        br.info.absorbed += ke;
    }
    if (m.clump) {
        ClumpData& c = world.bodies.clumps[m.at];
        c.vel = f * c.vel, c.spin = f * c.spin;
        if (!passes) c.fixity = all;
        placePebbles(world, c);
    } else {
        auto& b = world.bodies.balls;
        b.vel[m.at] = f * b.vel[m.at], b.spin[m.at] = f * b.spin[m.at];
        if (!passes && b.fixity[m.at] != all) {
            world.bodies.fixed_balls += (b.fixity[m.at] == 0);
            b.fixity[m.at] = all;
        }
    }
}

/// The barriers body m crossed in this step, in the order they were made: the first catches it
/// (a body stopped or slowed is not caught again in the same step).
void checkBody(World& world, const Moving& m, double dt) {
    const Vec2& p0 = m.start->pos;
    for (Barrier& br : world.barriers.list) {
        const BarrierDef& d = br.info.def;
        const double nx = br.dir.y(), ny = -br.dir.x();
        const double d0 = nx * (p0.x() - d.from.x()) + ny * (p0.y() - d.from.y());
        const double d1 = nx * (m.pos.x() - d.from.x()) + ny * (m.pos.y() - d.from.y());
        if (!(d0 < 0.0 && d1 >= 0.0)) continue;
        if (br.caught.count(m.key)) continue;
        const double s = -d0 / (d1 - d0);
        double ax = (m.vel.x() - m.start->vel.x()) / dt;
        double ay = (m.vel.y() - m.start->vel.y()) / dt;
        if (m.gravity_only && !m.start->pushed && !touchingNow(world, m.clump, m.at))
            ax = world.settings.gravity.x(), ay = world.settings.gravity.y();
        const CrossingState at = crossingAt(p0, m.start->spin, m.pos, m.spin, s, dt, ax, ay);
        const double along =
            br.dir.x() * (at.pos.x() - d.from.x()) + br.dir.y() * (at.pos.y() - d.from.y());
        if (along < -m.radius) continue;             // under its foot: not met
        br.caught.insert(m.key);                     // met: judged once
        if (along > br.length + m.radius) continue;  // over its top
        const double ke =
            translationalEnergy(m.mass, at.vel) + rotationalEnergy(m.inertia, at.spin);
        catchBody(world, br, m, ke);
        return;
    }
}

}  // namespace

void recordBodyStarts(World& world) {
    auto& br = world.barriers;
    br.start_time = world.clock.time;
    const auto& b = world.bodies.balls;
    br.ball_start.resize(b.size());
    for (std::size_t s = 0; s < b.size(); ++s) {
        const auto k = static_cast<uint32_t>(s);
        br.ball_start[s] = b.clump[s] == kNoClump ? BodyStart{b.handle[s], b.pos[s], b.vel[s],
                                                              b.spin[s], pushedBy(b, k)}
                                                  : BodyStart{};
    }
    const auto& cl = world.bodies.clumps;
    br.clump_start.resize(cl.size());
    for (std::size_t i = 0; i < cl.size(); ++i) {
        if (!cl[i].alive) {
            br.clump_start[i] = BodyStart{};
            continue;
        }
        bool pushed = false;
        for (std::size_t k = 0; k < cl[i].pebbles.size() && !pushed; ++k)
            pushed = pushedBy(b, world.bodies.pebbleSlot(cl[i], k));
        br.clump_start[i] = BodyStart{cl[i].generation, cl[i].pos, cl[i].vel, cl[i].spin, pushed};
    }
}

void applyBarriers(World& world, const StepContext& step) {
    auto& br = world.barriers;
    br.acted.clear();
    // The interval as the clock has it (as a tracker's two samples do), not the step's dt: the two
    // differ in the last bits once t >> dt, and a tracker on the barrier must see the same state.
    const double dt = world.clock.time - br.start_time;
    if (!(step.dt > 0.0) || !(dt > 0.0)) return;
    const auto& b = world.bodies.balls;
    // Bodies added since the start of the step (an event handler) have no start: not checked in
    // this step; a ball moved to another slot (one deleted before it) neither.
    const std::size_t nb = std::min(b.size(), br.ball_start.size());
    for (std::size_t s = 0; s < nb; ++s) {
        const BodyStart& st = br.ball_start[s];
        if (st.handle == 0 || st.handle != b.handle[s] || b.clump[s] != kNoClump) continue;
        Moving m;
        m.at = static_cast<uint32_t>(s);
        m.key = barrierBallKey(b.handle[s], world.bodies.generation[b.handle[s] - 1]);
        m.start = &st;
        m.pos = b.pos[s], m.vel = b.vel[s], m.spin = b.spin[s];
        m.mass = b.mass[s], m.inertia = b.inertia[s], m.radius = b.radius[s];
        m.fixity = b.fixity[s];
        m.gravity_only = gravityOnly(world, m.fixity, b.fapp[s], b.mapp[s]);
        checkBody(world, m, dt);
    }
    auto& cl = world.bodies.clumps;
    const std::size_t nc = std::min(cl.size(), br.clump_start.size());
    for (std::size_t i = 0; i < nc; ++i) {
        const ClumpData& c = cl[i];
        const BodyStart& st = br.clump_start[i];
        if (!c.alive || st.handle != c.generation) continue;
        Moving m;
        m.clump = true;
        m.at = static_cast<uint32_t>(i);
        m.key = barrierClumpKey(static_cast<uint32_t>(i), c.generation);
        m.start = &st;
        m.pos = c.pos, m.vel = c.vel, m.spin = c.spin;
        m.mass = c.mass, m.inertia = c.inertia, m.radius = clumpRadius(world, c);
        m.fixity = c.fixity;
        m.gravity_only = gravityOnly(world, m.fixity, c.fapp, c.mapp);
        checkBody(world, m, dt);
    }
}

}  // namespace talus
