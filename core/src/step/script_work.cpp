// SPDX-License-Identifier: MIT
//
// Work done by the script (docs/physics/energy.md, "Work done by the script").
//
// Velocities live at half steps, and the energy snapshot of a whole step t takes each body's
// kinetic energy at t, interpolated from the half-step velocity before t and the one after,
// together with the part before t of the damping and fixity impulses that span it
// (law_of_motion.cpp). A script acts between two steps, on the half-step velocity before t and on
// what the next step's law of motion reads (mass, fixity, applied load, gravity, damping). So the
// snapshot a change shows in is the next one, and the energy it brings is exactly the difference
// of what that snapshot takes for the body, `shareOf` below, with the change and without it.
// Evaluated at the start of the next step, when its length is known (the damping work depends on
// it), from the body as it was before its first change and as it is now. Gravity needs no
// potential energy item: the books count gravity's work as it is done (`body`), so moving a body
// up or down books nothing, and a change of gravity shows only in the velocity the snapshot
// interpolates at t, which is what it books.
#include "step/script_work.hpp"

#include <cmath>

#include "step/body_damping.hpp"
#include "step/group_energy.hpp"
#include "world/body_store.hpp"

namespace talus {

namespace {

uint64_t ballKey(uint32_t handle, uint32_t generation) {
    return (uint64_t(generation) << 32) | handle;
}
uint64_t clumpKey(uint32_t index) { return (uint64_t(1) << 63) | index; }

BodyMotion motionOfBall(const World& world, uint32_t s) {
    const auto& b = world.bodies.balls;
    BodyMotion m;
    m.mass = b.mass[s], m.inv_mass = b.inv_mass[s];
    m.inertia = b.inertia[s], m.inv_inertia = b.inv_inertia[s];
    m.vel = b.vel[s], m.spin = b.spin[s];
    m.force = b.force[s] + b.fapp[s];  // as the law of motion adds them
    m.moment = b.moment[s] + b.mapp[s];
    m.fixity = b.fixity[s];
    m.groups = b.groups[s];
    return m;
}

BodyMotion motionOfClump(const World& world, const ClumpData& c) {
    // The pebbles' forces of the last force loop, gathered as the law of motion gathers them.
    Vec2 f;
    double mom;
    sumPebbleForces(world, c, f, mom);
    BodyMotion m;
    m.mass = c.mass, m.inv_mass = c.inv_mass;
    m.inertia = c.inertia, m.inv_inertia = c.inv_inertia;
    m.vel = c.vel, m.spin = c.spin;
    m.force = f + c.fapp;
    m.moment = mom + c.mapp;
    m.fixity = c.fixity;
    m.groups = c.groups;
    return m;
}

/// What the snapshot at the start of `step` books for a body (law_of_motion.cpp, the general
/// loop, term by term): its kinetic energy at t, plus the part before t of its damping work, less
/// that of its fixities' reaction work (an input). The same update as the law of motion's.
double shareOf(const BodyMotion& m, const Vec2& g, const DampingSettings& d,
               const StepContext& step) {
    const double w = step.window;
    const double lead = w > 0.0 ? 0.5 * step.dt_prev / w : 0.0;
    const double alpha = d.local, c = d.viscous;
    const double keep = (1.0 - 0.5 * c * w) / (1.0 + 0.5 * c * w);
    const double gain = w / (1.0 + 0.5 * c * w);
    const Vec2 v_old = m.vel;
    const double w_old = m.spin;
    Vec2 fd = Vec2::Zero();
    double md = 0.0;
    if (alpha > 0.0) {
        const Vec2 unbalanced = m.force + m.mass * g;
        fd = Vec2(localDamping(alpha, unbalanced.x(), v_old.x()),
                  localDamping(alpha, unbalanced.y(), v_old.y()));
        md = localDamping(alpha, m.moment, w_old);
    }
    const Vec2 acc = (m.force + fd) * m.inv_mass + g;
    const double ang = (m.moment + md) * m.inv_inertia;
    Vec2 v = keep * v_old + gain * acc;
    double om = keep * w_old + gain * ang;
    double cx = c, cy = c, cw = c;
    if (m.fixity) {
        if (m.fixity & kFixX) v.x() = v_old.x(), fd.x() = 0.0, cx = 0.0;
        if (m.fixity & kFixY) v.y() = v_old.y(), fd.y() = 0.0, cy = 0.0;
        if (m.fixity & kFixSpin) om = w_old, md = 0.0, cw = 0.0;
    }
    const Vec2 v_now = v_old + (v - v_old) * lead;
    const double om_now = w_old + (om - w_old) * lead;
    double share = 0.5 * (m.mass * v_now.squaredNorm() + m.inertia * om_now * om_now);
    if (alpha > 0.0 || c > 0.0)
        share += lead * dampingWork(w, fd, md, v_now, om_now, 0.5 * (v_old + v), 0.5 * (w_old + om),
                                    m.mass, m.inertia, cx, cy, cw);
    if (m.fixity) {
        const Vec2 load = m.force + m.mass * g;
        double react = 0.0;
        if (m.fixity & kFixX) react -= load.x() * v.x();
        if (m.fixity & kFixY) react -= load.y() * v.y();
        if (m.fixity & kFixSpin) react -= m.moment * om;
        share -= lead * react * w;
    }
    return share;
}

bool noting(const World& world) { return world.books.on && world.books.opening == 0; }

/// The entry of a body, made (as it is now, `existed`) on its first change since the last step.
ScriptBody* entry(World& world, uint64_t key, bool clump, uint32_t index, uint32_t generation,
                  const BodyMotion& now, bool existed) {
    auto& sc = world.books.script;
    const auto found = sc.index.find(key);
    if (found != sc.index.end()) return &sc.bodies[found->second];
    sc.index.emplace(key, sc.bodies.size());
    ScriptBody& e = sc.bodies.emplace_back();
    e.index = index, e.generation = generation, e.clump = clump;
    e.existed = existed;
    e.before = now;
    return &e;
}

void clear(EnergyBooks::ScriptChanges& sc) {
    sc.bodies.clear();
    sc.index.clear();
}

}  // namespace

void noteBallChange(World& world, uint32_t slot) {
    const auto& b = world.bodies.balls;
    if (!noting(world) || b.clump[slot] != kNoClump) return;
    const uint32_t h = b.handle[slot], gen = world.bodies.generation[h - 1];
    entry(world, ballKey(h, gen), false, h, gen, motionOfBall(world, slot), true);
}

void noteBallAdded(World& world, uint32_t slot) {
    const auto& b = world.bodies.balls;
    if (!noting(world) || b.clump[slot] != kNoClump) return;
    const uint32_t h = b.handle[slot], gen = world.bodies.generation[h - 1];
    entry(world, ballKey(h, gen), false, h, gen, BodyMotion{}, false);
}

void noteBallDeleted(World& world, uint32_t slot) {
    const auto& b = world.bodies.balls;
    if (!noting(world) || b.clump[slot] != kNoClump) return;
    const uint32_t h = b.handle[slot], gen = world.bodies.generation[h - 1];
    const BodyMotion now = motionOfBall(world, slot);
    ScriptBody* e = entry(world, ballKey(h, gen), false, h, gen, now, true);
    e->deleted = true;
    e->gone = now;
}

void noteBarrierChange(World& world, bool clump, uint32_t slot_or_index) {
    if (!noting(world)) return;
    ScriptBody* e;
    if (clump) {
        e = entry(world, clumpKey(slot_or_index), true, slot_or_index, 0,
                  motionOfClump(world, world.bodies.clumps[slot_or_index]), true);
    } else {
        const uint32_t h = world.bodies.balls.handle[slot_or_index],
                       gen = world.bodies.generation[h - 1];
        e = entry(world, ballKey(h, gen), false, h, gen, motionOfBall(world, slot_or_index), true);
    }
    e->barrier = true;
}

void noteClumpChange(World& world, uint32_t index) {
    if (!noting(world)) return;
    entry(world, clumpKey(index), true, index, 0, motionOfClump(world, world.bodies.clumps[index]),
          true);
}

void noteClumpAdded(World& world, uint32_t index) {
    if (!noting(world)) return;
    entry(world, clumpKey(index), true, index, 0, BodyMotion{}, false);
}

void noteClumpDeleted(World& world, uint32_t index) {
    if (!noting(world)) return;
    const BodyMotion now = motionOfClump(world, world.bodies.clumps[index]);
    ScriptBody* e = entry(world, clumpKey(index), true, index, 0, now, true);
    e->deleted = true;
    e->gone = now;
}

void bookScriptWork(World& world, const StepContext& step) {
    EnergyBooks& books = world.books;
    auto& sc = books.script;
    const Vec2 g = world.settings.gravity;
    const DampingSettings& d = world.settings.damping;
    // Where the books open (api/energy.cpp) they start from this snapshot: nothing before it is
    // theirs.
    if (!books.on || books.opening > 0 || !sc.seen) {
        clear(sc);
        sc.seen = books.on;
        sc.gravity = g, sc.damping = d;
        return;
    }
    const bool global =
        g != sc.gravity || d.local != sc.damping.local || d.viscous != sc.damping.viscous;
    if (!global && sc.bodies.empty()) return;
    const bool groups = books.groups.on;
    double work = 0.0, deleted = 0.0, barrier = 0.0;
    bool by_barrier = false;  // the entry booked is a barrier's: what it took is `barrier`
    const auto book = [&](double amount, uint64_t mask) {
        if (by_barrier) {
            barrier -= amount;
            if (groups) bookBarrierToGroups(world, mask, -amount);
            return;
        }
        work += amount;
        if (groups) bookScriptToGroups(world, mask, amount);
    };
    const auto& b = world.bodies.balls;
    if (global) {
        // Every body the script did not touch: the same state under the new gravity or damping.
        for (uint32_t s = 0; s < b.size(); ++s) {
            if (b.clump[s] != kNoClump) continue;
            const uint32_t h = b.handle[s];
            if (sc.index.count(ballKey(h, world.bodies.generation[h - 1]))) continue;
            const BodyMotion m = motionOfBall(world, s);
            book(shareOf(m, g, d, step) - shareOf(m, sc.gravity, sc.damping, step), m.groups);
        }
        for (uint32_t i = 0; i < world.bodies.clumps.size(); ++i) {
            if (!world.bodies.clumps[i].alive || sc.index.count(clumpKey(i))) continue;
            const BodyMotion m = motionOfClump(world, world.bodies.clumps[i]);
            book(shareOf(m, g, d, step) - shareOf(m, sc.gravity, sc.damping, step), m.groups);
        }
    }
    for (const ScriptBody& e : sc.bodies) {
        by_barrier = e.barrier;
        if (e.existed) book(-shareOf(e.before, sc.gravity, sc.damping, step), e.before.groups);
        if (e.deleted) {
            // What it held when the script deleted it leaves the books as `deleted`.
            const double gone = shareOf(e.gone, g, d, step);
            book(gone, e.gone.groups);
            deleted += gone;
            if (groups) bookDeletedToGroups(world, e.gone.groups, gone);
        } else if (e.clump) {
            const ClumpData& c = world.bodies.clumps[e.index];
            if (c.alive) {  // (a released clump is gone: its balls are bodies of their own)
                const BodyMotion m = motionOfClump(world, c);
                book(shareOf(m, g, d, step), m.groups);
            }
        } else {
            const uint32_t s = world.bodies.slot_of[e.index - 1];
            if (s != kDeadSlot && world.bodies.generation[e.index - 1] == e.generation &&
                b.clump[s] == kNoClump) {  // (a ball made a pebble moves with its clump)
                const BodyMotion m = motionOfBall(world, s);
                book(shareOf(m, g, d, step), m.groups);
            }
        }
    }
    books.acc.script += work;
    books.acc.barrier += barrier;
    books.acc.deleted += deleted;
    clear(sc);
    sc.gravity = g, sc.damping = d;
}

void settleScriptWork(World& world) {
    const auto& sc = world.books.script;
    if (!world.books.on || (sc.bodies.empty() && sc.gravity == world.settings.gravity &&
                            sc.damping.local == world.settings.damping.local &&
                            sc.damping.viscous == world.settings.damping.viscous))
        return;
    // The step after a save is taken to be as long as the last one (exact unless viscous damping
    // acts and the next automatic step differs).
    StepContext step;
    step.dt_prev = world.clock.first_cycle ? 0.0 : world.clock.dt;
    step.dt = world.settings.timestep.automatic ? world.clock.dt : world.settings.timestep.fixed;
    step.window = 0.5 * (step.dt_prev + step.dt);
    step.energy = true;
    bookScriptWork(world, step);
}

}  // namespace talus
