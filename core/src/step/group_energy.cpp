// SPDX-License-Identifier: MIT
//
// Energy per group (docs/physics/energy.md, "Energy per group"; An 2006, chapter 3).
//
// Allocation: a contact gives group g the share s_g of every item it stores or dissipates,
//   s_g = ([g in G1] + [g in G2]) / 2   between two balls,   s_g = [g in G_ball]   ball-wall;
// body items (kinetic, body work, damping, fixity work, deleted, initial kinetic) go to every
// group of the body, a moving wall's boundary work to the wall's groups. A body in several
// groups counts fully in each.
//
// Exchanged work: the contact force does the work W_1, W_2 on its two ends over the window w
// around the force's time level, W_end = (F_end . v_mid + M_end w_mid) w with the rates at the
// half steps before and after the update (exactly the change of the half-step kinetic energy
// that force causes; for a wall end its set rates, the work moveWalls books as boundary with
// the opposite sign). The whole model sees W_1 + W_2 = -(stored + dissipated) of the contact;
// group g sees the work on its own ends but only its share of the contact's items, so
//   exchanged_g += sum_{ends in g} W_end - s_g (W_1 + W_2)
// closes g's balance with the same discretisation error as the whole model's. It is 0 for a
// contact inside g, and summed over a partition of the bodies sum_g s_g = 1 and every end is in
// one group, so the exchanged items cancel to round-off. Only contacts whose ends' masks
// differ (or with a moving wall in other groups) can give a nonzero term: the force loop
// records just those (bookContactToGroups), the next law of motion evaluates them.
#include "step/group_energy.hpp"

#include <algorithm>

#include "step/step.hpp"
#include "talus/errors.hpp"
#include "world/body_store.hpp"
#include "world/contact_store.hpp"
#include "world/types.hpp"

