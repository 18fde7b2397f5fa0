// SPDX-License-Identifier: MIT
//
// Model: bodies, contact-model rules, queries, and the cycle driver. The phases themselves are in
// timestep.cpp, law_of_motion.cpp, contact_detection.cpp, force_displacement.cpp and
// bookkeeping.cpp.
#include "talus/model.hpp"

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

namespace talus {

namespace {

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string fmt(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
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
                         fmt(kMaxCoordinate) + " m of the origin");
}

void requireRadius(double r) {
    if (!(r > 0.0) || !std::isfinite(r))
        throw InputError("ball: radius must be > 0 (got " + fmt(r) + ")");
    if (r < kMinRadius || r > kMaxCoordinate)
        throw InputError("ball: radius " + fmt(r) + " m is out of range [" + fmt(kMinRadius) +
                         ", " + fmt(kMaxCoordinate) + "] m");
}

/// The kinetic energy a velocity or spin gives must be finite: vel or spin = 1e300 made the
/// energy totals infinite and balance_error -inf.
void requireFiniteEnergy(double mass, double inertia, const Vec2& vel, double spin) {
    if (!std::isfinite(0.5 * mass * vel.squaredNorm()))
        throw InputError("ball: vel " + vecText(vel) + " gives a ball of " + fmt(mass) +
                         " kg an infinite kinetic energy");
    if (!std::isfinite(0.5 * inertia * spin * spin))
        throw InputError("ball: spin " + fmt(spin) + " gives a ball of inertia " + fmt(inertia) +
                         " kg m^2 an infinite kinetic energy");
}

/// Mass and inertia of a disk or sphere; throws when either (or its inverse) is not a finite
/// positive number (a huge radius or density overflows, a tiny one underflows).
void requireUsableMass(double mass, double inertia, const std::string& from) {
    auto usable = [](double v) { return v > 0.0 && std::isfinite(v) && std::isfinite(1.0 / v); };
    if (!usable(mass))
        throw InputError("ball: " + from + " give a mass of " + fmt(mass) +
                         " kg, which is not a usable positive number");
    if (!usable(inertia))
        throw InputError("ball: " + from + " give a moment of inertia of " + fmt(inertia) +
                         " kg m^2, which is not a usable positive number");
}

using Clock = std::chrono::steady_clock;

}  // namespace

const char* stepRuleName(StepRule r) {
    switch (r) {
        case StepRule::Fixed:
            return "fixed";
        case StepRule::Stability:
            return "stability";
        case StepRule::Resolution:
            return "resolution";
        case StepRule::Approach:
            return "approach";
        case StepRule::Kinematic:
            return "kinematic";
        case StepRule::Max:
            return "max";
        case StepRule::Growth:
            return "growth";
        case StepRule::Idle:
            return "idle";
        case StepRule::Damping:
            return "damping";
    }
    return "?";
}

std::string vecText(const Vec2& v) { return "(" + fmt(v.x()) + ", " + fmt(v.y()) + ")"; }

std::string messageNumber(double v, int digits) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

// ------------------------------------------------------------------------ small containers

// ------------------------------------------------------------------------ construction

Model::Model(const ModelDef& def, PluginRegistry& registry)
    : m_bodies(std::make_unique<BodyStore>()),
      m_contacts(std::make_unique<ContactStore>()),
      m_registry(registry),
      m_gravity(def.gravity),
      m_mass_mode(def.mass_mode) {
    if (!std::isfinite(def.gravity.x()) || !std::isfinite(def.gravity.y()))
        throw InputError("model: gravity must be finite");
    // Rule 0 is the default; until set it is "none" (no contacts are created).
    auto none = std::make_unique<Rule>();
    none->model_name = "";
    m_contacts->rules.push_back(std::move(none));
    m_fd_template.size = sizeof(FdBlock);
    m_fd_template.version = TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR;
    m_warning_handler = [](const std::string& w) { std::cerr << "warning: " << w << "\n"; };
}

