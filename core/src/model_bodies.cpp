// SPDX-License-Identifier: MIT
//
// Model's ball and wall API: create and delete bodies, read and set their state, with the input
// checks every value from a script goes through. The data is in the body store (body_store.hpp);
// changes that touch contacts (mass, radius, deletion) update the contact store as well.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "body_store.hpp"
#include "broadphase.hpp"
#include "contact_store.hpp"
#include "model_internal.hpp"
#include "narrowphase.hpp"
#include "props.hpp"
#include "talus/errors.hpp"
#include "talus/model.hpp"

namespace talus {

namespace {

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// Input ranges (issue 6, item 12). Every value a script gives, and every value derived from it
// (mass, inertia), must be finite and usable: a radius of 1e300 gave an infinite mass, a wall at
// 1e200 m broke the broadphase (its tree stores float coordinates) and failed later blaming the
// model. Coordinates beyond 1e9 m are refused: there a double resolves 1e-7 m, coarser than the
// overlaps of a stiff contact, and the float broadphase tree (scale 0.1 / margin, margin >=
// 1e-9 m, contact_detection.cpp) stays far from float overflow (3.4e38).
constexpr double kMaxCoordinate = 1e9;  // [m]
constexpr double kMinRadius = 1e-12;    // [m]

bool inRange(const Vec2& v) {
    return std::fabs(v.x()) <= kMaxCoordinate && std::fabs(v.y()) <= kMaxCoordinate;
}

/// Throws unless a coordinate is finite and within +-kMaxCoordinate; `what` names the option.
void requireCoordinate(const std::string& what, const Vec2& v) {
    if (!std::isfinite(v.x()) || !std::isfinite(v.y()))
        throw InputError(what + " must be finite (got " + vecText(v) + ")");
    if (!inRange(v))
        throw InputError(what + " " + vecText(v) + " is out of range: coordinates must be within " +
                         messageNumber(kMaxCoordinate) + " m of the origin");
}

void requireRadius(double r) {
    if (!(r > 0.0) || !std::isfinite(r))
        throw InputError("ball: radius must be > 0 (got " + messageNumber(r) + ")");
    if (r < kMinRadius || r > kMaxCoordinate)
        throw InputError("ball: radius " + messageNumber(r) + " m is out of range [" +
                         messageNumber(kMinRadius) + ", " + messageNumber(kMaxCoordinate) + "] m");
}

/// The kinetic energy a velocity or spin gives must be finite: vel or spin = 1e300 made the
/// energy totals infinite and balance_error -inf.
void requireFiniteEnergy(double mass, double inertia, const Vec2& vel, double spin) {
    if (!std::isfinite(0.5 * mass * vel.squaredNorm()))
        throw InputError("ball: vel " + vecText(vel) + " gives a ball of " + messageNumber(mass) +
                         " kg an infinite kinetic energy");
    if (!std::isfinite(0.5 * inertia * spin * spin))
        throw InputError("ball: spin " + messageNumber(spin) + " gives a ball of inertia " +
                         messageNumber(inertia) + " kg m^2 an infinite kinetic energy");
}

/// Mass and inertia of a disk or sphere; throws when either (or its inverse) is not a finite
/// positive number (a huge radius or density overflows, a tiny one underflows).
void requireUsableMass(double mass, double inertia, const std::string& from) {
    auto usable = [](double v) { return v > 0.0 && std::isfinite(v) && std::isfinite(1.0 / v); };
    if (!usable(mass))
        throw InputError("ball: " + from + " give a mass of " + messageNumber(mass) +
                         " kg, which is not a usable positive number");
    if (!usable(inertia))
        throw InputError("ball: " + from + " give a moment of inertia of " +
                         messageNumber(inertia) + " kg m^2, which is not a usable positive number");
}

}  // namespace

// ------------------------------------------------------------------------ balls

uint32_t Model::slotOf(BallId id) const { return m_bodies->slotOf(id); }
bool Model::isAlive(BallId id) const { return m_bodies->isAlive(id); }
std::string Model::describeBall(uint32_t slot) const { return m_bodies->describeBall(slot); }

std::size_t Model::ballCount() const { return m_bodies->balls.size() - m_bodies->pebble_count; }

void Model::refreshPairMasses(uint32_t s) {
    // Pairs cache their effective mass (force_displacement.cpp); a mass change is rare.
    const auto& b = m_bodies->balls;
    for (auto& p : m_contacts->pairs)
        if (p.end1 == s || (!p.wall && p.end2 == s))
            p.mass_eff = p.wall
                             ? b.mass[p.end1]
                             : b.mass[p.end1] * b.mass[p.end2] / (b.mass[p.end1] + b.mass[p.end2]),
            p.inv_mass_eff_s = tangentialInverseMass(p);
}

void Model::updateMass(uint32_t s) {
    auto& b = m_bodies->balls;
    const double r = b.radius[s];
    if (m_mass_mode == MassMode::Disk) {
        b.mass[s] = b.density[s] * M_PI * r * r;  // unit thickness
        b.inertia[s] = 0.5 * b.mass[s] * r * r;
    } else {
        b.mass[s] = b.density[s] * 4.0 / 3.0 * M_PI * r * r * r;
        b.inertia[s] = 0.4 * b.mass[s] * r * r;
    }
    b.inv_mass[s] = 1.0 / b.mass[s];
    b.inv_inertia[s] = 1.0 / b.inertia[s];
}

BallId Model::createBall(const BallDef& d) { return createBallIn(d, kNoClump); }

BallId Model::createBallIn(const BallDef& d, uint32_t clump) {
    m_limits_stale = true;
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
        const bool disk = m_mass_mode == MassMode::Disk;
        const double volume = disk ? M_PI * r * r : 4.0 / 3.0 * M_PI * r * r * r;
        const double mass = has_mass ? d.mass : d.density * volume;
        const double inertia =
            !std::isnan(d.inertia) ? d.inertia : (disk ? 0.5 : 0.4) * mass * r * r;
        requireUsableMass(
            mass, inertia,
            has_mass ? "mass " + messageNumber(d.mass) + " and radius " + messageNumber(r)
                     : "density " + messageNumber(d.density) + " and radius " + messageNumber(r));
        requireFiniteEnergy(mass, inertia, d.vel, d.spin);
    }

