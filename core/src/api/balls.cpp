// SPDX-License-Identifier: MIT
//
// The facade, balls: create and delete them, read and set their state, with the input checks
// every value from a script goes through (input_checks.hpp). The data is in the body store
// (world/body_store.hpp); changes that touch contacts (mass, radius, deletion) update the contact
// store as well.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "api/input_checks.hpp"
#include "api/operations.hpp"
#include "props.hpp"
#include "step/detection.hpp"
#include "step/group_energy.hpp"
#include "step/narrowphase.hpp"
#include "step/script_work.hpp"
#include "talus/errors.hpp"
#include "talus/model.hpp"
#include "world/body_store.hpp"
#include "world/broadphase.hpp"
#include "world/contact_store.hpp"
#include "world/lanes.hpp"
#include "world/messages.hpp"
#include "world/types.hpp"

namespace talus {

// ------------------------------------------------------------------------ balls

bool Model::isAlive(BallId id) const { return m_world->bodies.isAlive(id); }

std::size_t Model::ballCount() const {
    const World& world = *m_world;
    return world.bodies.balls.size() - world.bodies.pebble_count;
}

void refreshPairMasses(World& world, uint32_t s) {
    // Pairs cache their effective mass (force/loop.cpp); a mass change is rare.
    const auto& b = world.bodies.balls;
    for (auto& p : world.contacts.pairs)
        if (p.end1 == s || (!p.wall && p.end2 == s)) {
            // A kernel's step takes the mass from the contact's row (force/kernels.hpp,
            // runKernel): back to its object, whose next FDlaw takes the new mass.
            leaveLane(world.contacts, p);
            world.contacts.coldOf(p).mass_eff =
                p.wall ? b.mass[p.end1]
                       : b.mass[p.end1] * b.mass[p.end2] / (b.mass[p.end1] + b.mass[p.end2]),
            world.contacts.coldOf(p).inv_mass_eff_s = tangentialInverseMass(world, p);
        }
}

void updateMass(World& world, uint32_t s) {
    auto& b = world.bodies.balls;
    const double r = b.radius[s];
    if (world.settings.mass_mode == MassMode::Disk) {
        b.mass[s] = b.density[s] * M_PI * r * r;  // unit thickness
        b.inertia[s] = 0.5 * b.mass[s] * r * r;
    } else {
        b.mass[s] = b.density[s] * 4.0 / 3.0 * M_PI * r * r * r;
        b.inertia[s] = 0.4 * b.mass[s] * r * r;
    }
    b.inv_mass[s] = 1.0 / b.mass[s];
    b.inv_inertia[s] = 1.0 / b.inertia[s];
}

BallId Model::createBall(const BallDef& d) {
    World& world = *m_world;
    return createBallIn(world, d, kNoClump);
}

BallId createBallIn(World& world, const BallDef& d, uint32_t clump) {
    world.stepping.limits_stale = true;
    auto finite2 = [](const Vec2& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); };
    requireRadius(d.radius);
    const bool has_mass = !std::isnan(d.mass);
    if (has_mass && !(d.mass > 0.0 && std::isfinite(d.mass)))
        throw InputError("ball: mass must be > 0 (got " + messageNumber(d.mass) + ")");
    if (!has_mass && !(d.density > 0.0 && std::isfinite(d.density)))
        throw InputError("ball: density must be > 0 (got " + messageNumber(d.density) + ")");
    if (!std::isnan(d.inertia) && !(d.inertia > 0.0 && std::isfinite(d.inertia)))
        throw InputError("ball: inertia must be > 0 (got " + messageNumber(d.inertia) + ")");
    requireCoordinate("ball: pos", d.pos);
    if (!finite2(d.vel)) throw InputError("ball: vel must be finite");
    if (!std::isfinite(d.spin) || !std::isfinite(d.angle))
        throw InputError("ball: spin and angle must be finite");
    for (double v : {d.kn, d.ks, d.fric})
        if (!std::isnan(v) && !(v >= 0.0 && std::isfinite(v)))
            throw InputError("ball: kn, ks and fric must be >= 0 (got " + messageNumber(v) + ")");
    {
        // The derived values, before anything is stored.
        const double r = d.radius;
        const bool disk = world.settings.mass_mode == MassMode::Disk;
        const double volume = disk ? M_PI * r * r : 4.0 / 3.0 * M_PI * r * r * r;
        const double mass = has_mass ? d.mass : d.density * volume;
        const double inertia =
            !std::isnan(d.inertia) ? d.inertia : (disk ? 0.5 : 0.4) * mass * r * r;
        requireUsableMass(
            mass, inertia,
            has_mass ? "mass " + messageNumber(d.mass) + " and radius " + messageNumber(r)
                     : "density " + messageNumber(d.density) + " and radius " + messageNumber(r));
        requireFiniteEnergy(mass, inertia, d.vel, d.spin);
        requireClearOfWalls(world, d.pos, r, "ball");
    }