Model::~Model() {
    for (auto& p : m_contacts->pairs) {
        if (p.model) {
            p.model->Destroy();
            p.rule->pool->release(p.model);
        }
    }
}

int Model::groupIndex(const std::string& name, bool create) {
    for (std::size_t i = 0; i < m_group_names.size(); ++i)
        if (m_group_names[i] == name) return static_cast<int>(i);
    if (!create) return -1;
    if (m_group_names.size() >= 64)
        throw InputError("group '" + name + "': a model holds at most 64 group names");
    m_group_names.push_back(name);
    return static_cast<int>(m_group_names.size() - 1);
}

const Model::BallArrays& Model::balls() const { return m_bodies->balls; }
double Model::broadphaseMargin() const { return m_contacts->margin; }

// ------------------------------------------------------------------------ balls

uint32_t Model::slotOf(BallId id) const { return m_bodies->slotOf(id); }
bool Model::isAlive(BallId id) const { return m_bodies->isAlive(id); }
std::string Model::describeBall(uint32_t slot) const { return m_bodies->describeBall(slot); }

std::size_t Model::ballCount() const { return m_bodies->balls.size(); }

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

BallId Model::createBall(const BallDef& d) {
    m_limits_stale = true;
    auto finite2 = [](const Vec2& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); };
    requireRadius(d.radius);
    const bool has_mass = !std::isnan(d.mass);
    if (has_mass && !(d.mass > 0.0 && std::isfinite(d.mass)))
        throw InputError("ball: mass must be > 0 (got " + fmt(d.mass) + ")");
    if (!has_mass && !(d.density > 0.0 && std::isfinite(d.density)))
        throw InputError("ball: density must be > 0 (got " + fmt(d.density) + ")");
    if (!std::isnan(d.inertia) && !(d.inertia > 0.0 && std::isfinite(d.inertia)))
        throw InputError("ball: inertia must be > 0 (got " + fmt(d.inertia) + ")");
    requireCoordinate("ball: pos", d.pos);
    if (!finite2(d.vel)) throw InputError("ball: vel must be finite");
    if (!std::isfinite(d.spin) || !std::isfinite(d.angle))
        throw InputError("ball: spin and angle must be finite");
    for (double v : {d.kn, d.ks, d.fric})
        if (!std::isnan(v) && !(v >= 0.0 && std::isfinite(v)))
            throw InputError("ball: kn, ks and fric must be >= 0 (got " + fmt(v) + ")");
    {
        // The derived values, before anything is stored.
        const double r = d.radius;
        const bool disk = m_mass_mode == MassMode::Disk;
        const double volume = disk ? M_PI * r * r : 4.0 / 3.0 * M_PI * r * r * r;
        const double mass = has_mass ? d.mass : d.density * volume;
        const double inertia =
            !std::isnan(d.inertia) ? d.inertia : (disk ? 0.5 : 0.4) * mass * r * r;
        requireUsableMass(mass, inertia,
                          has_mass ? "mass " + fmt(d.mass) + " and radius " + fmt(r)
                                   : "density " + fmt(d.density) + " and radius " + fmt(r));
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
    m_limits_stale = true;
    const uint32_t s = slotOf(id);
    if (m_energy_on) {
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
        m_energy_acc.deleted += 0.5 * (b.mass[s] * vv.squaredNorm() + b.inertia[s] * ww * ww);
    }
    // Drop the ball's pairs (highest index first so swap-removal keeps the rest valid).
    for (std::size_t i = m_contacts->pairs.size(); i-- > 0;) {
        const Pair& p = m_contacts->pairs[i];
        if (p.end1 == s || (!p.wall && p.end2 == s)) removePair(i);
    }
    auto& b = m_bodies->balls;
    if (b.fixity[s]) --m_fixed_balls;
    if (b.proxy[s] >= 0) m_contacts->broadphase->destroy(b.proxy[s]);
    const uint32_t last = static_cast<uint32_t>(b.size() - 1);
    if (s != last) {
        b.move(s, last);
        m_bodies->slot_of[b.handle[s] - 1] = s;
        for (auto& p : m_contacts->pairs) {
            if (p.end1 == last) p.end1 = s;
            if (!p.wall && p.end2 == last) p.end2 = s;
        }
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
        if (m_bodies->slot_of[h - 1] != kDeadSlot)
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
                          "density " + fmt(rho) + " and radius " + fmt(r));
    }
    m_bodies->balls.radius[s] = r;
    if (m_bodies->balls.density[s] > 0.0) updateMass(s);
    refreshPairMasses(s);
}
void Model::setBallDensity(BallId id, double rho) {
    m_limits_stale = true;
    if (!(rho > 0.0) || !std::isfinite(rho))
        throw InputError("ball: density must be > 0 (got " + fmt(rho) + ")");
    const uint32_t s = slotOf(id);
    {
        const double r = m_bodies->balls.radius[s];
        const double mass =
            rho * (m_mass_mode == MassMode::Disk ? M_PI * r * r : 4.0 / 3.0 * M_PI * r * r * r);
        requireUsableMass(mass, (m_mass_mode == MassMode::Disk ? 0.5 : 0.4) * mass * r * r,
                          "density " + fmt(rho) + " and radius " + fmt(r));
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
        throw InputError("ball: mapp (applied moment) must be finite (got " + fmt(m) + ")");
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
        throw InputError("ball: " + name + " must be >= 0 (got " + fmt(v) + ")");
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
            throw InputError("wall: kn, ks and fric must be >= 0 (got " + fmt(v) + ")");

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
        throw InputError("wall: " + name + " must be >= 0 (got " + fmt(v) + ")");
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

// ------------------------------------------------------------------------ contact-model rules

const ModelFactory& Model::contactModelFactory(const std::string& name) {
    return m_registry.find(name);
}

void Model::setDefaultContactModel(const std::string& name, const std::vector<PropValue>& props) {
    addContactModelRule(name, props, "", "");
}

void Model::addContactModelRule(const std::string& name, const std::vector<PropValue>& props,
                                const std::string& group_a, const std::string& group_b) {
    auto rule = std::make_unique<Rule>();
    rule->factory = &m_registry.find(name);
    rule->model_name = rule->factory->name;
    rule->prototype = m_registry.createPrototype(*rule->factory);
    applyProps(*rule->prototype, props, "contact_model");
    PropBlock pb = emptyPropBlock();
    if (const char* err = rule->prototype->PreCycle(pb))
        throw InputError(std::string("contact_model '") + rule->model_name + "': " + err);
    rule->group_a = group_a.empty() ? -1 : groupIndex(group_a, true);
    rule->group_b = group_b.empty() ? -1 : groupIndex(group_b, true);
    rule->specificity = (rule->group_a >= 0) + (rule->group_b >= 0);
    rule->order = static_cast<int>(m_contacts->rules.size());
    rule->activity = rule->prototype->ActivityDistance();
    rule->pool = std::make_unique<ObjectPool>(rule->prototype->ObjectSize());
    if (rule->specificity == 0) {
        // A new default replaces the old one for future contacts; the old rule stays alive
        // (existing contacts hold objects from its pool) but is no longer matched.
        m_contacts->rules.push_back(std::move(m_contacts->rules[0]));
        m_contacts->rules[0] = std::move(rule);
    } else {
        m_contacts->rules.push_back(std::move(rule));
    }
    // Pairs that are not in contact pick the new rules up when they touch.
    ++m_contacts->rules_version;
    m_limits_stale = true;
    m_contacts->max_activity = 0.0;
    for (const auto& r : m_contacts->rules)
        if (r->prototype)
            m_contacts->max_activity = std::max(m_contacts->max_activity, r->activity);
}

const Model::Rule& Model::ruleFor(uint64_t g1, uint64_t g2) const {
    const Rule* best = m_contacts->rules[0].get();
    int best_spec = -1, best_order = -1;
    auto in = [](uint64_t g, int idx) { return idx < 0 || (g & (uint64_t(1) << idx)) != 0; };
    for (std::size_t i = 1; i < m_contacts->rules.size(); ++i) {
        const Rule& r = *m_contacts->rules[i];
        if (r.specificity == 0 || !r.prototype) continue;  // retired defaults
        const bool match =
            (in(g1, r.group_a) && in(g2, r.group_b)) || (in(g2, r.group_a) && in(g1, r.group_b));
        if (match &&
            (r.specificity > best_spec || (r.specificity == best_spec && r.order > best_order))) {
            best = &r;
            best_spec = r.specificity;
            best_order = r.order;
        }
    }
    return *best;
}

// ------------------------------------------------------------------------ contacts (queries)

Model::Pair* Model::pairByKey(ContactKey key) { return m_contacts->pairByKey(key); }
const Model::Pair* Model::pairByKey(ContactKey key) const { return m_contacts->pairByKey(key); }
std::size_t Model::pairIndex(const Pair& p) const { return m_contacts->pairIndex(p); }

bool Model::pairGeometry(const Pair& p, Vec2& normal, double& overlap, Vec2& point) const {
    const auto& b = m_bodies->balls;
    const Vec2& x1 = b.pos[p.end1];
    ContactGeometry g;
    if (p.wall) {
        if (!segmentGeometry(p.end2, x1, b.radius[p.end1], g)) return false;
    } else {
        const Vec2 d = b.pos[p.end2] - x1;
        const double dist = d.norm();
        g.normal = dist > 0.0 ? Vec2(d / dist) : Vec2(0.0, 1.0);
        g.overlap = b.radius[p.end1] + b.radius[p.end2] - dist;
        g.point = x1 + (b.radius[p.end1] - 0.5 * g.overlap) * g.normal;
    }
    normal = g.normal;
    overlap = g.overlap;
    point = g.point;
    return true;
}

ContactInfo Model::infoOf(std::size_t index) const {
    const Pair& p = m_contacts->pairs[index];
    ContactInfo c;
    c.key = ContactKey{m_contacts->cold[index].key};
    const uint32_t h1 = m_bodies->balls.handle[p.end1];
    c.ball1 = BallId{h1, m_bodies->generation[h1 - 1]};
    if (p.wall) {
        const Segment& s = m_bodies->segments[p.end2];
        c.wall = WallId{s.wall + 1, m_bodies->walls[s.wall].generation};
        c.segment = static_cast<int32_t>(p.end2 - m_bodies->walls[s.wall].first_segment);
    } else {
        const uint32_t h2 = m_bodies->balls.handle[p.end2];
        c.ball2 = BallId{h2, m_bodies->generation[h2 - 1]};
    }
    c.active = p.active;
    pairGeometry(p, c.normal, c.overlap, c.point);
    c.normal_force = p.n_force;
    c.shear_force = p.s_force;
    c.moment = p.moment;
    c.sliding = p.sliding;
    c.bonded = p.bonded;
    c.model = p.rule ? p.rule->model_name : "";
    return c;
}

std::string Model::describePair(const Pair& p) const {
    std::string s = "contact ball " + std::to_string(m_bodies->balls.handle[p.end1]) + " - ";
    if (p.wall) {
        const Segment& seg = m_bodies->segments[p.end2];
        s += "wall " + std::to_string(seg.wall + 1) + " segment " +
             std::to_string(p.end2 - m_bodies->walls[seg.wall].first_segment + 1);
    } else {
        s += "ball " + std::to_string(m_bodies->balls.handle[p.end2]);
    }
    s += " (model '" + (p.rule ? p.rule->model_name : std::string("?")) + "')";
    Vec2 n, point;
    double overlap;
    if (pairGeometry(p, n, overlap, point)) s += " at " + vecText(point);
    return s;
}

std::size_t Model::contactCount(bool active_only) const {
    if (!active_only) return m_contacts->pairs.size();
    std::size_t n = 0;
    for (const auto& p : m_contacts->pairs) n += p.active;
    return n;
}

std::vector<ContactInfo> Model::contacts(bool active_only) const {
    std::vector<ContactInfo> out;
    for (std::size_t i = 0; i < m_contacts->pairs.size(); ++i)
        if (m_contacts->pairs[i].active || !active_only) out.push_back(infoOf(i));
    return out;
}

bool Model::findContact(ContactKey key, ContactInfo& out) const {
    const Pair* p = pairByKey(key);
    if (!p) return false;
    out = infoOf(pairIndex(*p));
    return true;
}

double Model::contactProp(ContactKey key, const std::string& name) const {
    const Pair* p = pairByKey(key);
    if (!p || !p->model) throw InputError("contact no longer exists");
    const int32_t idx = propIndex(*p->model, name);
    if (idx < 0)
        throw InputError("contact: unknown property '" + name + "' for model '" + p->model->Name() +
                         "' (known: " + knownProps(*p->model) + ")");
    return p->model->ReturnProp(idx);
}

void Model::setContactProp(ContactKey key, const std::string& name, double value) {
    m_limits_stale = true;
    Pair* p = pairByKey(key);
    if (!p || !p->model) throw InputError("contact no longer exists");
    const int32_t idx = propIndex(*p->model, name);
    if (idx < 0)
        throw InputError("contact: unknown property '" + name + "' for model '" + p->model->Name() +
                         "' (known: " + knownProps(*p->model) + ")");
    if (const std::string why = propValueProblem(*p->model, idx, value); !why.empty())
        throw InputError(std::string("contact: ") + p->model->Name() + ": '" + name + "' " + why);
    if (p->model->AcceptProp(idx, value) != 0)
        throw InputError(std::string("contact: ") + p->model->LastError());
    // A stiffness set to zero on a live contact: the bodies may pass through each other.
    const PropInfo* info = p->model->PropInfoAt(idx);
    const std::string units = info && info->units ? info->units : "";
    if (value == 0.0 && (units == "N/m" || units == "Pa"))
        warn("contact " + describePair(*p) + ": property '" + name + "' of model '" +
             p->model->Name() + "' set to 0: the contact may let the bodies pass through");
}

void Model::setContactForce(ContactKey key, double normal_force, double shear_force) {
    Pair* p = pairByKey(key);
    if (!p) throw InputError("contact no longer exists");
    if (!std::isfinite(normal_force) || !std::isfinite(shear_force))
        throw InputError("contact: normal_force and shear_force must be finite (got " +
                         fmt(normal_force) + ", " + fmt(shear_force) + ")");
    p->n_force = normal_force;
    p->s_force = shear_force;
}

// ------------------------------------------------------------------------ the cycle

void Model::prepareRun() {
    if (!m_contacts->broadphase_ready) initBroadphase();
    const TimestepSettings& t = m_timestep;
    if (t.automatic != m_last_settings.automatic || t.safety != m_last_settings.safety ||
        t.resolution != m_last_settings.resolution)
        m_limits_stale = true;
    m_last_settings = t;
    for (auto& r : m_contacts->rules)
        if (r->prototype) {
            PropBlock pb = emptyPropBlock();
            if (const char* err = r->prototype->PreCycle(pb))
                throw InputError("contact model '" + r->model_name + "': " + err);
        }
    if (!m_contacts->rules[0]->prototype && m_contacts->rules.size() == 1 && ballCount() > 0 &&
        !m_warned_no_model) {
        m_warned_no_model = true;
        warn("no contact model is set (contact_model{...}): bodies will pass through each other");
    }
}

void Model::runSteps(int64_t steps) {
    using std::chrono::duration;
    const bool prof = m_profile.enabled;
    for (int64_t i = 0; i < steps; ++i) {
        // The PFC cycle (seed digest section 1), each phase timed into m_profile.
        Clock::time_point t0, t1;
        if (prof) t0 = Clock::now();
        computeTimestep();
        if (prof)
            t1 = Clock::now(), m_profile.timestep += duration<double>(t1 - t0).count(), t0 = t1;
        lawOfMotion();
        moveWalls();
        if (prof) t1 = Clock::now(), m_profile.motion += duration<double>(t1 - t0).count(), t0 = t1;
        detectContacts();
        if (prof)
            t1 = Clock::now(), m_profile.detection += duration<double>(t1 - t0).count(), t0 = t1;
        forceDisplacement();
        if (prof)
            t1 = Clock::now(), m_profile.force_displacement += duration<double>(t1 - t0).count(),
            t0 = t1;
        bookkeeping();
        if (prof) t1 = Clock::now(), m_profile.bookkeeping += duration<double>(t1 - t0).count();
        ++m_profile.cycles;
    }
}

void Model::cycle(int64_t steps) {
    if (steps < 0) throw InputError("cycle: number of steps must be >= 0");
    prepareRun();
    try {
        runSteps(steps);
    } catch (...) {
        flushWarnings();
        throw;
    }
    flushWarnings();
}

void Model::solveTime(double duration) {
    if (!(duration >= 0.0) || !std::isfinite(duration))
        throw InputError("solve: time must be >= 0 (got " + fmt(duration) + ")");
    // A duration no run can reach is refused rather than cycled for ever with no sign of life
    // (issue 6, item 12): beyond 1e9 s (32 years), and beyond 1e12 steps at a fixed step.
    if (duration > 1e9)
        throw InputError("solve: time " + fmt(duration) +
                         " s cannot be reached in a sane number of steps (at most 1e9 s per "
                         "solve; call solve repeatedly for longer runs)");
    if (!m_timestep.automatic && m_timestep.fixed > 0.0 && duration / m_timestep.fixed > 1e12)
        throw InputError("solve: time " + fmt(duration) + " s needs " +
                         fmt(duration / m_timestep.fixed) + " steps of the fixed step " +
                         fmt(m_timestep.fixed) + " s (more than 1e12)");
    prepareRun();
    const double end = m_time + duration;
    try {
        // Land exactly on `end`: cap each step by the time left.
        while (end - m_time > 1e-12 * std::max(1.0, std::fabs(end))) {
            m_step_cap = end - m_time;
            runSteps(1);
        }
    } catch (...) {
        m_step_cap = 0.0;
        flushWarnings();
        throw;
    }
    m_step_cap = 0.0;
    flushWarnings();
}

std::string Model::lastStepReason() const {
    std::string s = std::string(stepRuleName(m_dt_rule)) + " rule, dt = " + fmt(m_dt) + " s";
    std::string where;
    switch (m_dt_where.kind) {
        case StepWhere::Ball:
            if (m_dt_where.index < ballCount()) where = describeBall(m_dt_where.index);
            break;
        case StepWhere::Pair:
            if (const Pair* p = pairByKey(ContactKey{m_dt_where.key})) where = describePair(*p);
            break;
        case StepWhere::Wall:
            where = "wall " + std::to_string(m_dt_where.index + 1);
            break;
        case StepWhere::None:
            break;
    }
    if (!where.empty()) s += " (" + where + ")";
    return s;
}

void Model::warn(const std::string& text) {
    if (m_warning_handler) m_warning_handler(text);
}

void Model::throwNonFinite(const std::string& what) const {
    throw NumericalError("non-finite state at step " + std::to_string(m_step) +
                         " (t = " + fmt(m_time) + " s): " + what);
}

}  // namespace talus