    auto& b = m_bodies->balls;
    const uint32_t s = static_cast<uint32_t>(b.size());
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
        b.inertia[s] = (m_mass_mode == MassMode::Disk ? 0.5 : 0.4) * d.mass * d.radius * d.radius;
        b.inv_mass[s] = 1.0 / d.mass;
        b.inv_inertia[s] = 1.0 / b.inertia[s];
        b.density[s] = d.mass / (m_mass_mode == MassMode::Disk
                                     ? M_PI * d.radius * d.radius
                                     : 4.0 / 3.0 * M_PI * d.radius * d.radius * d.radius);
    } else {
        updateMass(s);
    }
    if (!std::isnan(d.inertia)) {
        b.inertia[s] = d.inertia;
        b.inv_inertia[s] = 1.0 / d.inertia;
    }
    b.fixity[s] = d.fixity;
    if (d.fixity) ++m_fixed_balls;
    b.proxy[s] = -1;
    b.groups[s] = 0;
    for (const auto& g : d.groups) b.groups[s] |= uint64_t(1) << groupIndex(g, true);
    b.kn[s] = d.kn, b.ks[s] = d.ks, b.fric[s] = d.fric;
    b.k_tran[s] = b.k_rot[s] = 0.0;
    // Before the broadphase sees it: pebbles of one clump never form a pair (makePair).
    b.clump[s] = clump;
    if (clump != kNoClump) ++m_bodies->pebble_count;

    uint32_t h;
    if (!m_bodies->free_handles.empty()) {
        h = m_bodies->free_handles.back();
        m_bodies->free_handles.pop_back();
        m_bodies->generation[h - 1] += 1;
    } else {
        m_bodies->slot_of.push_back(kDeadSlot);
        m_bodies->generation.push_back(1);
        h = static_cast<uint32_t>(m_bodies->slot_of.size());
    }
    m_bodies->slot_of[h - 1] = s;
    b.handle[s] = h;
    if (m_contacts->broadphase_ready) insertBall(s);
    return BallId{h, m_bodies->generation[h - 1]};
}