    auto& b = world.bodies.balls;
    const uint32_t s = static_cast<uint32_t>(b.size());
    // (where the ball arrays grow, the model's memory with its contacts is checked first)
    if (s == b.pos.capacity()) requireMemory(world, s + 1, "ball");
    b.resize(s + 1);
    b.pos[s] = d.pos;
    b.vel[s] = d.vel;
    b.force[s] = b.fapp[s] = Vec2::Zero();
    b.angle[s] = d.angle;
    b.spin[s] = d.spin;
    b.moment[s] = b.mapp[s] = 0.0;
    b.radius[s] = d.radius;
    b.density[s] = has_mass ? 0.0 : d.density;
    if (has_mass) {
        b.mass[s] = d.mass;
        b.inertia[s] =
            (world.settings.mass_mode == MassMode::Disk ? 0.5 : 0.4) * d.mass * d.radius * d.radius;
        b.inv_mass[s] = 1.0 / d.mass;
        b.inv_inertia[s] = 1.0 / b.inertia[s];
        b.density[s] = d.mass / (world.settings.mass_mode == MassMode::Disk
                                     ? M_PI * d.radius * d.radius
                                     : 4.0 / 3.0 * M_PI * d.radius * d.radius * d.radius);
    } else {
        updateMass(world, s);
    }
    if (!std::isnan(d.inertia)) {
        b.inertia[s] = d.inertia;
        b.inv_inertia[s] = 1.0 / d.inertia;
    }
    b.fixity[s] = d.fixity;
    if (d.fixity) ++world.bodies.fixed_balls;
    b.proxy[s] = -1;
    b.groups[s] = 0;
    for (const auto& g : d.groups) b.groups[s] |= uint64_t(1) << talus::groupIndex(world, g, true);
    b.kn[s] = d.kn, b.ks[s] = d.ks, b.fric[s] = d.fric;
    b.k_tran[s] = b.k_rot[s] = 0.0;
    // Before the broadphase sees it: pebbles of one clump never form a pair (makePair).
    b.clump[s] = clump;
    if (clump != kNoClump) ++world.bodies.pebble_count;

    uint32_t h;
    if (!world.bodies.free_handles.empty()) {
        h = world.bodies.free_handles.back();
        world.bodies.free_handles.pop_back();
        world.bodies.generation[h - 1] += 1;
    } else {
        world.bodies.slot_of.push_back(kDeadSlot);
        world.bodies.generation.push_back(1);
        h = static_cast<uint32_t>(world.bodies.slot_of.size());
    }
    world.bodies.slot_of[h - 1] = s;
    b.handle[s] = h;
    if (world.contacts.broadphase_ready) insertBall(world, s);
    noteBallAdded(world, s);  // its kinetic energy comes in as script work
    return BallId{h, world.bodies.generation[h - 1]};
}

void Model::deleteBall(BallId id) {
    World& world = *m_world;
    const uint32_t s = world.bodies.slotOf(id);
    if (world.bodies.balls.clump[s] != kNoClump)
        throw InputError("ball " + std::to_string(id.index) + " is a pebble of clump " +
                         std::to_string(world.bodies.balls.clump[s] + 1) +
                         ": delete or release the clump");
    removeBall(world, id, true);
}

void removeBall(World& world, BallId id, bool book_energy) {
    world.stepping.limits_stale = true;
    const uint32_t s = world.bodies.slotOf(id);
    // The ball leaves the books with what the next energy snapshot would have taken for it, as
    // `deleted`, booked at the next step (step/script_work.cpp). Its contacts' stored energy goes
    // to `released` (removePair).
    if (book_energy) noteBallDeleted(world, s);
    if (world.books.groups.on) followRemovedSlot(world, s);
    // Drop the ball's pairs (highest index first so swap-removal keeps the rest valid).
    for (std::size_t i = world.contacts.pairs.size(); i-- > 0;) {
        const Pair& p = world.contacts.pairs[i];
        if (p.end1 == s || (!p.wall && p.end2 == s)) removePair(world, i);
    }
    auto& b = world.bodies.balls;
    if (b.fixity[s]) --world.bodies.fixed_balls;
    if (b.clump[s] != kNoClump) --world.bodies.pebble_count;
    if (b.proxy[s] >= 0) world.contacts.broadphase->destroy(b.proxy[s]);
    const uint32_t last = static_cast<uint32_t>(b.size() - 1);
    if (s != last) {
        b.move(s, last);
        world.bodies.slot_of[b.handle[s] - 1] = s;
        for (auto& p : world.contacts.pairs) {
            if (p.end1 == last) p.end1 = s;
            if (!p.wall && p.end2 == last) p.end2 = s;
        }
        ++world.contacts.pairs_version;
    }
    b.resize(last);
    if (world.contacts.ball_moved.size() > last) world.contacts.ball_moved.resize(last);
    world.bodies.slot_of[id.index - 1] = kDeadSlot;
    world.bodies.free_handles.push_back(id.index);
}

