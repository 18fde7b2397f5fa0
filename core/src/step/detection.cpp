// SPDX-License-Identifier: MIT
//
// Phase 3: contact detection, broadphase part (docs/architecture.md).
//
// One b2DynamicTree proxy per ball and per wall segment (broadphase.hpp). A body is re-inserted
// only when it has less than one margin of room left in its fat box, and only re-inserted
// bodies are queried for new pairs, so a settled packing does almost no broadphase work.
// A pair lives while the fat boxes of its ends overlap; the narrowphase (is it touching?) runs
// in the force loop (force/pass_geometry.hpp), which is where the pair's data is hot anyway.
#include "step/detection.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <numeric>
#include <unordered_map>

#include "step/group_energy.hpp"
#include "step/narrowphase.hpp"
#include "step/step.hpp"
#include "talus/errors.hpp"
#include "world/body_store.hpp"
#include "world/broadphase.hpp"
#include "world/capacity.hpp"
#include "world/contact_store.hpp"
#include "world/lanes.hpp"
#include "world/messages.hpp"
#include "world/permute.hpp"
#include "world/types.hpp"

namespace talus {

namespace {

Box grow(const Box& b, double d) {
    Box g = b;
    g.lo.array() -= d;
    g.hi.array() += d;
    return g;
}

}  // namespace

Box ballBox(const World& world, uint32_t s) {
    const double r = world.bodies.balls.radius[s] + 0.5 * world.contacts.max_activity;
    const Vec2& p = world.bodies.balls.pos[s];
    return Box{Vec2(p.x() - r, p.y() - r), Vec2(p.x() + r, p.y() + r)};
}

Box segmentBox(const World& world, uint32_t seg) {
    const Vec2& a = world.bodies.vertices[world.bodies.segments[seg].a];
    const Vec2& b = world.bodies.vertices[world.bodies.segments[seg].b];
    const double h = 0.5 * world.contacts.max_activity;
    return Box{Vec2(std::min(a.x(), b.x()) - h, std::min(a.y(), b.y()) - h),
               Vec2(std::max(a.x(), b.x()) + h, std::max(a.y(), b.y()) + h)};
}

bool segmentGeometry(const World& world, uint32_t seg, const Vec2& c, double r,
                     ContactGeometry& g) {
    const Segment& sg = world.bodies.segments[seg];
    const Vec2* before =
        sg.prev >= 0 ? &world.bodies.vertices[world.bodies.segments[sg.prev].a] : nullptr;
    const Vec2* after =
        sg.next >= 0 ? &world.bodies.vertices[world.bodies.segments[sg.next].b] : nullptr;
    return ballSegmentGeometry(c, r, world.bodies.vertices[sg.a], world.bodies.vertices[sg.b],
                               before, after, g);
}

int32_t wallHolder(const World& world, uint32_t seg, const Vec2& c, double r) {
    // A segment gives up a ball only beyond one of its ends, at a convex vertex
    // (narrowphase.hpp), so the holder lies that way along the chain; a fast ball or short
    // segments may put it more than one segment away. The walk cannot turn back (the segment
    // beyond a convex vertex gives the ball back only on this side of it, where this one holds
    // it), and a closed chain is walked at most once round.
    const uint32_t n = world.bodies.walls[world.bodies.segments[seg].wall].segment_count;
    ContactGeometry g;
    int32_t cur = static_cast<int32_t>(seg);
    for (uint32_t k = 0; k < n; ++k) {
        const Segment& sg = world.bodies.segments[static_cast<uint32_t>(cur)];
        const Vec2 ab = world.bodies.vertices[sg.b] - world.bodies.vertices[sg.a];
        const double t = (c - world.bodies.vertices[sg.a]).dot(ab) / ab.squaredNorm();
        cur = t <= 0.0 ? sg.prev : (t >= 1.0 ? sg.next : -1);
        if (cur < 0) return -1;
        if (segmentGeometry(world, static_cast<uint32_t>(cur), c, r, g)) return cur;
    }
    return -1;
}

void initBroadphase(World& world) {
    auto& b = world.bodies.balls;
    if (!(world.contacts.margin > 0.0)) {
        double mean = 0.0;
        for (double r : b.radius) mean += r;
        mean = b.size() ? mean / static_cast<double>(b.size()) : 0.0;
        if (mean <= 0.0) {
            // Only walls: take 1% of the walls' extent.
            Box all{Vec2(1e300, 1e300), Vec2(-1e300, -1e300)};
            for (const Vec2& v : world.bodies.vertices)
                all.lo = all.lo.cwiseMin(v), all.hi = all.hi.cwiseMax(v);
            mean = world.bodies.vertices.empty() ? 1.0
                                                 : std::max(0.01 * (all.hi - all.lo).norm(), 1e-6);
        }
        world.contacts.margin = 0.05 * mean;
    }
    // The balls of a script were added one at a time: their arrays' spare capacity goes before
    // the pairs are made.
    b.trim();
    world.contacts.broadphase->reset(world.contacts.margin);
    world.contacts.wall_broadphase->reset(world.contacts.margin);
    world.contacts.broadphase_ready = true;
    for (std::size_t i = 0; i < world.bodies.segments.size(); ++i) {
        world.bodies.segments[i].proxy = -1;
        if (!world.bodies.walls[world.bodies.segments[i].wall].alive) continue;
        const auto seg = static_cast<uint32_t>(i);
        world.bodies.segments[i].proxy = world.contacts.wall_broadphase->create(
            grow(segmentBox(world, seg), world.contacts.margin), seg);
        world.bodies.segments[i].fat =
            world.contacts.wall_broadphase->fatBox(world.bodies.segments[i].proxy);
    }
    for (std::size_t s = 0; s < b.size(); ++s) {
        b.proxy[s] = world.contacts.broadphase->create(
            grow(ballBox(world, static_cast<uint32_t>(s)), world.contacts.margin), b.handle[s]);
        b.fat[s] = world.contacts.broadphase->fatBox(b.proxy[s]);
    }
    for (std::size_t s = 0; s < b.size(); ++s) addPairsForBall(world, static_cast<uint32_t>(s));
    // (made one at a time too; trimmed before the first step adds the kernel rows and watches)
    trimCapacity(world.contacts.pairs);
    trimCapacity(world.contacts.cold);
    trimCapacity(world.contacts.stored);
    world.contacts.ball_moved.assign(b.size(), 0);
    world.contacts.segment_moved.assign(world.bodies.segments.size(), 0);
}

void rebuildBallTree(World& world) {
    // The tree's quality depends on the order of insertion; after the balls were sorted along a
    // Morton curve, inserting them in that order gives a spatially coherent tree (a query costs
    // about ten times less than in a tree built in random order, docs/benchmarks.md).
    auto& b = world.bodies.balls;
    world.contacts.broadphase->reset(world.contacts.margin);
    for (std::size_t s = 0; s < b.size(); ++s) {
        b.proxy[s] = world.contacts.broadphase->create(
            grow(ballBox(world, static_cast<uint32_t>(s)), world.contacts.margin), b.handle[s]);
        b.fat[s] = world.contacts.broadphase->fatBox(b.proxy[s]);
    }
}

void insertBall(World& world, uint32_t s) {
    auto& b = world.bodies.balls;
    b.proxy[s] = world.contacts.broadphase->create(grow(ballBox(world, s), world.contacts.margin),
                                                   b.handle[s]);
    b.fat[s] = world.contacts.broadphase->fatBox(b.proxy[s]);
    world.contacts.ball_moved.resize(b.size(), 0);
    addPairsForBall(world, s);
}

void insertSegment(World& world, uint32_t seg) {
    Segment& sg = world.bodies.segments[seg];
    sg.proxy = world.contacts.wall_broadphase->create(
        grow(segmentBox(world, seg), world.contacts.margin), seg);
    sg.fat = world.contacts.wall_broadphase->fatBox(sg.proxy);
    world.contacts.segment_moved.resize(world.bodies.segments.size(), 0);
    addPairsForSegment(world, seg);
}

void addPairsForBall(World& world, uint32_t s) {
    // Balls and wall segments live in two trees: the segments of a box span the whole model and
    // would make every query of the ball tree descend into them.
    const Box& fat = world.bodies.balls.fat[s];
    world.contacts.query.clear();
    world.contacts.broadphase->query(fat, world.contacts.query);
    for (int32_t other : world.contacts.query) {
        const uint32_t handle = world.contacts.broadphase->user(other);
        const uint32_t o = world.bodies.slot_of[handle - 1];
        if (o != s) makePair(world, s, o, false);
    }
    world.contacts.query.clear();
    world.contacts.wall_broadphase->query(fat, world.contacts.query);
    for (int32_t other : world.contacts.query)
        makePair(world, s, world.contacts.wall_broadphase->user(other), true);
}

void addPairsForSegment(World& world, uint32_t seg) {
    world.contacts.query.clear();
    world.contacts.broadphase->query(world.bodies.segments[seg].fat, world.contacts.query);
    for (int32_t other : world.contacts.query)
        makePair(world, world.bodies.slot_of[world.contacts.broadphase->user(other) - 1], seg,
                 true);
}

void detectContacts(World& world, const StepContext& /*step: detection needs only the positions*/) {
    auto& b = world.bodies.balls;
    // The memory order (Model::setSortInterval): at the first step, as the balls were made, and
    // every `every` steps after.
    int64_t every = world.settings.sort_every;
    if (every == Model::kSortAuto)
        every = b.size() >= Model::kSortAutoBalls ? Model::kSortAutoEvery : 0;
    if (every > 0 && (world.clock.step - 1) % every == 0) {
        ++world.profile.sorts;
        sortBalls(world);
        rebuildBallTree(world);
    }
    world.contacts.moved_balls.clear();
    world.contacts.moved_segments.clear();
    // Which balls left their fat boxes: a read-only test per ball, on the force loop's threads
    // (over the same ranges of balls as the law of motion); the tree is then updated for them
    // in slot order, as one thread does it.
    auto& leaving = world.contacts.leaving;
    const auto nballs = static_cast<std::ptrdiff_t>(b.size());
    leaving.resize(b.size());
    const int threads = world.clock.threads;
    (void)threads;
    TALUS_OMP(omp parallel for num_threads(threads) schedule(static) if (threads > 1))
    for (std::ptrdiff_t s = 0; s < nballs; ++s)
        leaving[s] = !b.fat[s].contains(
            grow(ballBox(world, static_cast<uint32_t>(s)), world.contacts.margin));
    for (std::size_t s = 0; s < b.size(); ++s) {
        if (!leaving[s]) continue;
        const Box want = grow(ballBox(world, static_cast<uint32_t>(s)), world.contacts.margin);
        if (world.contacts.broadphase->move(b.proxy[s], want)) {
            b.fat[s] = world.contacts.broadphase->fatBox(b.proxy[s]);
            world.contacts.moved_balls.push_back(static_cast<uint32_t>(s));
            world.contacts.ball_moved[s] = 1;
        }
    }
    for (std::size_t w = 0; w < world.bodies.walls.size(); ++w) {
        const WallData& wd = world.bodies.walls[w];
        if (!wd.alive || (wd.vel.squaredNorm() == 0.0 && wd.spin == 0.0)) continue;
        for (uint32_t k = 0; k < wd.segment_count; ++k) {
            const uint32_t seg = wd.first_segment + k;
            Segment& sg = world.bodies.segments[seg];
            const Box want = grow(segmentBox(world, seg), world.contacts.margin);
            if (sg.fat.contains(want)) continue;
            if (world.contacts.wall_broadphase->move(sg.proxy, want)) {
                sg.fat = world.contacts.wall_broadphase->fatBox(sg.proxy);
                world.contacts.moved_segments.push_back(seg);
                world.contacts.segment_moved[seg] = 1;
            }
        }
    }
    world.profile.proxy_moves += static_cast<int64_t>(world.contacts.moved_balls.size() +
                                                      world.contacts.moved_segments.size());
    for (uint32_t s : world.contacts.moved_balls) addPairsForBall(world, s);
    for (uint32_t seg : world.contacts.moved_segments) addPairsForSegment(world, seg);
}

void clearMovedFlags(World& world) {
    for (uint32_t s : world.contacts.moved_balls) world.contacts.ball_moved[s] = 0;
    for (uint32_t seg : world.contacts.moved_segments) world.contacts.segment_moved[seg] = 0;
    world.contacts.moved_balls.clear();
    world.contacts.moved_segments.clear();
}

// ------------------------------------------------------------------------ pairs

const Rule& ruleFor(const World& world, uint64_t g1, uint64_t g2) {
    const Rule* best = world.contacts.rules[0].get();
    int best_spec = -1, best_order = -1;
    auto in = [](uint64_t g, int idx) { return idx < 0 || (g & (uint64_t(1) << idx)) != 0; };
    for (std::size_t i = 1; i < world.contacts.rules.size(); ++i) {
        const Rule& r = *world.contacts.rules[i];
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

bool pairGeometry(const World& world, const Pair& p, Vec2& normal, double& overlap, Vec2& point) {
    const auto& b = world.bodies.balls;
    const Vec2& x1 = b.pos[p.end1];
    ContactGeometry g;
    if (p.wall) {
        if (!segmentGeometry(world, p.end2, x1, b.radius[p.end1], g)) return false;
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

PropBlock propBlockFor(const World& world, const Pair& p, double mass_eff) {
    const auto& b = world.bodies.balls;
    PropBlock pb{};
    pb.size = sizeof(PropBlock);
    pb.version = world.contacts.fd_template.version;
    pb.kn[0] = b.kn[p.end1], pb.ks[0] = b.ks[p.end1], pb.fric[0] = b.fric[p.end1];
    pb.radius[0] = b.radius[p.end1];
    pb.mass[0] = b.mass[p.end1];
    if (p.wall) {
        const WallData& w = world.bodies.walls[world.bodies.segments[p.end2].wall];
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
    pb.mass_eff = mass_eff;
    return pb;
}

double tangentialInverseMass(const World& world, const Pair& p) {
    // Contact points at the rims: r = R (the overlap's share is negligible for this use).
    const auto& b = world.bodies.balls;
    const double r1 = b.radius[p.end1];
    double inv = b.inv_mass[p.end1] + r1 * r1 * b.inv_inertia[p.end1];
    if (!p.wall) {
        const double r2 = b.radius[p.end2];
        inv += b.inv_mass[p.end2] + r2 * r2 * b.inv_inertia[p.end2];
    }
    return inv;
}

ContactModel* cloneFor(World& world, const Pair& p, double mass_eff) {
    Rule& rule = world.contacts.ruleOf(p);
    void* mem = rule.pool->allocate();
    ContactModel* m = nullptr;
    std::string why;
    try {
        m = rule.prototype->Clone(propBlockFor(world, p, mass_eff), mem);
        if (!m) why = rule.prototype->LastError();
    } catch (const std::exception& e) {
        why = e.what();
    } catch (...) {
        why = "unknown exception";
    }
    if (!m) {
        rule.pool->release(mem);
        throw PluginError("contact model '" + rule.model_name + "': cannot create the model for " +
                          describePair(world, p) + ": " + why);
    }
    return m;
}

bool makePair(World& world, uint32_t s1, uint32_t other, bool other_is_segment) {
    auto& b = world.bodies.balls;
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
    if (world.contacts.key_index.count(cold.key)) return false;
    const uint64_t g2 =
        p.wall ? world.bodies.walls[world.bodies.segments[p.end2].wall].groups : b.groups[p.end2];
    const Rule& rule = ruleFor(world, b.groups[p.end1], g2);
    if (!rule.prototype) return false;  // no contact model: bodies pass through
    p.rule = world.contacts.ruleIndex(&rule);
    cold.rules_version = world.contacts.rules_version;
    cold.activity = rule.activity;
    const double m1 = b.mass[p.end1];
    cold.mass_eff = p.wall ? m1 : m1 * b.mass[p.end2] / (m1 + b.mass[p.end2]);
    cold.inv_mass_eff_s = tangentialInverseMass(world, p);
    p.model = cloneFor(world, p, cold.mass_eff);
    cold.knest = p.model->KnEstimate();
    cold.ksest = p.model->KsEstimate();
    world.contacts.key_index.emplace(cold.key, static_cast<uint32_t>(world.contacts.pairs.size()));
    // (by a quarter: the first pair made after the stores were trimmed would double them)
    reserveOneMore(world.contacts.pairs);
    reserveOneMore(world.contacts.cold);
    reserveOneMore(world.contacts.stored);
    world.contacts.pairs.push_back(p);
    world.contacts.cold.push_back(cold);
    world.contacts.stored.emplace_back();
    ++world.contacts.pairs_version;
    ++world.profile.pairs_created;
    return true;
}

void removePair(World& world, std::size_t i) {
    Pair& p = world.contacts.pairs[i];
    // A contact removed while active (its ball deleted) ends with what it stores: released,
    // not dropped (the next step's strain sum no longer holds it).
    if (p.active && world.books.on) {
        const double stored = world.contacts.stored[i].total();
        world.books.acc.released += stored;
        if (world.books.groups.on) bookReleasedToGroups(world, p, stored);
    }
    world.contacts.endWatch(p, world.contacts.cold[i]);
    if (p.model) {
        dropLane(world.contacts, p);
        p.model->Destroy();
        world.contacts.ruleOf(p).pool->release(p.model);
        p.model = nullptr;
    }
    world.contacts.key_index.erase(world.contacts.cold[i].key);
    const std::size_t last = world.contacts.pairs.size() - 1;
    if (i != last) {
        world.contacts.pairs[i] = world.contacts.pairs[last];
        world.contacts.cold[i] = world.contacts.cold[last];
        world.contacts.stored[i] = world.contacts.stored[last];
        world.contacts.key_index[world.contacts.cold[i].key] = static_cast<uint32_t>(i);
    }
    world.contacts.pairs.pop_back();
    world.contacts.cold.pop_back();
    world.contacts.stored.pop_back();
    ++world.contacts.pairs_version;
}

void refreshRule(World& world, Pair& p) {
    world.contacts.cold[world.contacts.pairIndex(p)].rules_version = world.contacts.rules_version;
    const auto& b = world.bodies.balls;
    const uint64_t g2 =
        p.wall ? world.bodies.walls[world.bodies.segments[p.end2].wall].groups : b.groups[p.end2];
    const Rule* rule = &ruleFor(world, b.groups[p.end1], g2);
    if (rule == &world.contacts.ruleOf(p) || !rule->prototype) return;
    dropLane(world.contacts, p);
    PairCold& c = world.contacts.coldOf(p);
    p.model->Destroy();
    world.contacts.ruleOf(p).pool->release(p.model);
    p.rule = world.contacts.ruleIndex(rule);
    c.activity = rule->activity;
    p.model = cloneFor(world, p, c.mass_eff);
}

void resetPair(World& world, Pair& p) {
    // A fresh clone: the next touch starts from a clean state.
    dropLane(world.contacts, p);
    PairCold& c = world.contacts.coldOf(p);
    world.contacts.endWatch(p, c);
    p.model->Destroy();
    world.contacts.ruleOf(p).pool->release(p.model);
    p.model = nullptr;
    if (world.contacts.ruleOf(p).installed) {
        // A contact bonded by m:bond ended (its bond broke or was removed, and it separated):
        // the next touch gets the ordinary rules, never the bond (api/bonds.cpp).
        c.rules_version = world.contacts.rules_version;
        const auto& b = world.bodies.balls;
        const uint64_t g2 = p.wall ? world.bodies.walls[world.bodies.segments[p.end2].wall].groups
                                   : b.groups[p.end2];
        const Rule* rule = &ruleFor(world, b.groups[p.end1], g2);
        if (rule->prototype) p.rule = world.contacts.ruleIndex(rule);
    }
    p.model = cloneFor(world, p, c.mass_eff);
    p.active = p.sliding = p.bonded = p.loading = p.watched = false;
    p.n_force = p.s_force = p.moment = 0.0;
    // The cold record afresh but for what names the pair and what its law needs.
    PairCold fresh;
    fresh.activity = world.contacts.ruleOf(p).activity;
    fresh.mass_eff = c.mass_eff;
    fresh.inv_mass_eff_s = c.inv_mass_eff_s;
    fresh.knest = p.model->KnEstimate();
    fresh.ksest = p.model->KsEstimate();
    fresh.key = c.key;
    fresh.rules_version = c.rules_version;
    c = fresh;
    world.contacts.storedOf(p) = PairStored{};
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

void swapPairState(World& world, std::size_t i, std::size_t j) { world.contacts.swapState(i, j); }

bool handOverWallContact(World& world, std::size_t i) {
    // Slot i holds an active wall contact whose segment gave the ball up. After the handover,
    // slot i holds the holder's pair with the contact and the old segment's pair, inactive,
    // takes the holder's former slot: the force loop processes slot i again, so the contact gets
    // its FDlaw this step whether the holder's pair came before or after it in the loop (or is
    // created here, at the end of the list).
    const uint32_t s1 = world.contacts.pairs[i].end1;
    const int32_t h = wallHolder(world, world.contacts.pairs[i].end2, world.bodies.balls.pos[s1],
                                 world.bodies.balls.radius[s1]);
    if (h < 0) return false;
    const uint64_t key = (uint64_t(world.bodies.balls.handle[s1]) << 32) | (kWallBit | uint32_t(h));
    auto it = world.contacts.key_index.find(key);
    if (it == world.contacts.key_index.end()) {
        if (!makePair(world, s1, static_cast<uint32_t>(h), true)) return false;
        it = world.contacts.key_index.find(key);
    }
    const std::size_t q = it->second;
    // An active holder already has a contact of its own (never so at a vertex of one chain,
    // where the rule above gives every point to one segment): do not merge two contacts.
    if (world.contacts.pairs[q].active) return false;
    std::swap(world.contacts.pairs[i].end2, world.contacts.pairs[q].end2);
    std::swap(world.contacts.cold[i].key, world.contacts.cold[q].key);
    world.contacts.key_index[world.contacts.cold[i].key] = static_cast<uint32_t>(i);
    world.contacts.key_index[world.contacts.cold[q].key] = static_cast<uint32_t>(q);
    // Slot q may have been marked for removal this step (the holder's pair, far from the ball
    // then); it now holds the old segment's pair, which a later step will check again.
    world.contacts.to_remove.erase(
        std::remove(world.contacts.to_remove.begin(), world.contacts.to_remove.end(), uint32_t(q)),
        world.contacts.to_remove.end());
    return true;
}

bool adoptWallContact(World& world, std::size_t i) {
    // Slot i: an inactive wall pair that now touches. If the ball's contact with this chain is
    // still held by the pair of a segment that gave it up (visited later in this step's loop),
    // this pair takes it over instead of starting a fresh contact. Walk the chain both ways over
    // existing, inactive pairs of this ball.
    const Pair& p = world.contacts.pairs[i];
    const uint32_t s1 = p.end1, seg = p.end2;
    const uint64_t hi = uint64_t(world.bodies.balls.handle[s1]) << 32;
    const uint32_t n = world.bodies.walls[world.bodies.segments[seg].wall].segment_count;
    for (int dir = 0; dir < 2; ++dir) {
        int32_t cur = static_cast<int32_t>(seg);
        for (uint32_t k = 0; k + 1 < n; ++k) {
            const Segment& sg = world.bodies.segments[static_cast<uint32_t>(cur)];
            cur = dir == 0 ? sg.prev : sg.next;
            if (cur < 0 || uint32_t(cur) == seg) break;
            const auto it = world.contacts.key_index.find(hi | kWallBit | uint32_t(cur));
            if (it == world.contacts.key_index.end()) break;
            const std::size_t j = it->second;
            if (!world.contacts.pairs[j].active) continue;
            // A segment that still holds the ball has a contact of its own (the other face of
            // a valley): leave it.
            ContactGeometry g;
            if (segmentGeometry(world, uint32_t(cur), world.bodies.balls.pos[s1],
                                world.bodies.balls.radius[s1], g) ||
                wallHolder(world, uint32_t(cur), world.bodies.balls.pos[s1],
                           world.bodies.balls.radius[s1]) != static_cast<int32_t>(seg))
                break;
            swapPairState(world, i, j);
            return true;
        }
    }
    return false;
}

// ------------------------------------------------------------------------ memory order

void sortBalls(World& world) {
    auto& b = world.bodies.balls;
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
        world.bodies.slot_of[b.handle[s] - 1] = static_cast<uint32_t>(s);
    for (auto& p : world.contacts.pairs) {
        p.end1 = new_of[p.end1];
        if (!p.wall) p.end2 = new_of[p.end2];
    }
    // Pairs in the order of their first end, so the force loop walks memory forward.
    std::vector<uint32_t> porder(world.contacts.pairs.size());
    std::iota(porder.begin(), porder.end(), 0u);
    std::sort(porder.begin(), porder.end(), [&](uint32_t x, uint32_t y) {
        const Pair &px = world.contacts.pairs[x], &py = world.contacts.pairs[y];
        return px.end1 != py.end1 ? px.end1 < py.end1
                                  : world.contacts.cold[x].key < world.contacts.cold[y].key;
    });
    // (in place: copies of the three stores would be the run's largest transient)
    ContactStore& cs = world.contacts;
    gatherInPlace(porder, porder.size(), [&](std::size_t i, std::size_t j) {
        std::swap(cs.pairs[i], cs.pairs[j]);
        std::swap(cs.cold[i], cs.cold[j]);
        std::swap(cs.stored[i], cs.stored[j]);
    });
    for (std::size_t i = 0; i < cs.pairs.size(); ++i)
        cs.key_index[cs.cold[i].key] = static_cast<uint32_t>(i);
    ++world.contacts.pairs_version;
    repackContactObjects(world);
    reorderLanes(world);
}

void repackContactObjects(World& world) {
    // Contact objects are placed as pairs appear, so after a while the force loop, which walks
    // the pairs in memory order, jumps around the pools. Every rule's objects go to the first
    // blocks of its pool in the pairs' order (ContactModel::MoveTo), in place (a second pool
    // would hold them twice), and the chunks left empty are freed.
    ContactStore& cs = world.contacts;
    for (std::size_t r = 0; r < cs.rules.size(); ++r) {
        ObjectPool* pool = cs.rules[r]->pool.get();
        if (!pool) continue;
        std::vector<uint32_t> users;  // the rule's pairs with an object, in pair order
        std::vector<const void*> objects;
        for (std::size_t i = 0; i < cs.pairs.size(); ++i)
            if (cs.pairs[i].model && cs.pairs[i].rule == r) {
                users.push_back(static_cast<uint32_t>(i));
                objects.push_back(cs.pairs[i].model);
            }
        const std::vector<uint32_t> order = pool->blockIndices(objects);
        std::vector<uint32_t> owner(pool->blockCount(), UINT32_MAX);  // block -> its pair
        for (std::size_t k = 0; k < users.size(); ++k) owner[order[k]] = users[k];
        std::unique_ptr<unsigned char[]> spare(new unsigned char[pool->blockSize()]);
        gatherInPlace(order, pool->blockCount(), [&](std::size_t to, std::size_t from) {
            // `from` holds an object; `to` holds one or is free.
            Pair& moving = cs.pairs[owner[from]];
            if (owner[to] != UINT32_MAX) {
                Pair& other = cs.pairs[owner[to]];
                ContactModel* parked = other.model->MoveTo(spare.get());
                moving.model = moving.model->MoveTo(pool->block(to));
                other.model = parked->MoveTo(pool->block(from));
            } else {
                moving.model = moving.model->MoveTo(pool->block(to));
            }
            std::swap(owner[to], owner[from]);
        });
        pool->keepFirst(users.size());
    }
}

}  // namespace talus