void Model::deleteBall(BallId id) {
    const uint32_t s = slotOf(id);
    if (m_bodies->balls.clump[s] != kNoClump)
        throw InputError("ball " + std::to_string(id.index) + " is a pebble of clump " +
                         std::to_string(m_bodies->balls.clump[s] + 1) +
                         ": delete or release the clump");
    removeBall(id, true);
}

void Model::removeBall(BallId id, bool book_energy) {
    m_limits_stale = true;
    const uint32_t s = slotOf(id);
    if (m_books.on && book_energy) {
        // The ball leaves the books with its kinetic energy at the present whole step, taken as
        // the next energy snapshot would take it (law_of_motion.cpp): the half-step velocity
        // plus half a step of the acceleration of the last force loop. Its contacts' stored
        // energy goes to `released` (removePair).
        const auto& b = m_bodies->balls;
        const double half = 0.5 * m_dt;
        const Vec2 v = b.vel[s] + ((b.force[s] + b.fapp[s]) * b.inv_mass[s] + m_gravity) * half;
        const double w = b.spin[s] + (b.moment[s] + b.mapp[s]) * b.inv_inertia[s] * half;
        const Vec2 vv = Vec2((b.fixity[s] & kFixX) ? b.vel[s].x() : v.x(),
                             (b.fixity[s] & kFixY) ? b.vel[s].y() : v.y());
        const double ww = (b.fixity[s] & kFixSpin) ? b.spin[s] : w;
        const double ke = 0.5 * (b.mass[s] * vv.squaredNorm() + b.inertia[s] * ww * ww);
        m_books.acc.deleted += ke;
        if (m_books.groups.on) bookDeletedToGroups(b.groups[s], ke);
    }
    if (m_books.groups.on) followRemovedSlot(s);
    // Drop the ball's pairs (highest index first so swap-removal keeps the rest valid).
    for (std::size_t i = m_contacts->pairs.size(); i-- > 0;) {
        const Pair& p = m_contacts->pairs[i];
        if (p.end1 == s || (!p.wall && p.end2 == s)) removePair(i);
    }
    auto& b = m_bodies->balls;
    if (b.fixity[s]) --m_fixed_balls;
    if (b.clump[s] != kNoClump) --m_bodies->pebble_count;
    if (b.proxy[s] >= 0) m_contacts->broadphase->destroy(b.proxy[s]);
    const uint32_t last = static_cast<uint32_t>(b.size() - 1);
    if (s != last) {
        b.move(s, last);
        m_bodies->slot_of[b.handle[s] - 1] = s;
        for (auto& p : m_contacts->pairs) {
            if (p.end1 == last) p.end1 = s;
            if (!p.wall && p.end2 == last) p.end2 = s;
        }
        ++m_contacts->pairs_version;
    }
    b.resize(last);
    if (m_contacts->ball_moved.size() > last) m_contacts->ball_moved.resize(last);
    m_bodies->slot_of[id.index - 1] = kDeadSlot;
    m_bodies->free_handles.push_back(id.index);
}

std::vector<BallId> Model::ballIds() const {
    std::vector<BallId> ids;
    ids.reserve(m_bodies->balls.size());
    for (uint32_t h = 1; h <= m_bodies->slot_of.size(); ++h)
        if (m_bodies->slot_of[h - 1] != kDeadSlot &&
            m_bodies->balls.clump[m_bodies->slot_of[h - 1]] == kNoClump)
            ids.push_back(BallId{h, m_bodies->generation[h - 1]});
    return ids;
}

Vec2 Model::ballPos(BallId id) const { return m_bodies->balls.pos[slotOf(id)]; }
Vec2 Model::ballVel(BallId id) const { return m_bodies->balls.vel[slotOf(id)]; }
double Model::ballSpin(BallId id) const { return m_bodies->balls.spin[slotOf(id)]; }
double Model::ballAngle(BallId id) const { return m_bodies->balls.angle[slotOf(id)]; }
double Model::ballRadius(BallId id) const { return m_bodies->balls.radius[slotOf(id)]; }
double Model::ballMass(BallId id) const { return m_bodies->balls.mass[slotOf(id)]; }
double Model::ballInertia(BallId id) const { return m_bodies->balls.inertia[slotOf(id)]; }
double Model::ballDensity(BallId id) const { return m_bodies->balls.density[slotOf(id)]; }
Vec2 Model::ballForce(BallId id) const { return m_bodies->balls.force[slotOf(id)]; }
double Model::ballMoment(BallId id) const { return m_bodies->balls.moment[slotOf(id)]; }
Vec2 Model::ballAppliedForce(BallId id) const { return m_bodies->balls.fapp[slotOf(id)]; }
double Model::ballAppliedMoment(BallId id) const { return m_bodies->balls.mapp[slotOf(id)]; }
uint8_t Model::ballFixity(BallId id) const { return m_bodies->balls.fixity[slotOf(id)]; }