std::vector<BallId> Model::ballIds() const {
    const World& world = *m_world;
    std::vector<BallId> ids;
    ids.reserve(world.bodies.balls.size());
    for (uint32_t h = 1; h <= world.bodies.slot_of.size(); ++h)
        if (world.bodies.slot_of[h - 1] != kDeadSlot &&
            world.bodies.balls.clump[world.bodies.slot_of[h - 1]] == kNoClump)
            ids.push_back(BallId{h, world.bodies.generation[h - 1]});
    return ids;
}

Vec2 Model::ballPos(BallId id) const {
    const World& world = *m_world;
    return world.bodies.balls.pos[world.bodies.slotOf(id)];
}
Vec2 Model::ballVel(BallId id) const {
    const World& world = *m_world;
    return world.bodies.balls.vel[world.bodies.slotOf(id)];
}
double Model::ballSpin(BallId id) const {
    const World& world = *m_world;
    return world.bodies.balls.spin[world.bodies.slotOf(id)];
}
double Model::ballAngle(BallId id) const {
    const World& world = *m_world;
    return world.bodies.balls.angle[world.bodies.slotOf(id)];
}
double Model::ballRadius(BallId id) const {
    const World& world = *m_world;
    return world.bodies.balls.radius[world.bodies.slotOf(id)];
}
double Model::ballMass(BallId id) const {
    const World& world = *m_world;
    return world.bodies.balls.mass[world.bodies.slotOf(id)];
}
double Model::ballInertia(BallId id) const {
    const World& world = *m_world;
    return world.bodies.balls.inertia[world.bodies.slotOf(id)];
}
double Model::ballDensity(BallId id) const {
    const World& world = *m_world;
    return world.bodies.balls.density[world.bodies.slotOf(id)];
}
Vec2 Model::ballForce(BallId id) const {
    const World& world = *m_world;
    return world.bodies.balls.force[world.bodies.slotOf(id)];
}
double Model::ballMoment(BallId id) const {
    const World& world = *m_world;
    return world.bodies.balls.moment[world.bodies.slotOf(id)];
}
Vec2 Model::ballAppliedForce(BallId id) const {
    const World& world = *m_world;
    return world.bodies.balls.fapp[world.bodies.slotOf(id)];
}
double Model::ballAppliedMoment(BallId id) const {
    const World& world = *m_world;
    return world.bodies.balls.mapp[world.bodies.slotOf(id)];
}
uint8_t Model::ballFixity(BallId id) const {
    const World& world = *m_world;
    return world.bodies.balls.fixity[world.bodies.slotOf(id)];
}

