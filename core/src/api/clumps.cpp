// SPDX-License-Identifier: MIT
//
// The facade, clumps (docs/physics/clumps.md): create a clump from pebbles or a template, delete
// or release it, read and set its state. The clump data is in the body store (ClumpData); its
// pebbles are balls whose mass and inertia fields hold the clump's, so the pairs' effective
// masses (dashpot damping, resolution rule) are the clump's, as in PFC.
#include <cctype>
#include <cmath>
#include <string>

#include "api/input_checks.hpp"
#include "api/operations.hpp"
#include "step/detection.hpp"
#include "step/group_energy.hpp"
#include "step/script_work.hpp"
#include "step/step.hpp"
#include "talus/errors.hpp"
#include "talus/model.hpp"
#include "world/body_store.hpp"
#include "world/contact_store.hpp"
#include "world/messages.hpp"
#include "world/types.hpp"

namespace talus {

namespace {

bool finite2(const Vec2& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); }

void requirePositive(const char* what, double v) {
    if (!(v > 0.0) || !std::isfinite(v) || !std::isfinite(1.0 / v))
        throw InputError(std::string("clump: ") + what + " must be a positive finite number (got " +
                         messageNumber(v) + ")");
}

Vec2 rotate(const Vec2& v, double a) {
    const double c = std::cos(a), s = std::sin(a);
    return Vec2(c * v.x() - s * v.y(), s * v.x() + c * v.y());
}

std::string clumpText(ClumpId id) { return "clump " + std::to_string(id.index); }

// A pebble becomes a ball: the ball limits apply (api/balls.cpp, kMinRadius and
// kMaxCoordinate). They are checked before the mass properties, whose arc integrals underflow
// for a radius of 1e-320 (the union's area came out 0: an internal assertion reached the user)
// and overflow for 1e300 (the error then named the mass, not the pebble).
constexpr double kPebbleMinRadius = 1e-12;  // [m]
constexpr double kPebbleMaxLength = 1e9;    // [m]
void requirePebbles(const std::vector<Pebble>& peb, const std::string& what, double scale) {
    const std::string scaled = scale != 1.0 ? " (after scale " + messageNumber(scale) + ")" : "";
    for (std::size_t i = 0; i < peb.size(); ++i) {
        const double r = peb[i].radius;
        const std::string name = what + ": pebble " + std::to_string(i + 1);
        if (!(r >= kPebbleMinRadius && r <= kPebbleMaxLength))
            throw InputError(name + " radius " + messageNumber(r) + " m" + scaled +
                             " is out of range [" + messageNumber(kPebbleMinRadius) + ", " +
                             messageNumber(kPebbleMaxLength) + "] m");
        if (!(std::fabs(peb[i].pos.x()) <= kPebbleMaxLength &&
              std::fabs(peb[i].pos.y()) <= kPebbleMaxLength))
            throw InputError(name + " position " + vecText(peb[i].pos) + scaled +
                             " is out of range: coordinates must be within " +
                             messageNumber(kPebbleMaxLength) + " m");
    }
}

/// Mass, inertia about the centroid, density (0 when direct) and centroid (pebbles' frame) of
/// a clump of the (scaled) pebbles `peb`; `props` holds a template's scaled properties.
void resolveMass(const std::vector<Pebble>& peb, const ClumpDef& d, double sc, bool from_template,
                 MassProps props, MassMode model_mode, ClumpMassMode& mode, double& mass,
                 double& inertia, double& density, Vec2& centroid) {
    const bool direct = mode == ClumpMassMode::Direct || !std::isnan(d.mass);
    if (direct) mode = ClumpMassMode::Direct;
    if (!from_template || direct) props = clumpMassProps(peb, direct ? ClumpMassMode::Union : mode);

    // --- mass, inertia, centroid (pebbles' frame)
    density = 0.0;
    centroid = props.centroid;
    if (direct) {
        if (!std::isnan(d.density))
            throw InputError("clump: give 'density' or direct 'mass' and 'inertia', not both");
        requirePositive("mass", d.mass);
        requirePositive("inertia", d.inertia);
        mass = d.mass;
        inertia = d.inertia;
        if (!std::isnan(d.centroid.x()) || !std::isnan(d.centroid.y())) {
            if (!finite2(d.centroid)) throw InputError("clump: centroid must be finite");
            centroid = d.centroid * sc;
            if (!(std::fabs(centroid.x()) <= kPebbleMaxLength &&
                  std::fabs(centroid.y()) <= kPebbleMaxLength))
                throw InputError("clump: centroid " + vecText(centroid) +
                                 " is out of range: coordinates must be within " +
                                 messageNumber(kPebbleMaxLength) + " m");
        }
    } else {
        if (model_mode == MassMode::Sphere)
            throw InputError(
                "clump: the model's mass mode is 'sphere', and the union of spheres is not "
                "supported; give the clump's mass and inertia directly (mass_mode = direct)");
        if (!std::isnan(d.inertia) || !std::isnan(d.centroid.x()))
            throw InputError("clump: 'inertia' and 'centroid' need direct mass ('mass')");
        requirePositive("density", d.density);
        density = d.density;
        if (peb.size() == 1) {
            // One pebble: the same expressions as a ball's (updateMass), so that such a
            // clump moves bit for bit as the ball.
            const double r = peb[0].radius;
            mass = density * M_PI * r * r;
            inertia = 0.5 * mass * r * r;
            centroid = peb[0].pos;
        } else {
            mass = density * props.area;
            inertia = density * props.polar_moment;
        }
        requirePositive("mass (density x area)", mass);
        requirePositive("inertia (density x polar moment)", inertia);
    }
}

}  // namespace