static void requireFinite(const char* what, const Vec2& v) {
    if (!std::isfinite(v.x()) || !std::isfinite(v.y()))
        throw InputError(std::string("ball: ") + what + " must be finite");
}

void Model::setBallPos(BallId id, const Vec2& p) {
    m_limits_stale = true;
    requireCoordinate("ball: pos", p);
    const uint32_t s = slotOf(id);
    m_bodies->balls.pos[s] = p;
}
void Model::setBallVel(BallId id, const Vec2& v) {
    m_limits_stale = true;
    requireFinite("vel", v);
    const uint32_t s = slotOf(id);
    requireFiniteEnergy(m_bodies->balls.mass[s], 0.0, v, 0.0);
    m_bodies->balls.vel[s] = v;
}
void Model::setBallSpin(BallId id, double w) {
    m_limits_stale = true;
    if (!std::isfinite(w)) throw InputError("ball: spin must be finite");
    const uint32_t s = slotOf(id);
    requireFiniteEnergy(0.0, m_bodies->balls.inertia[s], Vec2::Zero(), w);
    m_bodies->balls.spin[s] = w;
}
void Model::setBallRadius(BallId id, double r) {
    m_limits_stale = true;
    requireRadius(r);
    const uint32_t s = slotOf(id);
    if (m_bodies->balls.density[s] > 0.0) {
        const double rho = m_bodies->balls.density[s];
        const double mass =
            rho * (m_mass_mode == MassMode::Disk ? M_PI * r * r : 4.0 / 3.0 * M_PI * r * r * r);
        requireUsableMass(mass, (m_mass_mode == MassMode::Disk ? 0.5 : 0.4) * mass * r * r,
                          "density " + messageNumber(rho) + " and radius " + messageNumber(r));
    }
    m_bodies->balls.radius[s] = r;
    if (m_bodies->balls.density[s] > 0.0) updateMass(s);
    refreshPairMasses(s);
}
void Model::setBallDensity(BallId id, double rho) {
    m_limits_stale = true;
    if (!(rho > 0.0) || !std::isfinite(rho))
        throw InputError("ball: density must be > 0 (got " + messageNumber(rho) + ")");
    const uint32_t s = slotOf(id);
    {
        const double r = m_bodies->balls.radius[s];
        const double mass =
            rho * (m_mass_mode == MassMode::Disk ? M_PI * r * r : 4.0 / 3.0 * M_PI * r * r * r);
        requireUsableMass(mass, (m_mass_mode == MassMode::Disk ? 0.5 : 0.4) * mass * r * r,
                          "density " + messageNumber(rho) + " and radius " + messageNumber(r));
    }
    m_bodies->balls.density[s] = rho;
    updateMass(s);
    refreshPairMasses(s);
}
void Model::setBallAppliedForce(BallId id, const Vec2& f) {
    requireFinite("fapp (applied force)", f);
    Vec2& fapp = m_bodies->balls.fapp[slotOf(id)];
    if (fapp != f) m_limits_stale = true;  // the approach rule's accelerations (timestep.cpp)
    fapp = f;
}
void Model::setBallAppliedMoment(BallId id, double m) {
    if (!std::isfinite(m))
        throw InputError("ball: mapp (applied moment) must be finite (got " + messageNumber(m) +
                         ")");
    m_bodies->balls.mapp[slotOf(id)] = m;
}
void Model::setBallFixity(BallId id, uint8_t f) {
    uint8_t& cur = m_bodies->balls.fixity[slotOf(id)];
    m_fixed_balls += (f != 0) - (cur != 0);
    cur = f;
}

