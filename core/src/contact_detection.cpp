// SPDX-License-Identifier: MIT
//
// Phase 3: contact detection, broadphase part (docs/architecture.md).
//
// One b2DynamicTree proxy per ball and per wall segment (broadphase.hpp). A body is re-inserted
// only when it has less than one margin of room left in its fat box, and only re-inserted
// bodies are queried for new pairs, so a settled packing does almost no broadphase work.
// A pair lives while the fat boxes of its ends overlap; the narrowphase (is it touching?) runs
// in the force loop (force_displacement.cpp), which is where the pair's data is hot anyway.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <unordered_map>

#include "body_store.hpp"
#include "broadphase.hpp"
#include "contact_store.hpp"
#include "model_internal.hpp"
#include "narrowphase.hpp"
#include "talus/errors.hpp"

namespace talus {

namespace {

Box grow(const Box& b, double d) {
    Box g = b;
    g.lo.array() -= d;
    g.hi.array() += d;
    return g;
}

}  // namespace

Box Model::ballBox(uint32_t s) const {
    const double r = m_bodies->balls.radius[s] + 0.5 * m_contacts->max_activity;
    const Vec2& p = m_bodies->balls.pos[s];
    return Box{Vec2(p.x() - r, p.y() - r), Vec2(p.x() + r, p.y() + r)};
}

Box Model::segmentBox(uint32_t seg) const {
    const Vec2& a = m_bodies->vertices[m_bodies->segments[seg].a];
    const Vec2& b = m_bodies->vertices[m_bodies->segments[seg].b];
    const double h = 0.5 * m_contacts->max_activity;
    return Box{Vec2(std::min(a.x(), b.x()) - h, std::min(a.y(), b.y()) - h),
               Vec2(std::max(a.x(), b.x()) + h, std::max(a.y(), b.y()) + h)};
}

bool Model::segmentGeometry(uint32_t seg, const Vec2& c, double r, ContactGeometry& g) const {
    const Segment& sg = m_bodies->segments[seg];
    const Vec2* before =
        sg.prev >= 0 ? &m_bodies->vertices[m_bodies->segments[sg.prev].a] : nullptr;
    const Vec2* after = sg.next >= 0 ? &m_bodies->vertices[m_bodies->segments[sg.next].b] : nullptr;
    return ballSegmentGeometry(c, r, m_bodies->vertices[sg.a], m_bodies->vertices[sg.b], before,
                               after, g);
}

int32_t Model::wallHolder(uint32_t seg, const Vec2& c, double r) const {
    // A segment gives up a ball only beyond one of its ends, at a convex vertex
    // (narrowphase.hpp), so the holder lies that way along the chain; a fast ball or short
    // segments may put it more than one segment away. The walk cannot turn back (the segment
    // beyond a convex vertex gives the ball back only on this side of it, where this one holds
    // it), and a closed chain is walked at most once round.
    const uint32_t n = m_bodies->walls[m_bodies->segments[seg].wall].segment_count;
    ContactGeometry g;
    int32_t cur = static_cast<int32_t>(seg);
    for (uint32_t k = 0; k < n; ++k) {
        const Segment& sg = m_bodies->segments[static_cast<uint32_t>(cur)];
        const Vec2 ab = m_bodies->vertices[sg.b] - m_bodies->vertices[sg.a];
        const double t = (c - m_bodies->vertices[sg.a]).dot(ab) / ab.squaredNorm();
        cur = t <= 0.0 ? sg.prev : (t >= 1.0 ? sg.next : -1);
        if (cur < 0) return -1;
        if (segmentGeometry(static_cast<uint32_t>(cur), c, r, g)) return cur;
    }
    return -1;
}

void Model::setBroadphaseMargin(double margin) {
    // The float broadphase tree works in units of margin / 0.1: a subnormal margin (1e-320)
    // made them infinite and no contact was ever found (issue 6, item 12). Below 1e-9 m the
    // margin is under a double's resolution of coordinates of 1e7 m, and the kinematic rule
    // (no body leaves its fat box in a step) stalls the step. 0 = automatic.
    if (!(margin >= 0.0) || !std::isfinite(margin) || (margin > 0.0 && margin < 1e-9) ||
        margin > 1e9) {
        char got[32];
        std::snprintf(got, sizeof got, "%g", margin);
        throw InputError(
            std::string("broadphase: margin must be 0 (automatic) or in [1e-9, 1e9] m (got ") +
            got + ")");
    }
    m_contacts->margin = margin;
    if (m_contacts->broadphase_ready) {
        // Rebuild with the new margin; existing pairs are kept (makePair finds them), and pairs
        // whose fat boxes no longer overlap are dropped at the next step.
        m_contacts->broadphase_ready = false;
        initBroadphase();
        std::fill(m_contacts->ball_moved.begin(), m_contacts->ball_moved.end(), 1);
        std::fill(m_contacts->segment_moved.begin(), m_contacts->segment_moved.end(), 1);
        for (uint32_t s = 0; s < m_contacts->ball_moved.size(); ++s)
            m_contacts->moved_balls.push_back(s);
        for (uint32_t g = 0; g < m_contacts->segment_moved.size(); ++g)
            m_contacts->moved_segments.push_back(g);
    }
}

void Model::initBroadphase() {
    auto& b = m_bodies->balls;
    if (!(m_contacts->margin > 0.0)) {
        double mean = 0.0;
        for (double r : b.radius) mean += r;
        mean = b.size() ? mean / static_cast<double>(b.size()) : 0.0;
        if (mean <= 0.0) {
            // Only walls: take 1% of the walls' extent.
            Box all{Vec2(1e300, 1e300), Vec2(-1e300, -1e300)};
            for (const Vec2& v : m_bodies->vertices)
                all.lo = all.lo.cwiseMin(v), all.hi = all.hi.cwiseMax(v);
            mean =
                m_bodies->vertices.empty() ? 1.0 : std::max(0.01 * (all.hi - all.lo).norm(), 1e-6);
        }
        m_contacts->margin = 0.05 * mean;
    }
    m_contacts->broadphase->reset(m_contacts->margin);
    m_contacts->wall_broadphase->reset(m_contacts->margin);
    m_contacts->broadphase_ready = true;
    for (std::size_t i = 0; i < m_bodies->segments.size(); ++i) {
        m_bodies->segments[i].proxy = -1;
        if (!m_bodies->walls[m_bodies->segments[i].wall].alive) continue;
        const auto seg = static_cast<uint32_t>(i);
        m_bodies->segments[i].proxy =
            m_contacts->wall_broadphase->create(grow(segmentBox(seg), m_contacts->margin), seg);
        m_bodies->segments[i].fat =
            m_contacts->wall_broadphase->fatBox(m_bodies->segments[i].proxy);
    }
    for (std::size_t s = 0; s < b.size(); ++s) {
        b.proxy[s] = m_contacts->broadphase->create(
            grow(ballBox(static_cast<uint32_t>(s)), m_contacts->margin), b.handle[s]);
        b.fat[s] = m_contacts->broadphase->fatBox(b.proxy[s]);
    }
    for (std::size_t s = 0; s < b.size(); ++s) addPairsForBall(static_cast<uint32_t>(s));
    m_contacts->ball_moved.assign(b.size(), 0);
    m_contacts->segment_moved.assign(m_bodies->segments.size(), 0);
}

void Model::rebuildBallTree() {
    // The tree's quality depends on the order of insertion; after the balls were sorted along a
    // Morton curve, inserting them in that order gives a spatially coherent tree (a query costs
    // about ten times less than in a tree built in random order, docs/benchmarks.md).
    auto& b = m_bodies->balls;
    m_contacts->broadphase->reset(m_contacts->margin);
    for (std::size_t s = 0; s < b.size(); ++s) {
        b.proxy[s] = m_contacts->broadphase->create(
            grow(ballBox(static_cast<uint32_t>(s)), m_contacts->margin), b.handle[s]);
        b.fat[s] = m_contacts->broadphase->fatBox(b.proxy[s]);
    }
}

void Model::insertBall(uint32_t s) {
    auto& b = m_bodies->balls;
    b.proxy[s] = m_contacts->broadphase->create(grow(ballBox(s), m_contacts->margin), b.handle[s]);
    b.fat[s] = m_contacts->broadphase->fatBox(b.proxy[s]);
    m_contacts->ball_moved.resize(b.size(), 0);
    addPairsForBall(s);
}

void Model::insertSegment(uint32_t seg) {
    Segment& sg = m_bodies->segments[seg];
    sg.proxy = m_contacts->wall_broadphase->create(grow(segmentBox(seg), m_contacts->margin), seg);
    sg.fat = m_contacts->wall_broadphase->fatBox(sg.proxy);
    m_contacts->segment_moved.resize(m_bodies->segments.size(), 0);
    addPairsForSegment(seg);
}

void Model::addPairsForBall(uint32_t s) {
    // Balls and wall segments live in two trees: the segments of a box span the whole model and
    // would make every query of the ball tree descend into them.
    const Box& fat = m_bodies->balls.fat[s];
    m_contacts->query.clear();
    m_contacts->broadphase->query(fat, m_contacts->query);
    for (int32_t other : m_contacts->query) {
        const uint32_t handle = m_contacts->broadphase->user(other);
        const uint32_t o = m_bodies->slot_of[handle - 1];
        if (o != s) makePair(s, o, false);
    }
    m_contacts->query.clear();
    m_contacts->wall_broadphase->query(fat, m_contacts->query);
    for (int32_t other : m_contacts->query)
        makePair(s, m_contacts->wall_broadphase->user(other), true);
}

void Model::addPairsForSegment(uint32_t seg) {
    m_contacts->query.clear();
    m_contacts->broadphase->query(m_bodies->segments[seg].fat, m_contacts->query);
    for (int32_t other : m_contacts->query)
        makePair(m_bodies->slot_of[m_contacts->broadphase->user(other) - 1], seg, true);
}

void Model::detectContacts() {
    auto& b = m_bodies->balls;
    if (m_sort_every > 0 && m_step % m_sort_every == 0) {
        sortBalls();
        rebuildBallTree();
    }
    m_contacts->moved_balls.clear();
    m_contacts->moved_segments.clear();
    // Which balls left their fat boxes: a read-only test per ball, on the force loop's threads
    // (over the same ranges of balls as the law of motion); the tree is then updated for them
    // in slot order, as one thread does it.
    auto& leaving = m_contacts->leaving;
    const auto nballs = static_cast<std::ptrdiff_t>(b.size());
    leaving.resize(b.size());
    const int threads = m_step_threads;
    (void)threads;
    TALUS_OMP(omp parallel for num_threads(threads) schedule(static) if (threads > 1))
    for (std::ptrdiff_t s = 0; s < nballs; ++s)
        leaving[s] =
            !b.fat[s].contains(grow(ballBox(static_cast<uint32_t>(s)), m_contacts->margin));
    for (std::size_t s = 0; s < b.size(); ++s) {
        if (!leaving[s]) continue;
        const Box want = grow(ballBox(static_cast<uint32_t>(s)), m_contacts->margin);
        if (m_contacts->broadphase->move(b.proxy[s], want)) {
            b.fat[s] = m_contacts->broadphase->fatBox(b.proxy[s]);
            m_contacts->moved_balls.push_back(static_cast<uint32_t>(s));
            m_contacts->ball_moved[s] = 1;
        }
    }
    for (std::size_t w = 0; w < m_bodies->walls.size(); ++w) {
        const WallData& wd = m_bodies->walls[w];
        if (!wd.alive || (wd.vel.squaredNorm() == 0.0 && wd.spin == 0.0)) continue;
        for (uint32_t k = 0; k < wd.segment_count; ++k) {
            const uint32_t seg = wd.first_segment + k;
            Segment& sg = m_bodies->segments[seg];
            const Box want = grow(segmentBox(seg), m_contacts->margin);
            if (sg.fat.contains(want)) continue;
            if (m_contacts->wall_broadphase->move(sg.proxy, want)) {
                sg.fat = m_contacts->wall_broadphase->fatBox(sg.proxy);
                m_contacts->moved_segments.push_back(seg);
                m_contacts->segment_moved[seg] = 1;
            }
        }
    }
    m_profile.proxy_moves +=
        static_cast<int64_t>(m_contacts->moved_balls.size() + m_contacts->moved_segments.size());
    for (uint32_t s : m_contacts->moved_balls) addPairsForBall(s);
    for (uint32_t seg : m_contacts->moved_segments) addPairsForSegment(seg);
}

void Model::clearMovedFlags() {
    for (uint32_t s : m_contacts->moved_balls) m_contacts->ball_moved[s] = 0;
    for (uint32_t seg : m_contacts->moved_segments) m_contacts->segment_moved[seg] = 0;
    m_contacts->moved_balls.clear();
    m_contacts->moved_segments.clear();
}

// ------------------------------------------------------------------------ pairs

PropBlock Model::propBlockFor(const Pair& p) const {
    const auto& b = m_bodies->balls;
    PropBlock pb{};
    pb.size = sizeof(PropBlock);
    pb.version = m_fd_template.version;
    pb.kn[0] = b.kn[p.end1], pb.ks[0] = b.ks[p.end1], pb.fric[0] = b.fric[p.end1];
    pb.radius[0] = b.radius[p.end1];
    pb.mass[0] = b.mass[p.end1];
    if (p.wall) {
        const WallData& w = m_bodies->walls[m_bodies->segments[p.end2].wall];
        pb.end2_type = kEndWall;
        pb.kn[1] = w.kn, pb.ks[1] = w.ks, pb.fric[1] = w.fric;
        pb.radius[1] = 0.0;
        pb.mass[1] = 0.0;
    } else {
        pb.end2_type = kEndBall;
        pb.kn[1] = b.kn[p.end2], pb.ks[1] = b.ks[p.end2], pb.fric[1] = b.fric[p.end2];
        pb.radius[1] = b.radius[p.end2];
        pb.mass[1] = b.mass[p.end2];
    }
    pb.mass_eff = p.mass_eff;
    return pb;
}

double Model::tangentialInverseMass(const Pair& p) const {
    // Contact points at the rims: r = R (the overlap's share is negligible for this use).
    const auto& b = m_bodies->balls;
    const double r1 = b.radius[p.end1];
    double inv = b.inv_mass[p.end1] + r1 * r1 * b.inv_inertia[p.end1];
    if (!p.wall) {
        const double r2 = b.radius[p.end2];
        inv += b.inv_mass[p.end2] + r2 * r2 * b.inv_inertia[p.end2];
    }
    return inv;
}

ContactModel* Model::cloneFor(Pair& p) {
    Rule& rule = *p.rule;
    void* mem = rule.pool->allocate();
    ContactModel* m = nullptr;
    std::string why;
    try {
        m = rule.prototype->Clone(propBlockFor(p), mem);
        if (!m) why = rule.prototype->LastError();
    } catch (const std::exception& e) {
        why = e.what();
    } catch (...) {
        why = "unknown exception";
    }
    if (!m) {
        rule.pool->release(mem);
        throw PluginError("contact model '" + rule.model_name + "': cannot create the model for " +
                          describePair(p) + ": " + why);
    }
    return m;
}

bool Model::makePair(uint32_t s1, uint32_t other, bool other_is_segment) {
    auto& b = m_bodies->balls;
    Pair p;
    PairCold cold;
    if (other_is_segment) {
        p.end1 = s1;
        p.end2 = other;
        p.wall = true;
        cold.key = (uint64_t(b.handle[s1]) << 32) | (kWallBit | other);
    } else {
        if (s1 == other) return false;
        // Pebbles of one clump never touch each other (they may overlap by construction).
        if (b.clump[s1] != kNoClump && b.clump[s1] == b.clump[other]) return false;
        uint32_t a = s1, c = other;
        if (b.handle[a] > b.handle[c]) std::swap(a, c);
        p.end1 = a;
        p.end2 = c;
        cold.key = (uint64_t(b.handle[a]) << 32) | b.handle[c];
    }
    if (m_contacts->key_index.count(cold.key)) return false;
    const uint64_t g2 =
        p.wall ? m_bodies->walls[m_bodies->segments[p.end2].wall].groups : b.groups[p.end2];
    const Rule& rule = ruleFor(b.groups[p.end1], g2);
    if (!rule.prototype) return false;  // no contact model: bodies pass through
    p.rule = const_cast<Rule*>(&rule);
    cold.rules_version = m_contacts->rules_version;
    p.activity = rule.activity;
    const double m1 = b.mass[p.end1];
    p.mass_eff = p.wall ? m1 : m1 * b.mass[p.end2] / (m1 + b.mass[p.end2]);
    p.inv_mass_eff_s = tangentialInverseMass(p);
    p.model = cloneFor(p);
    p.knest = p.model->KnEstimate();
    p.ksest = p.model->KsEstimate();
    m_contacts->key_index.emplace(cold.key, static_cast<uint32_t>(m_contacts->pairs.size()));
    m_contacts->pairs.push_back(p);
    m_contacts->cold.push_back(cold);
    ++m_contacts->pairs_version;
    ++m_profile.pairs_created;
    return true;
}

void Model::removePair(std::size_t i) {
    Pair& p = m_contacts->pairs[i];
    // A contact removed while active (its ball deleted) ends with what it stores: released,
    // not dropped (the next step's strain sum no longer holds it).
    if (p.active && m_books.on) {
        m_books.acc.released += m_contacts->cold[i].strain + m_contacts->cold[i].bond;
        if (m_books.groups.on)
            bookReleasedToGroups(p, m_contacts->cold[i].strain + m_contacts->cold[i].bond);
    }
    if (p.model) {
        dropLane(p);
        p.model->Destroy();
        p.rule->pool->release(p.model);
        p.model = nullptr;
    }
    m_contacts->key_index.erase(m_contacts->cold[i].key);
    const std::size_t last = m_contacts->pairs.size() - 1;
    if (i != last) {
        m_contacts->pairs[i] = m_contacts->pairs[last];
        m_contacts->cold[i] = m_contacts->cold[last];
        m_contacts->key_index[m_contacts->cold[i].key] = static_cast<uint32_t>(i);
    }
    m_contacts->pairs.pop_back();
    m_contacts->cold.pop_back();
    ++m_contacts->pairs_version;
}

void Model::refreshRule(Pair& p) {
    m_contacts->cold[pairIndex(p)].rules_version = m_contacts->rules_version;
    const auto& b = m_bodies->balls;
    const uint64_t g2 =
        p.wall ? m_bodies->walls[m_bodies->segments[p.end2].wall].groups : b.groups[p.end2];
    Rule* rule = const_cast<Rule*>(&ruleFor(b.groups[p.end1], g2));
    if (rule == p.rule || !rule->prototype) return;
    dropLane(p);
    p.model->Destroy();
    p.rule->pool->release(p.model);
    p.rule = rule;
    p.activity = rule->activity;
    p.model = cloneFor(p);
}

void Model::resetPair(Pair& p) {
    // A fresh clone: the next touch starts from a clean state.
    dropLane(p);
    p.model->Destroy();
    p.rule->pool->release(p.model);
    p.model = nullptr;
    if (p.rule->installed) {
        // A contact bonded by m:bond ended (its bond broke or was removed, and it separated):
        // the next touch gets the ordinary rules, never the bond (model_bonds.cpp).
        m_contacts->cold[pairIndex(p)].rules_version = m_contacts->rules_version;
        const auto& b = m_bodies->balls;
        const uint64_t g2 =
            p.wall ? m_bodies->walls[m_bodies->segments[p.end2].wall].groups : b.groups[p.end2];
        Rule* rule = const_cast<Rule*>(&ruleFor(b.groups[p.end1], g2));
        if (rule->prototype) {
            p.rule = rule;
            p.activity = rule->activity;
        }
    }
    p.model = cloneFor(p);
    p.active = p.sliding = p.bonded = p.loading = false;
    p.steps = 0;
    p.work = p.work_peak = 0.0;
    p.n_force = p.s_force = p.moment = 0.0;
    p.knest = p.model->KnEstimate();
    p.ksest = p.model->KsEstimate();
    PairCold& c = m_contacts->cold[pairIndex(p)];
    const uint64_t key = c.key;
    const uint32_t version = c.rules_version;
    c = PairCold{};
    c.key = key;
    c.rules_version = version;
}

// ------------------------------------------------------------------------ wall vertices
//
// Pairs are keyed per (ball, segment), but a contact with a wall chain is one contact however
// many segments its point runs over: when the point crosses a convex vertex, the contact moves
// to the pair of the segment that holds it now, with its model object (the loading history of
// power, hysdamp's hysteresis, the shear spring, a bond) and its host state (forces, overlap,
// the guard's work and step count, duration, stored energies). In the vertex region the normal
// points from the centre to the vertex, which at the boundary of the next face region is that
// face's normal: the normal is continuous across the handover, so the shear force is kept as it
// is in the local frame (n, t = perp(n)), as it would be on a curved surface. Both pairs have the
// same ends' properties and the same rule (a rule depends on the groups, the same for every
// segment of a wall), so the model object fits either pair. docs/physics/walls.md.

void Model::swapPairState(std::size_t i, std::size_t j) { m_contacts->swapState(i, j); }

bool Model::handOverWallContact(std::size_t i) {
    // Slot i holds an active wall contact whose segment gave the ball up. After the handover,
    // slot i holds the holder's pair with the contact and the old segment's pair, inactive,
    // takes the holder's former slot: the force loop processes slot i again, so the contact gets
    // its FDlaw this step whether the holder's pair came before or after it in the loop (or is
    // created here, at the end of the list).
    const uint32_t s1 = m_contacts->pairs[i].end1;
    const int32_t h =
        wallHolder(m_contacts->pairs[i].end2, m_bodies->balls.pos[s1], m_bodies->balls.radius[s1]);
    if (h < 0) return false;
    const uint64_t key = (uint64_t(m_bodies->balls.handle[s1]) << 32) | (kWallBit | uint32_t(h));
    auto it = m_contacts->key_index.find(key);
    if (it == m_contacts->key_index.end()) {
        if (!makePair(s1, static_cast<uint32_t>(h), true)) return false;
        it = m_contacts->key_index.find(key);
    }
    const std::size_t q = it->second;
    // An active holder already has a contact of its own (never so at a vertex of one chain,
    // where the rule above gives every point to one segment): do not merge two contacts.
    if (m_contacts->pairs[q].active) return false;
    std::swap(m_contacts->pairs[i].end2, m_contacts->pairs[q].end2);
    std::swap(m_contacts->cold[i].key, m_contacts->cold[q].key);
    m_contacts->key_index[m_contacts->cold[i].key] = static_cast<uint32_t>(i);
    m_contacts->key_index[m_contacts->cold[q].key] = static_cast<uint32_t>(q);
    // Slot q may have been marked for removal this step (the holder's pair, far from the ball
    // then); it now holds the old segment's pair, which a later step will check again.
    m_contacts->to_remove.erase(
        std::remove(m_contacts->to_remove.begin(), m_contacts->to_remove.end(), uint32_t(q)),
        m_contacts->to_remove.end());
    return true;
}

bool Model::adoptWallContact(std::size_t i) {
    // Slot i: an inactive wall pair that now touches. If the ball's contact with this chain is
    // still held by the pair of a segment that gave it up (visited later in this step's loop),
    // this pair takes it over instead of starting a fresh contact. Walk the chain both ways over
    // existing, inactive pairs of this ball.
    const Pair& p = m_contacts->pairs[i];
    const uint32_t s1 = p.end1, seg = p.end2;
    const uint64_t hi = uint64_t(m_bodies->balls.handle[s1]) << 32;
    const uint32_t n = m_bodies->walls[m_bodies->segments[seg].wall].segment_count;
    for (int dir = 0; dir < 2; ++dir) {
        int32_t cur = static_cast<int32_t>(seg);
        for (uint32_t k = 0; k + 1 < n; ++k) {
            const Segment& sg = m_bodies->segments[static_cast<uint32_t>(cur)];
            cur = dir == 0 ? sg.prev : sg.next;
            if (cur < 0 || uint32_t(cur) == seg) break;
            const auto it = m_contacts->key_index.find(hi | kWallBit | uint32_t(cur));
            if (it == m_contacts->key_index.end()) break;
            const std::size_t j = it->second;
            if (!m_contacts->pairs[j].active) continue;
            // A segment that still holds the ball has a contact of its own (the other face of
            // a valley): leave it.
            ContactGeometry g;
            if (segmentGeometry(uint32_t(cur), m_bodies->balls.pos[s1], m_bodies->balls.radius[s1],
                                g) ||
                wallHolder(uint32_t(cur), m_bodies->balls.pos[s1], m_bodies->balls.radius[s1]) !=
                    static_cast<int32_t>(seg))
                break;
            swapPairState(i, j);
            return true;
        }
    }
    return false;
}

// ------------------------------------------------------------------------ memory order

void Model::sortBalls() {
    auto& b = m_bodies->balls;
    const std::size_t n = b.size();
    if (n < 2) return;
    Box all{b.pos[0], b.pos[0]};
    double rsum = 0.0;
    for (std::size_t s = 0; s < n; ++s) {
        all.lo = all.lo.cwiseMin(b.pos[s]);
        all.hi = all.hi.cwiseMax(b.pos[s]);
        rsum += b.radius[s];
    }
    const double cell = std::max(2.0 * rsum / static_cast<double>(n), 1e-300);
    auto spread = [](uint32_t v) {  // interleave bits for a Morton code
        uint64_t x = v;
        x = (x | (x << 16)) & 0x0000FFFF0000FFFFull;
        x = (x | (x << 8)) & 0x00FF00FF00FF00FFull;
        x = (x | (x << 4)) & 0x0F0F0F0F0F0F0F0Full;
        x = (x | (x << 2)) & 0x3333333333333333ull;
        x = (x | (x << 1)) & 0x5555555555555555ull;
        return x;
    };
    std::vector<uint64_t> code(n);
    for (std::size_t s = 0; s < n; ++s) {
        const Vec2 q = (b.pos[s] - all.lo) / cell;
        const auto ix = static_cast<uint32_t>(std::min(q.x(), 4.0e9));
        const auto iy = static_cast<uint32_t>(std::min(q.y(), 4.0e9));
        code[s] = spread(ix) | (spread(iy) << 1);
    }
    std::vector<uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t x, uint32_t y) { return code[x] < code[y]; });
    b.permute(order);
    std::vector<uint32_t> new_of(n);
    for (std::size_t i = 0; i < n; ++i) new_of[order[i]] = static_cast<uint32_t>(i);
    for (std::size_t s = 0; s < n; ++s)
        m_bodies->slot_of[b.handle[s] - 1] = static_cast<uint32_t>(s);
    for (auto& p : m_contacts->pairs) {
        p.end1 = new_of[p.end1];
        if (!p.wall) p.end2 = new_of[p.end2];
    }
    // Pairs in the order of their first end, so the force loop walks memory forward.
    std::vector<uint32_t> porder(m_contacts->pairs.size());
    std::iota(porder.begin(), porder.end(), 0u);
    std::sort(porder.begin(), porder.end(), [&](uint32_t x, uint32_t y) {
        const Pair &px = m_contacts->pairs[x], &py = m_contacts->pairs[y];
        return px.end1 != py.end1 ? px.end1 < py.end1
                                  : m_contacts->cold[x].key < m_contacts->cold[y].key;
    });
    std::vector<Pair> pairs(m_contacts->pairs.size());
    std::vector<PairCold> cold(m_contacts->cold.size());
    for (std::size_t i = 0; i < porder.size(); ++i) {
        pairs[i] = m_contacts->pairs[porder[i]];
        cold[i] = m_contacts->cold[porder[i]];
        m_contacts->key_index[cold[i].key] = static_cast<uint32_t>(i);
    }
    m_contacts->pairs.swap(pairs);
    m_contacts->cold.swap(cold);
    ++m_contacts->pairs_version;
    repackContactObjects();
    reorderLanes();
}

void Model::repackContactObjects() {
    // Contact objects are placed as pairs appear, so after a while the force loop, which walks
    // the pairs in memory order, jumps around the pools. Move every object into a fresh pool in
    // the pairs' order (ContactModel::MoveTo) and drop the old pools.
    std::vector<std::unique_ptr<ObjectPool>> fresh(m_contacts->rules.size());
    std::unordered_map<const Rule*, std::size_t> slot;
    for (std::size_t r = 0; r < m_contacts->rules.size(); ++r) {
        slot[m_contacts->rules[r].get()] = r;
        if (m_contacts->rules[r]->pool)
            fresh[r] = std::make_unique<ObjectPool>(m_contacts->rules[r]->pool->blockSize());
    }
    for (auto& p : m_contacts->pairs) {
        if (!p.model) continue;
        ObjectPool& pool = *fresh[slot[p.rule]];
        p.model = p.model->MoveTo(pool.allocate());
    }
    for (std::size_t r = 0; r < m_contacts->rules.size(); ++r)
        if (fresh[r]) m_contacts->rules[r]->pool = std::move(fresh[r]);
}

}  // namespace talus