// ------------------------------------------------------------------------ templates

int Model::defineClumpTemplate(const std::vector<Pebble>& pebbles, ClumpMassMode mode) {
    World& world = *m_world;
    if (pebbles.empty()) throw InputError("clump template: needs at least one pebble");
    ClumpTemplate t;
    t.pebbles = pebbles;
    t.mass_mode = mode;
    // Computed once here; a placement scales them (area s^2, centroid s, polar moment s^4).
    // Direct templates carry no geometric mass (the placement gives mass and inertia), but the
    // pebbles are checked all the same.
    requirePebbles(pebbles, "clump template", 1.0);
    t.props = clumpMassProps(pebbles, mode == ClumpMassMode::Direct ? ClumpMassMode::Union : mode);
    if (mode == ClumpMassMode::Direct) t.props.area = t.props.polar_moment = 0.0;
    world.bodies.clump_templates.push_back(std::move(t));
    return static_cast<int>(world.bodies.clump_templates.size());
}

const ClumpTemplate& Model::clumpTemplate(int id) const {
    const World& world = *m_world;
    if (id < 1 || static_cast<std::size_t>(id) > world.bodies.clump_templates.size())
        throw InputError("clump template " + std::to_string(id) + " does not exist");
    return world.bodies.clump_templates[static_cast<std::size_t>(id) - 1];
}

// ------------------------------------------------------------------------ create