static double& inheritableRef(std::vector<double>& kn, std::vector<double>& ks,
                              std::vector<double>& fric, uint32_t s, const std::string& name,
                              const char* owner) {
    const std::string n = lower(name);
    if (n == "kn") return kn[s];
    if (n == "ks") return ks[s];
    if (n == "fric") return fric[s];
    throw InputError(std::string(owner) + ": unknown contact property '" + name +
                     "' (inheritable: kn, ks, fric)");
}

double Model::ballContactProp(BallId id, const std::string& name) const {
    auto& b = m_bodies->balls;
    return inheritableRef(b.kn, b.ks, b.fric, slotOf(id), name, "ball");
}
void Model::setBallContactProp(BallId id, const std::string& name, double v) {
    if (!std::isnan(v) && !(v >= 0.0 && std::isfinite(v)))
        throw InputError("ball: " + name + " must be >= 0 (got " + messageNumber(v) + ")");
    auto& b = m_bodies->balls;
    inheritableRef(b.kn, b.ks, b.fric, slotOf(id), name, "ball") = v;
}

std::vector<std::string> Model::ballGroups(BallId id) const {
    std::vector<std::string> out;
    const uint64_t g = m_bodies->balls.groups[slotOf(id)];
    for (std::size_t i = 0; i < m_group_names.size(); ++i)
        if (g & (uint64_t(1) << i)) out.push_back(m_group_names[i]);
    return out;
}
void Model::addBallGroup(BallId id, const std::string& group) {
    const uint32_t s = slotOf(id);
    m_bodies->balls.groups[s] |= uint64_t(1) << groupIndex(group, true);
}

std::vector<std::string> Model::wallGroups(WallId id) const {
    std::vector<std::string> out;
    const uint64_t g = wallOf(id).groups;
    for (std::size_t i = 0; i < m_group_names.size(); ++i)
        if (g & (uint64_t(1) << i)) out.push_back(m_group_names[i]);
    return out;
}
void Model::addWallGroup(WallId id, const std::string& group) {
    WallData& w = wallOf(id);
    w.groups |= uint64_t(1) << groupIndex(group, true);
}

// ------------------------------------------------------------------------ walls

WallId Model::createWall(const WallDef& d) {
    m_limits_stale = true;
    const std::size_t n = d.points.size();
    if (n < 2) throw InputError("wall: needs at least 2 points (got " + std::to_string(n) + ")");
    if (d.closed && n < 3) throw InputError("wall: a closed wall needs at least 3 points");
    for (std::size_t i = 0; i < n; ++i) {
        const Vec2& p = d.points[i];
        if (!std::isfinite(p.x()) || !std::isfinite(p.y()))
            throw InputError("wall: point " + std::to_string(i + 1) + " is not finite");
        requireCoordinate("wall: point " + std::to_string(i + 1), p);
        const std::size_t j = (i + 1) % n;
        if ((i + 1 < n || d.closed) && (d.points[j] - p).norm() <= 0.0)
            throw InputError("wall: points " + std::to_string(i + 1) + " and " +
                             std::to_string(j + 1) + " coincide (zero-length segment)");
    }
    if (!std::isfinite(d.vel.x()) || !std::isfinite(d.vel.y()) || !std::isfinite(d.spin))
        throw InputError("wall: vel and spin must be finite");
    if (!std::isnan(d.center.x()) || !std::isnan(d.center.y()))
        requireCoordinate("wall: center", d.center);
    for (double v : {d.kn, d.ks, d.fric})
        if (!std::isnan(v) && !(v >= 0.0 && std::isfinite(v)))
            throw InputError("wall: kn, ks and fric must be >= 0 (got " + messageNumber(v) + ")");

    WallData w;
    w.closed = d.closed;
    w.first_vertex = static_cast<uint32_t>(m_bodies->vertices.size());
    w.vertex_count = static_cast<uint32_t>(n);
    Vec2 centroid = Vec2::Zero();
    for (const auto& p : d.points) {
        m_bodies->vertices.push_back(p);
        centroid += p;
    }
    centroid /= static_cast<double>(n);
    w.center = std::isnan(d.center.x()) ? centroid : d.center;
    w.vel = d.vel;
    w.spin = d.spin;
    for (const auto& g : d.groups) w.groups |= uint64_t(1) << groupIndex(g, true);
    w.kn = d.kn, w.ks = d.ks, w.fric = d.fric;
    const uint32_t wall_index = static_cast<uint32_t>(m_bodies->walls.size());
    const std::size_t nseg = d.closed ? n : n - 1;
    w.first_segment = static_cast<uint32_t>(m_bodies->segments.size());
    w.segment_count = static_cast<uint32_t>(nseg);
    for (std::size_t i = 0; i < nseg; ++i) {
        Segment s;
        s.wall = wall_index;
        s.a = w.first_vertex + static_cast<uint32_t>(i);
        s.b = w.first_vertex + static_cast<uint32_t>((i + 1) % n);
        const int32_t first = static_cast<int32_t>(w.first_segment);
        const int32_t k = static_cast<int32_t>(i), ns = static_cast<int32_t>(nseg);
        s.prev = (i > 0) ? first + k - 1 : (d.closed ? first + ns - 1 : -1);
        s.next = (i + 1 < nseg) ? first + k + 1 : (d.closed ? first : -1);
        m_bodies->segments.push_back(s);
    }
    m_bodies->walls.push_back(w);
    if (m_contacts->broadphase_ready)
        for (uint32_t i = 0; i < nseg; ++i) insertSegment(w.first_segment + i);
    return WallId{wall_index + 1, m_bodies->walls.back().generation};
}