void Model::setBallPos(BallId id, const Vec2& p) {
    World& world = *m_world;
    world.stepping.limits_stale = true;
    requireCoordinate("ball: pos", p);
    const uint32_t s = world.bodies.slotOf(id);
    requireClearOfWalls(world, p, world.bodies.balls.radius[s], "ball " + std::to_string(id.index));
    world.bodies.balls.pos[s] = p;
}
void Model::setBallVel(BallId id, const Vec2& v) {
    World& world = *m_world;
    world.stepping.limits_stale = true;
    requireFinite("vel", v);
    const uint32_t s = world.bodies.slotOf(id);
    requireFiniteEnergy(world.bodies.balls.mass[s], 0.0, v, 0.0);
    noteBallChange(world, s);
    world.bodies.balls.vel[s] = v;
}
void Model::setBallSpin(BallId id, double w) {
    World& world = *m_world;
    world.stepping.limits_stale = true;
    if (!std::isfinite(w)) throw InputError("ball: spin must be finite");
    const uint32_t s = world.bodies.slotOf(id);
    requireFiniteEnergy(0.0, world.bodies.balls.inertia[s], Vec2::Zero(), w);
    noteBallChange(world, s);
    world.bodies.balls.spin[s] = w;
}
void Model::setBallRadius(BallId id, double r) {
    World& world = *m_world;
    world.stepping.limits_stale = true;
    requireRadius(r);
    const uint32_t s = world.bodies.slotOf(id);
    if (world.bodies.balls.density[s] > 0.0) {
        const double rho = world.bodies.balls.density[s];
        const double mass =
            rho * (world.settings.mass_mode == MassMode::Disk ? M_PI * r * r
                                                              : 4.0 / 3.0 * M_PI * r * r * r);
        requireUsableMass(mass,
                          (world.settings.mass_mode == MassMode::Disk ? 0.5 : 0.4) * mass * r * r,
                          "density " + messageNumber(rho) + " and radius " + messageNumber(r));
    }
    noteBallChange(world, s);
    world.bodies.balls.radius[s] = r;
    if (world.bodies.balls.density[s] > 0.0) updateMass(world, s);
    refreshPairMasses(world, s);
    // Its contacts' overlap changes with no work behind it: like a contact born overlapping, each
    // gives back energy it never took, which is the script's doing, not the step's (the guard's
    // energy check passes such contacts; docs/physics/guard.md).
    for (const Pair& p : world.contacts.pairs)
        if (p.active && (p.end1 == s || (!p.wall && p.end2 == s)))
            if (GuardWatch* w = world.contacts.watchOf(world.contacts.coldOf(p)))
                w->born_overlapped = true;
}
void Model::setBallDensity(BallId id, double rho) {
    World& world = *m_world;
    world.stepping.limits_stale = true;
    if (!(rho > 0.0) || !std::isfinite(rho))
        throw InputError("ball: density must be > 0 (got " + messageNumber(rho) + ")");
    const uint32_t s = world.bodies.slotOf(id);
    {
        const double r = world.bodies.balls.radius[s];
        const double mass =
            rho * (world.settings.mass_mode == MassMode::Disk ? M_PI * r * r
                                                              : 4.0 / 3.0 * M_PI * r * r * r);
        requireUsableMass(mass,
                          (world.settings.mass_mode == MassMode::Disk ? 0.5 : 0.4) * mass * r * r,
                          "density " + messageNumber(rho) + " and radius " + messageNumber(r));
    }
    noteBallChange(world, s);
    world.bodies.balls.density[s] = rho;
    updateMass(world, s);
    refreshPairMasses(world, s);
}
void Model::setBallAppliedForce(BallId id, const Vec2& f) {
    World& world = *m_world;
    requireFinite("fapp (applied force)", f);
    const uint32_t s = world.bodies.slotOf(id);
    Vec2& fapp = world.bodies.balls.fapp[s];
    if (fapp != f) {
        world.stepping.limits_stale = true;  // the approach rule's accelerations (timestep.cpp)
        noteBallChange(world, s);
    }
    fapp = f;
}
void Model::setBallAppliedMoment(BallId id, double m) {
    World& world = *m_world;
    if (!std::isfinite(m))
        throw InputError("ball: mapp (applied moment) must be finite (got " + messageNumber(m) +
                         ")");
    const uint32_t s = world.bodies.slotOf(id);
    if (world.bodies.balls.mapp[s] != m) noteBallChange(world, s);
    world.bodies.balls.mapp[s] = m;
}
void Model::setBallFixity(BallId id, uint8_t f) {
    World& world = *m_world;
    const uint32_t s = world.bodies.slotOf(id);
    uint8_t& cur = world.bodies.balls.fixity[s];
    if (cur != f) noteBallChange(world, s);
    world.bodies.fixed_balls += (f != 0) - (cur != 0);
    cur = f;
}

double Model::ballContactProp(BallId id, const std::string& name) const {
    const World& world = *m_world;
    auto& b = world.bodies.balls;
    return inheritableRef(b.kn, b.ks, b.fric, world.bodies.slotOf(id), name, "ball");
}
void Model::setBallContactProp(BallId id, const std::string& name, double v) {
    World& world = *m_world;
    if (!std::isnan(v) && !(v >= 0.0 && std::isfinite(v)))
        throw InputError("ball: " + name + " must be >= 0 (got " + messageNumber(v) + ")");
    auto& b = world.bodies.balls;
    inheritableRef(b.kn, b.ks, b.fric, world.bodies.slotOf(id), name, "ball") = v;
}

std::vector<std::string> Model::ballGroups(BallId id) const {
    const World& world = *m_world;
    std::vector<std::string> out;
    const uint64_t g = world.bodies.balls.groups[world.bodies.slotOf(id)];
    for (std::size_t i = 0; i < world.bodies.group_names.size(); ++i)
        if (g & (uint64_t(1) << i)) out.push_back(world.bodies.group_names[i]);
    return out;
}
void Model::addBallGroup(BallId id, const std::string& group) {
    World& world = *m_world;
    const uint32_t s = world.bodies.slotOf(id);
    world.bodies.balls.groups[s] |= uint64_t(1) << talus::groupIndex(world, group, true);
}

// ------------------------------------------------------------------------ walls

}  // namespace talus