namespace {

/// The pebbles of a new clump, scaled, and the template's scaled mass properties per unit
/// density (a template's mass mode, unless direct, into `mode`).
std::vector<Pebble> scaledPebbles(const Model& model, const ClumpDef& d, ClumpMassMode& mode,
                                  MassProps& props) {
    if (!(d.scale > 0.0) || !std::isfinite(d.scale))
        throw InputError("clump: scale must be > 0 (got " + messageNumber(d.scale) + ")");
    const double sc = d.scale;
    std::vector<Pebble> peb;
    if (d.template_id != 0) {
        if (!d.pebbles.empty()) throw InputError("clump: give pebbles or a template, not both");
        const ClumpTemplate& t = model.clumpTemplate(d.template_id);
        peb = t.pebbles;
        if (mode == ClumpMassMode::Union) mode = t.mass_mode;  // the template's unless direct
        for (Pebble& p : peb) p.pos *= sc, p.radius *= sc;
        props.area = t.props.area * sc * sc;
        props.centroid = t.props.centroid * sc;
        props.polar_moment = t.props.polar_moment * sc * sc * sc * sc;
    } else {
        if (d.pebbles.empty()) throw InputError("clump: needs at least one pebble");
        peb = d.pebbles;
        for (std::size_t i = 0; i < peb.size(); ++i) {
            if (!finite2(peb[i].pos))
                throw InputError("clump: pebble " + std::to_string(i + 1) + " position " +
                                 vecText(peb[i].pos) + " is not finite");
            if (!(peb[i].radius > 0.0) || !std::isfinite(peb[i].radius))
                throw InputError("clump: pebble " + std::to_string(i + 1) +
                                 " radius must be > 0 (got " + messageNumber(peb[i].radius) + ")");
            peb[i].pos *= sc, peb[i].radius *= sc;
        }
    }
    requirePebbles(peb, "clump", sc);
    return peb;
}

/// The clump's motion and properties as given: finite, a finite kinetic energy, kn/ks/fric >= 0.
void checkClumpState(const ClumpDef& d, bool placed, double mass, double inertia) {
    if (placed && !finite2(d.pos)) throw InputError("clump: pos must be finite");
    if (!std::isfinite(d.angle)) throw InputError("clump: angle must be finite");
    if (!finite2(d.vel) || !std::isfinite(d.spin))
        throw InputError("clump: vel and spin must be finite");
    if (!std::isfinite(0.5 * (mass * d.vel.squaredNorm() + inertia * d.spin * d.spin)))
        throw InputError("clump: vel and spin give an infinite kinetic energy");
    for (double v : {d.kn, d.ks, d.fric})
        if (!std::isnan(v) && !(v >= 0.0 && std::isfinite(v)))
            throw InputError("clump: kn, ks and fric must be >= 0 (got " + messageNumber(v) + ")");
}

/// A clump record with its mass properties.
ClumpData clumpWithMass(ClumpMassMode mode, double mass, double inertia, double density) {
    ClumpData c;
    c.mode = mode;
    c.mass = mass, c.inv_mass = 1.0 / mass;
    c.inertia = inertia, c.inv_inertia = 1.0 / inertia;
    c.density = density;
    return c;
}

/// A ball per pebble of clump `index`, at its place in the clump with the clump's motion. A
/// pebble the ball checks refuse (radius or position out of range) undoes the clump.
void addPebbleBalls(World& world, uint32_t index, const std::vector<Pebble>& peb) {
    try {
        for (std::size_t k = 0; k < peb.size(); ++k) {
            ClumpData& cl = world.bodies.clumps[index];
            BallDef bd;
            const Vec2 r = rotate(cl.offset[k], cl.angle);
            bd.pos = cl.pos + r;
            bd.radius = peb[k].radius;
            bd.mass = cl.mass;
            bd.inertia = cl.inertia;
            bd.vel = cl.vel + spinCross(cl.spin, r);
            bd.spin = cl.spin;
            bd.angle = cl.angle;
            bd.kn = cl.kn, bd.ks = cl.ks, bd.fric = cl.fric;
            const BallId id = createBallIn(world, bd, index);
            const uint32_t s = world.bodies.slotOf(id);
            world.bodies.balls.groups[s] = cl.groups;
            world.bodies.balls.density[s] = cl.density;
            world.bodies.clumps[index].pebbles.push_back(id.index);
        }
    } catch (const InputError& e) {
        ClumpData& cl = world.bodies.clumps[index];
        for (uint32_t h : cl.pebbles)
            removeBall(world, BallId{h, world.bodies.generation[h - 1]}, false);
        cl.pebbles.clear();
        cl.alive = false;
        --world.bodies.live_clumps;
        throw InputError(std::string("clump: ") + e.what());
    }
}

}  // namespace