namespace talus {

namespace {

/// Share of a contact's items for group bit `bit`.
inline double share(uint64_t bit, uint64_t g1, uint64_t g2, bool wall) {
    if (wall) return (g1 & bit) ? 1.0 : 0.0;
    return 0.5 * (((g1 & bit) ? 1.0 : 0.0) + ((g2 & bit) ? 1.0 : 0.0));
}

}  // namespace

void openGroupBooks(World& world) {
    auto& gb = world.books.groups;
    const std::size_t n = world.bodies.group_names.size();
    if (!world.books.on || n == 0) {
        gb = EnergyBooks::GroupBooks{};
        return;
    }
    const std::size_t old = gb.g.size();
    // Grow, keeping what the existing groups have booked (a group named while tracing is on
    // starts with empty books: its members' energy at that moment is not an input to it).
    gb.g.resize(n);
    gb.traced = n >= 64 ? ~uint64_t(0) : (uint64_t(1) << n) - 1;
    gb.on = true;
    if (old == 0) {
        // Tracing switched on now: the groups' initial kinetic energy, as the whole model's.
        const auto book = [&](uint64_t mask, double ke) {
            for (uint64_t m = mask & gb.traced; m; m &= m - 1) {
                const int g = __builtin_ctzll(m);
                gb.g[g].acc.initial_kinetic += ke;
                gb.g[g].acc.kinetic += ke;
            }
        };
        const auto& b = world.bodies.balls;
        for (std::size_t s = 0; s < b.size(); ++s)
            if (b.clump[s] == kNoClump)  // a pebble's motion is its clump's (below)
                book(b.groups[s], 0.5 * (b.mass[s] * b.vel[s].squaredNorm() +
                                         b.inertia[s] * b.spin[s] * b.spin[s]));
        for (const ClumpData& c : world.bodies.clumps)
            if (c.alive)
                book(c.groups, 0.5 * (c.mass * c.vel.squaredNorm() + c.inertia * c.spin * c.spin));
        for (auto& gr : gb.g) gr.snapshot = gr.acc;
    }
}

uint64_t endGroups(const World& world, const Pair& p, bool end2) {
    if (!end2) return world.bodies.balls.groups[p.end1];
    if (p.wall) return world.bodies.walls[world.bodies.segments[p.end2].wall].groups;
    return world.bodies.balls.groups[p.end2];
}

void bookContactToGroups(World& world, std::size_t i, const double* energy, double moment,
                         bool placement, bool ends, double held, const Vec2& f, const Vec2& point) {
    auto& gb = world.books.groups;
    const Pair& p = world.contacts.pairs[i];
    const PairStored& stored = world.contacts.stored[i];  // (this step's, written before)
    const uint64_t g1 = endGroups(world, p, false), g2 = endGroups(world, p, true);
    const double placed = placement ? world.books.last_placed : 0.0;
    auto* groups = gb.g.data();
    for (uint64_t m = (g1 | (p.wall ? 0 : g2)) & gb.traced; m; m &= m - 1) {
        const int g = __builtin_ctzll(m);
        addContactShare(groups[g], share(uint64_t(1) << g, g1, g2, p.wall), energy, placed, held,
                        ends, stored);
    }
    // Work passed across a group border: only when the ends' groups differ (with a wall, only
    // when it moves, else it does no work and the ball's groups take the whole contact).
    if (g1 == g2) return;
    EnergyBooks::GroupBooks::Exchange x;
    x.end1 = p.end1;
    x.g1 = g1;
    x.g2 = g2;
    x.f1 = -f;  // the loop applies -f to end 1 and +f to end 2
    x.m1 = -cross(point - endCentre(world, p.end1), f) - moment;
    if (p.wall) {
        const uint32_t wi = world.bodies.segments[p.end2].wall;
        const WallData& w = world.bodies.walls[wi];
        if (w.vel.squaredNorm() == 0.0 && w.spin == 0.0) return;
        x.wall = true;
        x.end2 = wi;
        x.m2 = cross(point - w.center, f) + moment;
        // the velocity the wall moved at in this step (its work before the next snapshot)
        x.v2 = w.vel;
        x.w2 = w.spin;
    } else {
        x.end2 = p.end2;
        x.m2 = cross(point - endCentre(world, p.end2), f) + moment;
    }
    gb.exchange.push_back(x);
}

void bookReleasedToGroups(World& world, const Pair& p, double released) {
    auto& gb = world.books.groups;
    const uint64_t g1 = endGroups(world, p, false), g2 = endGroups(world, p, true);
    for (uint64_t m = (g1 | (p.wall ? 0 : g2)) & gb.traced; m; m &= m - 1) {
        const int g = __builtin_ctzll(m);
        gb.g[g].acc.released += share(uint64_t(1) << g, g1, g2, p.wall) * released;
    }
}

void bookDeletedToGroups(World& world, uint64_t mask, double kinetic) {
    auto& gb = world.books.groups;
    for (uint64_t m = mask & gb.traced; m; m &= m - 1)
        gb.g[__builtin_ctzll(m)].acc.deleted += kinetic;
}

void bookScriptToGroups(World& world, uint64_t mask, double work) {
    auto& gb = world.books.groups;
    for (uint64_t m = mask & gb.traced; m; m &= m - 1) gb.g[__builtin_ctzll(m)].acc.script += work;
}

void bookBarrierToGroups(World& world, uint64_t mask, double taken) {
    auto& gb = world.books.groups;
    for (uint64_t m = mask & gb.traced; m; m &= m - 1)
        gb.g[__builtin_ctzll(m)].acc.barrier += taken;
}

void followRemovedSlot(World& world, uint32_t slot) {
    auto& gb = world.books.groups;
    // deleteBall moves the last slot into this one: follow it in the pending records, and mark
    // the deleted ball's ends gone (its force is never applied, so that end does no work).
    const uint32_t last = static_cast<uint32_t>(world.bodies.balls.size() - 1);
    for (auto& x : gb.exchange) {
        if (x.end1 == slot) x.gone1 = true;
        if (!x.wall && x.end2 == slot) x.gone2 = true;
        if (x.end1 == last && !x.gone1) x.end1 = slot;
        if (!x.wall && x.end2 == last && !x.gone2) x.end2 = slot;
    }
}

void groupForceLoopStart(World& world) {
    auto& gb = world.books.groups;
    for (auto& gr : gb.g) gr.strain_now = gr.bond_now = gr.held_before = 0.0;
    gb.exchange.clear();  // a force loop run twice before a law of motion books once
}

void groupForceLoopEnd(World& world) {
    for (auto& gr : world.books.groups.g) {
        gr.acc.strain = gr.strain_now;
        gr.acc.bond = gr.bond_now;
        if (world.books.strain_baseline_pending) gr.acc.initial_strain = gr.held_before;
    }
}

void gatherExchangeStart(World& world) {
    for (auto& x : world.books.groups.exchange) {
        if (!x.gone1) endRates(world, x.end1, x.v1, x.w1);
        if (!x.wall && !x.gone2) endRates(world, x.end2, x.v2, x.w2);
    }
}

void groupSnapshot(World& world, double lead) {
    auto& gb = world.books.groups;
    const double win = world.clock.window;
    for (const auto& x : gb.exchange) {
        double w1 = 0.0, w2 = 0.0;
        Vec2 v;
        double om;
        if (!x.gone1) {
            endRates(world, x.end1, v, om);
            w1 = (x.f1.dot(0.5 * (x.v1 + v)) + x.m1 * 0.5 * (x.w1 + om)) * win;
        }
        if (x.wall) {
            // As moveWalls and bookWallsBefore book it: the part of the window before the
            // snapshot with the velocity the wall moved at then, the part after with its present
            // velocity.
            const WallData& wd = world.bodies.walls[x.end2];
            if (wd.alive)
                w2 = ((-x.f1.dot(x.v2) + x.m2 * x.w2) * lead +
                      (-x.f1.dot(wd.vel) + x.m2 * wd.spin) * (1.0 - lead)) *
                     win;
        } else if (!x.gone2) {
            endRates(world, x.end2, v, om);
            w2 = (-x.f1.dot(0.5 * (x.v2 + v)) + x.m2 * 0.5 * (x.w2 + om)) * win;
        }
        const double total = w1 + w2;
        for (uint64_t m = (x.g1 | x.g2) & gb.traced; m; m &= m - 1) {
            const int g = __builtin_ctzll(m);
            const uint64_t bit = uint64_t(1) << g;
            gb.g[g].exchanged_pending += ((x.g1 & bit) ? w1 : 0.0) + ((x.g2 & bit) ? w2 : 0.0) -
                                         share(bit, x.g1, x.g2, x.wall) * total;
        }
    }
    gb.exchange.clear();
    // The same split at the snapshot as the whole model's (law_of_motion.cpp), and where the
    // books open or wait (openBooks), the same start: nothing before the snapshot is booked.
    const EnergyBooks::Stage stage = world.books.stage;
    const double before = stage == EnergyBooks::Stage::Open ? lead : 0.0;
    for (auto& gr : gb.g) {
        EnergyTotals& a = gr.acc;
        if (stage != EnergyBooks::Stage::Open) {
            const double strain = a.strain, bond = a.bond;
            a = EnergyTotals{};
            a.initial_kinetic = a.kinetic = gr.step_kinetic;
            if (stage == EnergyBooks::Stage::Opened) {
                a.strain = strain;
                a.bond = bond;
                a.initial_strain = strain + bond;
            }
        }
        a.damping += gr.step_damping * before;
        a.boundary += gr.step_driven * before;
        a.dashpot += gr.dashpot_pending * before;
        a.exchanged += gr.exchanged_pending * before;
        gr.snapshot = a;
        gr.snapshot.kinetic = gr.step_kinetic;
        if (stage != EnergyBooks::Stage::Waiting) {
            a.body += gr.step_body;
            a.boundary += gr.step_driven * (1.0 - lead);
            a.damping += gr.step_damping * (1.0 - lead);
            a.dashpot += gr.dashpot_pending * (1.0 - lead);
            a.exchanged += gr.exchanged_pending * (1.0 - lead);
        }
        gr.dashpot_pending = gr.exchanged_pending = 0.0;
        gr.step_kinetic = gr.step_body = gr.step_damping = gr.step_driven = 0.0;
    }
}

void bookWallToGroups(World& world, uint64_t mask, double work) {
    auto& gb = world.books.groups;
    for (uint64_t m = mask & gb.traced; m; m &= m - 1)
        gb.g[__builtin_ctzll(m)].acc.boundary += work;
}

}  // namespace talus