std::size_t Model::wallCount() const { return m_bodies->walls.size(); }

const Model::WallData& Model::wallOf(WallId id) const { return m_bodies->wallOf(id); }
Model::WallData& Model::wallOf(WallId id) { return m_bodies->wallOf(id); }

std::vector<WallId> Model::wallIds() const {
    std::vector<WallId> ids;
    for (std::size_t i = 0; i < m_bodies->walls.size(); ++i)
        if (m_bodies->walls[i].alive)
            ids.push_back(WallId{static_cast<uint32_t>(i + 1), m_bodies->walls[i].generation});
    return ids;
}

std::vector<Vec2> Model::wallPoints(WallId id) const {
    const WallData& w = wallOf(id);
    return std::vector<Vec2>(m_bodies->vertices.begin() + w.first_vertex,
                             m_bodies->vertices.begin() + w.first_vertex + w.vertex_count);
}
bool Model::wallClosed(WallId id) const { return wallOf(id).closed; }
Vec2 Model::wallVel(WallId id) const { return wallOf(id).vel; }
void Model::setWallVel(WallId id, const Vec2& v) {
    m_limits_stale = true;
    if (!std::isfinite(v.x()) || !std::isfinite(v.y()))
        throw InputError("wall: vel must be finite");
    wallOf(id).vel = v;
}
double Model::wallSpin(WallId id) const { return wallOf(id).spin; }
void Model::setWallSpin(WallId id, double w) {
    m_limits_stale = true;
    if (!std::isfinite(w)) throw InputError("wall: spin must be finite");
    wallOf(id).spin = w;
}
Vec2 Model::wallCenter(WallId id) const { return wallOf(id).center; }
void Model::setWallCenter(WallId id, const Vec2& c) {
    requireCoordinate("wall: center", c);
    wallOf(id).center = c;
}
Vec2 Model::wallForce(WallId id) const { return wallOf(id).force; }

double Model::wallContactProp(WallId id, const std::string& name) const {
    const WallData& w = wallOf(id);
    const std::string n = lower(name);
    if (n == "kn") return w.kn;
    if (n == "ks") return w.ks;
    if (n == "fric") return w.fric;
    throw InputError("wall: unknown contact property '" + name + "' (inheritable: kn, ks, fric)");
}
void Model::setWallContactProp(WallId id, const std::string& name, double v) {
    if (!std::isnan(v) && !(v >= 0.0 && std::isfinite(v)))
        throw InputError("wall: " + name + " must be >= 0 (got " + messageNumber(v) + ")");
    WallData& w = wallOf(id);
    const std::string n = lower(name);
    if (n == "kn")
        w.kn = v;
    else if (n == "ks")
        w.ks = v;
    else if (n == "fric")
        w.fric = v;
    else
        throw InputError("wall: unknown contact property '" + name +
                         "' (inheritable: kn, ks, fric)");
}

}  // namespace talus