ClumpId Model::createClump(const ClumpDef& d) {
    World& world = *m_world;
    // --- pebbles and the geometric mass properties per unit density, in the pebbles' frame
    MassProps props;
    ClumpMassMode mode = d.mass_mode;
    const std::vector<Pebble> peb = scaledPebbles(*this, d, mode, props);
    double mass, inertia, density;
    Vec2 centroid;
    resolveMass(peb, d, d.scale, d.template_id != 0, props, world.settings.mass_mode, mode, mass,
                inertia, density, centroid);
    const bool placed = !std::isnan(d.pos.x()) || !std::isnan(d.pos.y());
    checkClumpState(d, placed, mass, inertia);

    // --- state
    ClumpData c = clumpWithMass(mode, mass, inertia, density);
    c.angle = d.angle;
    // With `pos` the pebbles are in the clump frame at angle 0 and the clump is turned by
    // `angle`; without it they are where they are, and `angle` only names the orientation.
    c.pos = placed ? d.pos : centroid;
    c.vel = d.vel;
    c.spin = d.spin;
    c.fixity = d.fixity;
    for (const auto& g : d.groups) c.groups |= uint64_t(1) << talus::groupIndex(world, g, true);
    c.kn = d.kn, c.ks = d.ks, c.fric = d.fric;
    for (const Pebble& p : peb) {
        const Vec2 o = p.pos - centroid;
        c.offset.push_back(placed ? o : rotate(o, -d.angle));
        c.angle_offset.push_back(0.0);
    }
    const uint32_t index = static_cast<uint32_t>(world.bodies.clumps.size());
    world.bodies.clumps.push_back(c);
    ++world.bodies.live_clumps;
    addPebbleBalls(world, index, peb);
    placePebbles(world, world.bodies.clumps[index]);
    world.stepping.limits_stale = true;
    noteClumpAdded(world, index);  // its kinetic energy comes in as script work
    return world.bodies.clumpId(index);
}

namespace {

/// The balls' slots (each free, listed once) and the pebbles at their places; their total mass
/// and area.
std::vector<uint32_t> ballSlots(const World& world, const std::vector<BallId>& ids,
                                std::vector<Pebble>& peb, double& mass, double& area) {
    const auto& b = world.bodies.balls;
    std::vector<uint32_t> slots;
    mass = area = 0.0;
    for (std::size_t i = 0; i < ids.size(); ++i) {
        const uint32_t s = world.bodies.slotOf(ids[i]);
        if (b.clump[s] != kNoClump)
            throw InputError("clump: ball " + std::to_string(ids[i].index) +
                             " is already a pebble of clump " + std::to_string(b.clump[s] + 1));
        for (uint32_t t : slots)
            if (t == s)
                throw InputError("clump: ball " + std::to_string(ids[i].index) +
                                 " is listed twice");
        slots.push_back(s);
        peb.push_back(Pebble{b.pos[s], b.radius[s]});
        mass += b.mass[s];
        area += M_PI * b.radius[s] * b.radius[s];
    }
    return slots;
}

/// The balls' momentum and angular momentum about the centroid, given to the rigid body
/// (v = P / sum m, w = L / sum (I + m d^2), the balls' own masses): the rigid motion that
/// conserves both when the clump's mass equals the balls' (no overlaps).
void rigidMotion(const World& world, const std::vector<uint32_t>& slots, double ball_mass,
                 ClumpData& c) {
    const auto& b = world.bodies.balls;
    Vec2 p = Vec2::Zero();
    for (uint32_t s : slots) p += b.mass[s] * b.vel[s];
    const Vec2 v = p / ball_mass;
    double l = 0.0, i_sum = 0.0;
    for (uint32_t s : slots) {
        const Vec2 r = b.pos[s] - c.pos;
        l += b.inertia[s] * b.spin[s] + b.mass[s] * cross(r, b.vel[s] - v);
        i_sum += b.inertia[s] + b.mass[s] * r.squaredNorm();
    }
    c.vel = v;
    c.spin = l / i_sum;
}

/// The pairs between the balls go (pebbles of one clump never touch); their stored energy is
/// released (removePair). Contacts with other bodies are kept, with the clump's mass.
void removeInnerPairs(World& world, const std::vector<uint32_t>& slots) {
    for (std::size_t i = world.contacts.pairs.size(); i-- > 0;) {
        const Pair& pr = world.contacts.pairs[i];
        if (pr.wall) continue;
        bool in1 = false, in2 = false;
        for (uint32_t s : slots) in1 |= pr.end1 == s, in2 |= pr.end2 == s;
        if (in1 && in2) removePair(world, i);
    }
}

/// The balls become the pebbles of clump `c` (to be clump `index`): the clump's mass, groups
/// and unset properties, no fixity or applied load of their own.
void makePebbles(World& world, const std::vector<uint32_t>& slots, ClumpData& c, uint32_t index) {
    auto& b = world.bodies.balls;
    for (uint32_t s : slots) {
        c.pebbles.push_back(b.handle[s]);
        c.offset.push_back(b.pos[s] - c.pos);
        c.angle_offset.push_back(b.angle[s]);
        b.clump[s] = index;
        ++world.bodies.pebble_count;
        if (b.fixity[s]) --world.bodies.fixed_balls;
        b.fixity[s] = 0;
        b.fapp[s] = Vec2::Zero(), b.mapp[s] = 0.0;
        b.mass[s] = c.mass, b.inv_mass[s] = c.inv_mass;
        b.inertia[s] = c.inertia, b.inv_inertia[s] = c.inv_inertia;
        b.density[s] = c.density;
        b.groups[s] = c.groups;
        // A ball's own kn/ks/fric stay its own (a pebble may set its own); unset ones take the
        // clump's.
        if (std::isnan(b.kn[s])) b.kn[s] = c.kn;
        if (std::isnan(b.ks[s])) b.ks[s] = c.ks;
        if (std::isnan(b.fric[s])) b.fric[s] = c.fric;
    }
}

}  // namespace

