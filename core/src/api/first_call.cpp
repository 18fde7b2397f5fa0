// SPDX-License-Identifier: MIT
//
// A contact's first FDlaw outside the force loop (first_call.hpp): the call itself, and what the
// host does with it. Nothing has moved since the last force loop, so:
//  - the next step's stability limit holds the new stiffnesses (the limits are surveyed again
//    before it, from the stiffnesses stored here);
//  - the ball forces the next law of motion applies are corrected by the change of the
//    contact's force;
//  - with tracing on, the change of the stored energy (the old model's last report against the
//    new one's) is booked to `released`, less the half step of work the old forces will now
//    never do (below), so the balance stays closed.
#include "api/first_call.hpp"

#include <cmath>

#include "api/operations.hpp"
#include "force/force.hpp"
#include "step/detection.hpp"
#include "step/group_energy.hpp"
#include "talus/errors.hpp"
#include "world/types.hpp"

namespace talus {

double firstCallStep(const World& world) {
    return world.clock.dt > 0.0                  ? world.clock.dt
           : world.settings.timestep.fixed > 0.0 ? world.settings.timestep.fixed
           : world.settings.timestep.max < 1e300 ? world.settings.timestep.max
                                                 : 1e-6;
}

std::string firstCall(const World& world, const Pair& p, ContactModel& model,
                      const FirstCallGeometry& g, double fn, double fs, uint32_t flags,
                      FdBlock& fd) {
    fd = world.contacts.fd_template;
    fd.flags = kFdFirstCall | (world.books.on ? kFdEnergyOn : 0u) | flags;
    fd.status = 0;
    fd.u_n = g.overlap;
    fd.u_dot_n = fd.u_dot_s = fd.t_dot_rel = 0.0;
    fd.du_n = fd.du_s = fd.dtheta = 0.0;
    fd.tdel = firstCallStep(world);
    fd.mass_eff = world.contacts.coldOf(p).mass_eff;
    fd.inv_mass_eff_s = world.contacts.coldOf(p).inv_mass_eff_s;
    fd.time = world.clock.time;
    fd.n_force = fn;
    fd.s_force = fs;
    fd.moment = 0.0;
    fd.knest = fd.ksest = fd.krest = 0.0;
    for (double& e : fd.energy) e = 0.0;
    try {
        model.FDlaw(fd);
    } catch (...) {
        fd.status = 1;
        fd.error = "exception in FDlaw";
    }
    if (fd.status != 0) return std::string("failed: ") + (fd.error ? fd.error : "(no message)");
    if (!std::isfinite(fd.n_force + fd.s_force + fd.moment + fd.knest + fd.ksest + fd.krest))
        return "returned a non-finite value";
    return {};
}

namespace {

/// The force the next law of motion applies: the last force loop's, corrected by the change of
/// this contact's force (same geometry: nothing moved since). With per-group books, the exchange
/// record the last force loop left for this contact (ends in different groups) carries its force
/// to the next law of motion: corrected too.
void correctEndForces(World& world, const Pair& p, const FirstCallGeometry& g, const Vec2& df,
                      double dm) {
    auto& b = world.bodies.balls;
    const Vec2& x1 = b.pos[p.end1];
    b.force[p.end1] -= df;
    b.moment[p.end1] -= cross(g.point - x1, df) + dm;
    if (!p.wall) {
        b.force[p.end2] += df;
        b.moment[p.end2] += cross(g.point - b.pos[p.end2], df) + dm;
    } else {
        WallData& w = world.bodies.walls[world.bodies.segments[p.end2].wall];
        w.force += df;
        w.moment += cross(g.point - w.center, df) + dm;
    }
    if (!world.books.groups.on || (df.squaredNorm() == 0.0 && dm == 0.0)) return;
    const uint32_t e2 = p.wall ? world.bodies.segments[p.end2].wall : p.end2;
    for (auto& x : world.books.groups.exchange) {
        if (x.end1 != p.end1 || x.end2 != e2 || x.wall != p.wall) continue;
        x.f1 -= df;
        x.m1 -= cross(g.point - endCentre(world, p.end1), df) + dm;
        x.m2 += cross(g.point - (p.wall ? world.bodies.walls[e2].center : endCentre(world, p.end2)),
                      df) +
                dm;
        break;
    }
}

/// The part of the old contact's stored energy the bodies never paid for. The old model's
/// report at the last step includes the work of that step's force over the first half of its
/// window (the trapezoid (F_prev + F) du / 2), but the bodies will now feel the new force at this
/// time level instead: that half-step work, (F - F_new) du / 2, was never done (for a linear
/// spring zeroed by a reset this gives F_prev F / 2k, the energy cbond releases when a bond
/// breaks: docs/models/cbond.md, Energies). du from the velocities the last force loop used,
/// which are the current ones (the law of motion has not run since).
double unpaidWork(const World& world, const Pair& p, const FirstCallGeometry& g, const FdBlock& fd,
                  const FirstCallEntry& before) {
    if (!before.was_active || !(world.clock.dt > 0.0)) return 0.0;
    const auto& b = world.bodies.balls;
    Vec2 v2c;
    double spin2;
    if (p.wall) {
        const WallData& w = world.bodies.walls[world.bodies.segments[p.end2].wall];
        v2c = w.vel + spinCross(w.spin, g.point - w.center);
        spin2 = w.spin;
    } else {
        v2c = b.vel[p.end2] + spinCross(b.spin[p.end2], g.point - b.pos[p.end2]);
        spin2 = b.spin[p.end2];
    }
    const Vec2 vrel = v2c - (b.vel[p.end1] + spinCross(b.spin[p.end1], g.point - b.pos[p.end1]));
    const double du_n = -vrel.dot(g.normal) * world.clock.dt,
                 du_s = vrel.dot(perp(g.normal)) * world.clock.dt;
    const double dth = (spin2 - b.spin[p.end1]) * world.clock.dt;
    return 0.5 * ((before.n_force - fd.n_force) * du_n - (before.s_force - fd.s_force) * du_s -
                  (before.moment - fd.moment) * dth);
}

/// The books: what the old contact stored against what the new one stores, less the unpaid
/// work, to `released` (for a placed contact: what it stores, to `placement`); the current
/// stored energies (the next snapshot may come before the next force loop sums them again),
/// for the model and its groups.
void bookFirstCall(World& world, std::size_t i, const FirstCallGeometry& g, const FdBlock& fd,
                   const FirstCallEntry& before, bool placed) {
    const Pair& p = world.contacts.pairs[i];
    PairStored& stored = world.contacts.stored[i];
    const double held = before.was_active ? stored.total() : 0.0;
    const double after = fd.energy[kEnergyStrain] + fd.energy[kEnergyBondStrain];
    const double placement = placed ? after : 0.0;
    const double change =
        placed ? fd.energy[kEnergyReleased]
               : held - after - unpaidWork(world, p, g, fd, before) + fd.energy[kEnergyReleased];
    const double ds = fd.energy[kEnergyStrain] - (before.was_active ? stored.strain : 0.0);
    const double db = fd.energy[kEnergyBondStrain] - (before.was_active ? stored.bond : 0.0);
    world.books.acc.released += change;
    world.books.acc.placement += placement;
    world.books.acc.strain += ds;
    world.books.acc.bond += db;
    if (world.books.groups.on) {
        bookReleasedToGroups(world, p, change);
        // The groups' current stored energies, shared as the force loop shares them
        // (group_energy.cpp: half to each ball's groups, all to the ball's for a wall).
        const uint64_t g1 = endGroups(world, p, false), g2 = endGroups(world, p, true);
        auto& books = world.books.groups;
        for (uint64_t mk = (g1 | (p.wall ? 0 : g2)) & books.traced; mk; mk &= mk - 1) {
            const uint64_t bit = mk & (~mk + 1);
            const double w = p.wall ? ((g1 & bit) ? 1.0 : 0.0)
                                    : 0.5 * (((g1 & bit) ? 1.0 : 0.0) + ((g2 & bit) ? 1.0 : 0.0));
            auto& gr = books.g[__builtin_ctzll(mk)];
            gr.acc.strain += w * ds;
            gr.acc.bond += w * db;
            gr.acc.placement += w * placement;
        }
    }
    stored.strain = fd.energy[kEnergyStrain];
    stored.bond = fd.energy[kEnergyBondStrain];
}

}  // namespace

void takeFirstCall(World& world, std::size_t i, const FirstCallGeometry& g, const FdBlock& fd,
                   const FirstCallEntry& before, bool placed) {
    Pair& p = world.contacts.pairs[i];
    PairCold& c = world.contacts.cold[i];
    if (!before.was_active) ++world.profile.contacts_created;
    p.active = true;
    if (!before.was_active) world.contacts.startWatch(p, c);  // (an active one keeps its watch)
    const Vec2 df =
        (fd.n_force - before.n_force) * g.normal + (fd.s_force - before.s_force) * perp(g.normal);
    correctEndForces(world, p, g, df, fd.moment - before.moment);
    if (world.books.on) bookFirstCall(world, i, g, fd, before, placed);
    p.n_force = fd.n_force;
    p.s_force = fd.s_force;
    p.moment = fd.moment;
    c.overlap = g.overlap;
    c.knest = fd.knest;
    c.ksest = fd.ksest;
    c.krest = fd.krest;
    p.sliding = (fd.flags & kFdSliding) != 0;
    p.bonded = (fd.flags & kFdBonded) != 0;
    // The impact rules' duration for this contact, and the guard: the contact holds energy no
    // traced approach put in (like a placed contact, its energy check is skipped) and is a
    // persistent contact, not an impact.
    c.duration = p.model->ContactDuration(c.mass_eff, 0.0);
    if (!(c.duration > 0.0)) c.duration = HUGE_VAL;
    if (GuardWatch* w = world.contacts.watchOf(c)) w->born_overlapped = true;
    if (fd.flags & kFdBroken) queueBreak(world, i, g.point, fd);
}

// ------------------------------------------------------------------------ at placement

namespace {

/// True when the ball of wall pair p has a contact with another segment of the same wall: that
/// contact moves along the chain in the force loop (step/detection.cpp, "wall vertices"); a
/// second one is not started here.
bool wallContactHeld(const World& world, const Pair& p) {
    const WallData& w = world.bodies.walls[world.bodies.segments[p.end2].wall];
    const uint64_t hi = uint64_t(world.bodies.balls.handle[p.end1]) << 32;
    for (uint32_t k = 0; k < w.segment_count; ++k) {
        const uint32_t seg = w.first_segment + k;
        if (seg == p.end2) continue;
        const auto it = world.contacts.key_index.find(hi | kWallBit | seg);
        if (it != world.contacts.key_index.end() && world.contacts.pairs[it->second].active)
            return true;
    }
    return false;
}

/// Pair i, a bond model's pair within reach where the script built it: its first call there,
/// with the entry forces zero and the host's memory of a broken bond (kFdNoAutoBond), then what
/// the force loop does at a contact's first touch (the count, the guard's note of a placed
/// overlap, the contact-created event).
void placeContact(World& world, std::size_t i, const FirstCallGeometry& g) {
    Pair& p = world.contacts.pairs[i];
    PairCold& c = world.contacts.cold[i];
    const uint32_t flags = world.contacts.unbonded.empty() ? 0u : autoBondFlags(world, p, c);
    FdBlock fd;
    const std::string why = firstCall(world, p, *p.model, g, 0.0, 0.0, flags, fd);
    if (!why.empty())
        throw PluginError("contact model '" + world.contacts.ruleOf(p).model_name + "' on " +
                          describePair(world, p) + ": the first FDlaw, where the bodies were " +
                          "placed, " + why);
    takeFirstCall(world, i, g, fd, FirstCallEntry{}, true);
    // Nothing moved (closure 0): what the contact holds was placed.
    notePlacement(world, p, 0.0, g.overlap, fd, world.books.on);
    if (world.callbacks.contact_events) noteContactCreated(world, p, c, g.point);
}

}  // namespace

void firstCallsAtPlacement(World& world) {
    // Nothing the script did since the last step: every pair within reach is a contact already.
    if (!world.stepping.limits_stale && !world.clock.first_cycle) return;
    ContactStore& cs = world.contacts;
    bool bond_rules = false;
    for (const auto& r : cs.rules)
        bond_rules |= r->prototype && !r->installed && (r->prototype->Traits() & kTraitBond);
    if (!bond_rules) return;
    bool placed = false;
    for (std::size_t i = 0; i < cs.pairs.size(); ++i) {
        Pair& p = cs.pairs[i];
        if (p.active || !p.model) continue;
        FirstCallGeometry g;
        if (!pairGeometry(world, p, g.normal, g.overlap, g.point) ||
            !(g.overlap > -cs.max_activity))
            continue;
        if (cs.cold[i].rules_version != cs.rules_version) refreshRule(world, p);
        if (!(p.model->Traits() & kTraitBond) || !(g.overlap > -cs.cold[i].activity)) continue;
        if (p.wall && wallContactHeld(world, p)) continue;
        placeContact(world, i, g);
        placed = true;
    }
    if (placed) world.stepping.limits_stale = true;
}

}  // namespace talus