ClumpId Model::createClumpFromBalls(const std::vector<BallId>& ids, const ClumpDef& opts) {
    World& world = *m_world;
    if (ids.empty()) throw InputError("clump: 'balls' is empty: a clump needs at least one ball");
    if (!opts.pebbles.empty() || opts.template_id)
        throw InputError("clump: give balls, pebbles or a template, not two of them");
    std::vector<Pebble> peb;
    double ball_mass, ball_area;
    const std::vector<uint32_t> slots = ballSlots(world, ids, peb, ball_mass, ball_area);
    // Density: the given one, else the balls' mass over their area (their common density when
    // they share one).
    ClumpDef d = opts;
    if (std::isnan(d.mass) && std::isnan(d.density) && d.mass_mode != ClumpMassMode::Direct)
        d.density = ball_mass / ball_area;
    ClumpMassMode mode = d.mass_mode;
    double mass, inertia, density;
    Vec2 centroid;
    resolveMass(peb, d, 1.0, false, MassProps{}, world.settings.mass_mode, mode, mass, inertia,
                density, centroid);
    ClumpData c = clumpWithMass(mode, mass, inertia, density);
    c.pos = centroid;
    c.angle = 0.0;
    rigidMotion(world, slots, ball_mass, c);
    c.fixity = opts.fixity;
    for (const auto& g : opts.groups) c.groups |= uint64_t(1) << talus::groupIndex(world, g, true);
    if (opts.groups.empty())
        for (uint32_t s : slots) c.groups |= world.bodies.balls.groups[s];
    c.kn = opts.kn, c.ks = opts.ks, c.fric = opts.fric;
    const uint32_t index = static_cast<uint32_t>(world.bodies.clumps.size());
    removeInnerPairs(world, slots);
    // The balls' kinetic energy becomes the clump's (momentum is kept, energy is not): script
    // work, booked at the next step.
    for (uint32_t s : slots) noteBallChange(world, s);
    makePebbles(world, slots, c, index);
    world.bodies.clumps.push_back(c);
    ++world.bodies.live_clumps;
    placePebbles(world, world.bodies.clumps[index]);
    for (uint32_t s : slots) refreshPairMasses(world, s);
    world.stepping.limits_stale = true;
    noteClumpAdded(world, index);
    return world.bodies.clumpId(index);
}

// ------------------------------------------------------------------------ delete, release

void Model::deleteClump(ClumpId id) {
    World& world = *m_world;
    const uint32_t ci = world.bodies.clumpIndex(id);
    ClumpData& c = world.bodies.clumps[ci];
    // What the next snapshot would have taken for the clump leaves the books as `deleted`, at
    // the next step (Model::deleteBall does the same for a ball); its pebbles' contacts release
    // their stored energy (removePair).
    noteClumpDeleted(world, ci);
    const std::vector<uint32_t> pebbles = c.pebbles;
    for (uint32_t h : pebbles) removeBall(world, BallId{h, world.bodies.generation[h - 1]}, false);
    ClumpData& dead = world.bodies.clumps[ci];
    dead.pebbles.clear(), dead.offset.clear(), dead.angle_offset.clear();
    dead.alive = false;
    --world.bodies.live_clumps;
    world.stepping.limits_stale = true;
}

std::vector<BallId> Model::releaseClump(ClumpId id) {
    World& world = *m_world;
    const uint32_t ci = world.bodies.clumpIndex(id);
    ClumpData& c = world.bodies.clumps[ci];
    auto& b = world.bodies.balls;
    // Density of the new balls: the clump's, or in direct mode the clump's mass shared by area.
    double rho = c.density;
    if (!(rho > 0.0)) {
        double area = 0.0;
        for (std::size_t k = 0; k < c.pebbles.size(); ++k) {
            const double r = b.radius[world.bodies.pebbleSlot(c, k)];
            area += world.settings.mass_mode == MassMode::Disk ? M_PI * r * r
                                                               : 4.0 / 3.0 * M_PI * r * r * r;
        }
        rho = c.mass / area;
    }
    std::vector<BallId> out;
    std::vector<uint32_t> slots;
    // The balls' masses are not the clump's (overlaps now count twice, and the inertia of the
    // pieces about their own centres replaces the union's), so the kinetic energy changes at the
    // release: script work, the balls' energy less the clump's, booked at the next step.
    noteClumpChange(world, ci);
    for (std::size_t k = 0; k < c.pebbles.size(); ++k) {
        const uint32_t s = world.bodies.pebbleSlot(c, k);
        // The pebble already moves with the clump's rigid velocity at the half step.
        b.clump[s] = kNoClump;
        --world.bodies.pebble_count;
        b.density[s] = rho;
        updateMass(world, s);
        refreshPairMasses(world, s);
        b.fixity[s] = c.fixity;
        if (c.fixity) ++world.bodies.fixed_balls;
        slots.push_back(s);
        out.push_back(world.bodies.ballId(s));
    }
    for (uint32_t s : slots) noteBallAdded(world, s);
    c.pebbles.clear(), c.offset.clear(), c.angle_offset.clear();
    c.alive = false;
    --world.bodies.live_clumps;
    // Former pebbles of this clump may now touch: their fat boxes overlap already, so the
    // broadphase would not report them again.
    if (world.contacts.broadphase_ready)
        for (uint32_t s : slots) addPairsForBall(world, s);
    world.stepping.limits_stale = true;
    return out;
}

// ------------------------------------------------------------------------ queries

bool Model::isAlive(ClumpId id) const {
    const World& world = *m_world;
    return id.index != 0 && id.index <= world.bodies.clumps.size() &&
           world.bodies.clumps[id.index - 1].alive &&
           world.bodies.clumps[id.index - 1].generation == id.generation;
}
std::size_t Model::clumpCount() const {
    const World& world = *m_world;
    return world.bodies.live_clumps;
}
std::vector<ClumpId> Model::clumpIds() const {
    const World& world = *m_world;
    std::vector<ClumpId> ids;
    for (uint32_t i = 0; i < world.bodies.clumps.size(); ++i)
        if (world.bodies.clumps[i].alive) ids.push_back(world.bodies.clumpId(i));
    return ids;
}
ClumpId Model::clumpOf(BallId id) const {
    const World& world = *m_world;
    const uint32_t k = world.bodies.balls.clump[world.bodies.slotOf(id)];
    return k == kNoClump ? ClumpId{} : world.bodies.clumpId(k);
}

#define TALUS_CLUMP(id) world.bodies.clumps[world.bodies.clumpIndex(id)]

Vec2 Model::clumpPos(ClumpId id) const {
    const World& world = *m_world;
    return TALUS_CLUMP(id).pos;
}
Vec2 Model::clumpVel(ClumpId id) const {
    const World& world = *m_world;
    return TALUS_CLUMP(id).vel;
}
double Model::clumpSpin(ClumpId id) const {
    const World& world = *m_world;
    return TALUS_CLUMP(id).spin;
}
double Model::clumpAngle(ClumpId id) const {
    const World& world = *m_world;
    return TALUS_CLUMP(id).angle;
}
double Model::clumpMass(ClumpId id) const {
    const World& world = *m_world;
    return TALUS_CLUMP(id).mass;
}
double Model::clumpInertia(ClumpId id) const {
    const World& world = *m_world;
    return TALUS_CLUMP(id).inertia;
}
double Model::clumpDensity(ClumpId id) const {
    const World& world = *m_world;
    return TALUS_CLUMP(id).density;
}
Vec2 Model::clumpForce(ClumpId id) const {
    const World& world = *m_world;
    return TALUS_CLUMP(id).force;
}
double Model::clumpMoment(ClumpId id) const {
    const World& world = *m_world;
    return TALUS_CLUMP(id).moment;
}
Vec2 Model::clumpAppliedForce(ClumpId id) const {
    const World& world = *m_world;
    return TALUS_CLUMP(id).fapp;
}
double Model::clumpAppliedMoment(ClumpId id) const {
    const World& world = *m_world;
    return TALUS_CLUMP(id).mapp;
}
uint8_t Model::clumpFixity(ClumpId id) const {
    const World& world = *m_world;
    return TALUS_CLUMP(id).fixity;
}

namespace {
/// A clump moved or turned (placed already): refused, and put back with `undo`, when a pebble's
/// centre lands within half its radius of a wall (requireClearOfWalls).
template <class Undo>
void requirePebblesClear(World& world, ClumpData& c, Undo undo, const std::string& what) {
    const auto& b = world.bodies.balls;
    try {
        for (std::size_t k = 0; k < c.pebbles.size(); ++k) {
            const uint32_t s = world.bodies.pebbleSlot(c, k);
            requireClearOfWalls(world, b.pos[s], b.radius[s],
                                what + " pebble " + std::to_string(k + 1));
        }
    } catch (const InputError&) {
        undo();
        placePebbles(world, c);
        throw;
    }
}
}  // namespace

void Model::setClumpPos(ClumpId id, const Vec2& p) {
    World& world = *m_world;
    if (!finite2(p)) throw InputError(clumpText(id) + ": pos must be finite");
    // The range of a ball's pos (its pebbles are balls).
    if (!(std::fabs(p.x()) <= kPebbleMaxLength && std::fabs(p.y()) <= kPebbleMaxLength))
        throw InputError(clumpText(id) + ": pos " + vecText(p) +
                         " is out of range: coordinates must be within " +
                         messageNumber(kPebbleMaxLength) + " m of the origin");
    ClumpData& c = TALUS_CLUMP(id);
    const Vec2 was = c.pos;
    c.pos = p;
    placePebbles(world, c);
    requirePebblesClear(
        world, c, [&] { c.pos = was; }, clumpText(id));
    world.stepping.limits_stale = true;
}
void Model::setClumpVel(ClumpId id, const Vec2& v) {
    World& world = *m_world;
    ClumpData& c = TALUS_CLUMP(id);
    if (!finite2(v) || !std::isfinite(0.5 * c.mass * v.squaredNorm()))
        throw InputError(clumpText(id) + ": vel " + vecText(v) + " is not usable");
    noteClumpChange(world, world.bodies.clumpIndex(id));
    c.vel = v;
    placePebbles(world, c);
    world.stepping.limits_stale = true;
}
void Model::setClumpSpin(ClumpId id, double w) {
    World& world = *m_world;
    ClumpData& c = TALUS_CLUMP(id);
    if (!std::isfinite(w) || !std::isfinite(0.5 * c.inertia * w * w))
        throw InputError(clumpText(id) + ": spin " + messageNumber(w) + " is not usable");
    noteClumpChange(world, world.bodies.clumpIndex(id));
    c.spin = w;
    placePebbles(world, c);
    world.stepping.limits_stale = true;
}
void Model::setClumpAngle(ClumpId id, double a) {
    World& world = *m_world;
    if (!std::isfinite(a)) throw InputError(clumpText(id) + ": angle must be finite");
    ClumpData& c = TALUS_CLUMP(id);
    const double was = c.angle;
    c.angle = a;
    placePebbles(world, c);
    requirePebblesClear(
        world, c, [&] { c.angle = was; }, clumpText(id));
    world.stepping.limits_stale = true;
}
void Model::setClumpAppliedForce(ClumpId id, const Vec2& f) {
    World& world = *m_world;
    if (!finite2(f)) throw InputError(clumpText(id) + ": fapp (applied force) must be finite");
    noteClumpChange(world, world.bodies.clumpIndex(id));
    TALUS_CLUMP(id).fapp = f;
    world.stepping.limits_stale = true;
}
void Model::setClumpAppliedMoment(ClumpId id, double m) {
    World& world = *m_world;
    if (!std::isfinite(m))
        throw InputError(clumpText(id) + ": mapp (applied moment) must be finite");
    noteClumpChange(world, world.bodies.clumpIndex(id));
    TALUS_CLUMP(id).mapp = m;
}
void Model::setClumpFixity(ClumpId id, uint8_t f) {
    World& world = *m_world;
    noteClumpChange(world, world.bodies.clumpIndex(id));
    TALUS_CLUMP(id).fixity = f;
}

double Model::clumpContactProp(ClumpId id, const std::string& name) const {
    const World& world = *m_world;
    const ClumpData& c = TALUS_CLUMP(id);
    const std::string n = lower(name);
    if (n == "kn") return c.kn;
    if (n == "ks") return c.ks;
    if (n == "fric") return c.fric;
    throw InputError("clump: unknown contact property '" + name + "' (inheritable: kn, ks, fric)");
}
void Model::setClumpContactProp(ClumpId id, const std::string& name, double v) {
    World& world = *m_world;
    if (!std::isnan(v) && !(v >= 0.0 && std::isfinite(v)))
        throw InputError("clump: " + name + " must be >= 0 (got " + messageNumber(v) + ")");
    ClumpData& c = TALUS_CLUMP(id);
    const std::string n = lower(name);
    double ClumpData::*field = n == "kn"     ? &ClumpData::kn
                               : n == "ks"   ? &ClumpData::ks
                               : n == "fric" ? &ClumpData::fric
                                             : nullptr;
    if (!field)
        throw InputError("clump: unknown contact property '" + name +
                         "' (inheritable: kn, ks, fric)");
    c.*field = v;
    // The pebbles inherit the clump's value (pairs made from now on see it).
    auto& b = world.bodies.balls;
    for (std::size_t k = 0; k < c.pebbles.size(); ++k) {
        const uint32_t s = world.bodies.pebbleSlot(c, k);
        (n == "kn" ? b.kn : n == "ks" ? b.ks : b.fric)[s] = v;
    }
}

std::vector<std::string> Model::clumpGroups(ClumpId id) const {
    const World& world = *m_world;
    std::vector<std::string> out;
    const uint64_t g = TALUS_CLUMP(id).groups;
    for (std::size_t i = 0; i < world.bodies.group_names.size(); ++i)
        if (g & (uint64_t(1) << i)) out.push_back(world.bodies.group_names[i]);
    return out;
}
void Model::addClumpGroup(ClumpId id, const std::string& group) {
    World& world = *m_world;
    ClumpData& c = TALUS_CLUMP(id);
    c.groups |= uint64_t(1) << talus::groupIndex(world, group, true);
    // Pebbles carry their clump's groups (contact-model rules, energy allocation).
    for (std::size_t k = 0; k < c.pebbles.size(); ++k)
        world.bodies.balls.groups[world.bodies.pebbleSlot(c, k)] = c.groups;
}

std::vector<Pebble> Model::clumpPebbles(ClumpId id) const {
    const World& world = *m_world;
    const ClumpData& c = TALUS_CLUMP(id);
    std::vector<Pebble> out;
    for (std::size_t k = 0; k < c.pebbles.size(); ++k) {
        const uint32_t s = world.bodies.pebbleSlot(c, k);
        out.push_back(Pebble{world.bodies.balls.pos[s], world.bodies.balls.radius[s]});
    }
    return out;
}
std::vector<BallId> Model::clumpPebbleIds(ClumpId id) const {
    const World& world = *m_world;
    const ClumpData& c = TALUS_CLUMP(id);
    std::vector<BallId> out;
    for (uint32_t h : c.pebbles) out.push_back(BallId{h, world.bodies.generation[h - 1]});
    return out;
}

#undef TALUS_CLUMP

}  // namespace talus
