// SPDX-License-Identifier: MIT
//
// The trackers' sample at the end of a step (bookkeeping phase; docs/lua-api.md, "Trackers").
// Each live tracker takes one sample of its body per step, in this order: its touches (impacts),
// the lines crossed since the last sample, its envelope bin, its path, then its end rules (region,
// rest, time). The state a sample sees is what a cycle hook sees: positions at the end of the
// step, velocities at the half step that moved them, before this step's contact forces act.
//
// Touches: one pass over the contacts finds, for every tracked body, whether it touches anything
// (positive overlap) and the first contact (in pair order) of the kind its impacts count. A clump
// is one body: a touch of any of its pebbles is the clump's.
#include "step/trackers.hpp"

#include <algorithm>
#include <cmath>

#include "step/detection.hpp"
#include "step/crossing.hpp"
#include "world/body_store.hpp"
#include "world/contact_store.hpp"
#include "world/types.hpp"

namespace talus {

namespace {

/// The tracked body now, and what the crossings' interpolation needs to know about it.
struct BodyNow {
    TrackedState state;
    double mass = 0.0, inertia = 0.0;
    // Only gravity acts on it between contacts: no applied force or moment, no fixity, no
    // damping. Then free flight follows the parabola of gravity exactly.
    bool gravity_only = false;
};

BodyNow readBody(const World& world, const Tracker& t) {
    BodyNow b;
    b.state.time = world.clock.time;
    uint8_t fixity = 0;
    bool loaded = false;  // an applied force or moment
    uint64_t key = 0;
    if (t.clump.valid()) {
        const ClumpData& c = world.bodies.clumps[t.clump.index - 1];
        b.state.pos = c.pos, b.state.vel = c.vel, b.state.spin = c.spin;
        b.mass = c.mass, b.inertia = c.inertia;
        fixity = c.fixity;
        loaded = c.fapp.x() != 0.0 || c.fapp.y() != 0.0 || c.mapp != 0.0;
        key = barrierClumpKey(t.clump.index - 1, t.clump.generation);
    } else {
        const auto& a = world.bodies.balls;
        const uint32_t s = world.bodies.slot_of[t.ball.index - 1];
        b.state.pos = a.pos[s], b.state.vel = a.vel[s], b.state.spin = a.spin[s];
        b.mass = a.mass[s], b.inertia = a.inertia[s];
        fixity = a.fixity[s];
        loaded = a.fapp[s].x() != 0.0 || a.fapp[s].y() != 0.0 || a.mapp[s] != 0.0;
        key = barrierBallKey(t.ball.index, t.ball.generation);
    }
    // A barrier caught the body in this step: the sample sees it as the barrier did.
    for (const BarrierActed& a : world.barriers.acted)
        if (a.key == key) b.state.vel = a.vel, b.state.spin = a.spin, fixity = a.fixity;
    const DampingSettings& d = world.settings.damping;
    b.gravity_only = fixity == 0 && !loaded && d.local == 0.0 && d.viscous == 0.0;
    return b;
}

double translational(double mass, const Vec2& v) { return translationalEnergy(mass, v); }
double rotational(double inertia, double w) { return rotationalEnergy(inertia, w); }

/// The live tracker of the body ball slot `slot` belongs to, or -1.
int32_t trackerOfSlot(const World& world, uint32_t slot) {
    const Trackers& tr = world.trackers;
    const auto& b = world.bodies.balls;
    const uint32_t c = b.clump[slot];
    if (c != kNoClump) return c < tr.by_clump.size() ? tr.by_clump[c] : -1;
    const uint32_t h = b.handle[slot] - 1;
    if (h >= tr.by_ball.size() || tr.by_ball[h] < 0) return -1;
    const int32_t k = tr.by_ball[h];
    // A handle re-used by a new ball since the tracked one was deleted (the tracker learns of
    // the deletion at its next sample).
    return tr.list[static_cast<std::size_t>(k)].ball.generation == world.bodies.generation[h] ? k
                                                                                              : -1;
}

bool countsAsImpact(TrackImpacts kind, bool wall) {
    switch (kind) {
        case TrackImpacts::Walls:
            return wall;
        case TrackImpacts::Bodies:
            return !wall;
        case TrackImpacts::Any:
            return true;
        case TrackImpacts::Off:
            break;
    }
    return false;
}

/// What the tracked end of pair p touches: the other end.
void describeHit(const World& world, const Pair& p, bool tracked_is_end2, TrackerTouch& hit) {
    const auto& b = world.bodies.balls;
    if (p.wall) {
        const Segment& sg = world.bodies.segments[p.end2];
        const WallData& w = world.bodies.walls[sg.wall];
        hit.wall = WallId{sg.wall + 1, w.generation};
        hit.segment = static_cast<int32_t>(p.end2 - w.first_segment);
        hit.groups = w.groups;
        return;
    }
    const uint32_t other = tracked_is_end2 ? p.end1 : p.end2;
    hit.ball = world.bodies.ballId(other);
    if (b.clump[other] != kNoClump) hit.clump = world.bodies.clumpId(b.clump[other]);
    hit.groups = b.groups[other];
}

void noteTouch(World& world, std::vector<TrackerTouch>& touch, int32_t k, const Pair& p, bool end2,
               const Vec2& normal, const Vec2& point) {
    TrackerTouch& t = touch[static_cast<std::size_t>(k)];
    t.any = true;
    if (t.kind) return;
    if (!countsAsImpact(world.trackers.list[static_cast<std::size_t>(k)].def.impacts, p.wall))
        return;
    t.kind = true;
    t.normal = normal;
    t.point = point;
    describeHit(world, p, end2, t);
}

/// The touches of every live tracker (only = -1) or of one, into `touch` (indexed as the
/// trackers): one pass over the contacts.
void scanContacts(World& world, int32_t only, std::vector<TrackerTouch>& touch) {
    touch.assign(world.trackers.list.size(), TrackerTouch{});
    const auto& pairs = world.contacts.pairs;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        const Pair& p = pairs[i];
        if (!p.active) continue;
        int32_t k1 = trackerOfSlot(world, p.end1);
        int32_t k2 = p.wall ? -1 : trackerOfSlot(world, p.end2);
        if (only >= 0) {
            if (k1 != only) k1 = -1;
            if (k2 != only) k2 = -1;
        }
        if (k1 < 0 && k2 < 0) continue;
        // The geometry now, as a contact query reports it (a pair is active from its first
        // touch until it ends, which for a model with an activity distance may be apart).
        Vec2 normal, point;
        double overlap = 0.0;
        if (!pairGeometry(world, p, normal, overlap, point) || !(overlap > 0.0)) continue;
        // The normal runs from end 1 to end 2: toward end 1 from what it touches is -normal.
        if (k1 >= 0) noteTouch(world, touch, k1, p, false, -normal, point);
        if (k2 >= 0) noteTouch(world, touch, k2, p, true, normal, point);
    }
}

void closeImpact(Tracker& t, const TrackedState& at, bool ended) {
    if (t.open_impact < 0) return;
    TrackedImpact& imp = t.impacts[static_cast<std::size_t>(t.open_impact)];
    imp.closed = true;
    imp.ended = ended;
    imp.end = at;
    t.open_impact = -1;
}

/// The lines crossed between the last sample and `now`, from line `from` on. Returns true when
/// a line with an event was crossed (the sample halts there until the handler has run).
bool crossLines(World& world, Tracker& t, const TrackedState& now, bool touched, bool gravity_only,
                double mass, double inertia, std::size_t from) {
    const TrackedState& last = t.last;
    for (std::size_t j = from; j < t.def.lines.size(); ++j) {
        const TrackLine& line = t.def.lines[j];
        const Vec2& u = t.line_dir[j];
        // Signed distances from the line, positive on its right (the right-hand normal (u_y,
        // -u_x)). For a line along +y this is x - x_line exactly, whatever the other terms.
        const double nx = u.y(), ny = -u.x();
        const double d0 = nx * (last.pos.x() - line.from.x()) + ny * (last.pos.y() - line.from.y());
        const double d1 = nx * (now.pos.x() - line.from.x()) + ny * (now.pos.y() - line.from.y());
        if (!(d0 < 0.0 && d1 >= 0.0)) continue;
        // Within a step the centre moves on a straight line (central differences at the half-step
        // velocity): the chord gives the fraction s of the step at the line.
        const double s = -d0 / (d1 - d0);
        const double qx = last.pos.x() + s * (now.pos.x() - last.pos.x());
        const double qy = last.pos.y() + s * (now.pos.y() - last.pos.y());
        const double along = u.x() * (qx - line.from.x()) + u.y() * (qy - line.from.y());
        if (along < 0.0 || along > t.line_length[j]) continue;
        // The state at the line (step/crossing.hpp): the acceleration is gravity in free flight
        // at both samples, else the change of the half-step velocity over the interval.
        const double dt = now.time - last.time;
        double ax = 0.0, ay = 0.0;
        if (gravity_only && !touched && !t.last_touched) {
            ax = world.settings.gravity.x(), ay = world.settings.gravity.y();
        } else {
            ax = (now.vel.x() - last.vel.x()) / dt, ay = (now.vel.y() - last.vel.y()) / dt;
        }
        const CrossingState at = crossingAt(last.pos, last.spin, now.pos, now.spin, s, dt, ax, ay);
        TrackedCrossing c;
        c.line = static_cast<int32_t>(j);
        c.time = last.time + s * dt;
        c.pos = at.pos, c.vel = at.vel, c.spin = at.spin;
        c.ke_trans = translational(mass, c.vel);
        c.ke_rot = rotational(inertia, c.spin);
        t.crossings.push_back(c);
        if (line.event && world.trackers.handler) {
            t.halted = true;
            t.resume_line = static_cast<int32_t>(j + 1);
            return true;
        }
    }
    return false;
}

/// The rest of a sample after its lines: envelope, path, the sample becomes the last one, then
/// the end rules (region, rest, time) in that order.
void finishSample(World& world, std::size_t k, const TrackedState& now, bool touched, double ke) {
    Tracker& t = world.trackers.list[k];
    const TrackerDef& d = t.def;
    if (d.envelope_bins > 0) {
        const double bin = std::floor((now.pos.x() - d.envelope_x0) / d.envelope_dx);
        if (bin >= 0.0 && bin < static_cast<double>(d.envelope_bins)) {
            const auto b = static_cast<std::size_t>(bin);
            const double h = now.pos.y() - groundHeight(d.ground, now.pos.x(), &t.ground_segment);
            if (std::isnan(t.envelope_height[b]) || h > t.envelope_height[b])
                t.envelope_height[b] = h;
            if (std::isnan(t.envelope_energy[b]) || ke > t.envelope_energy[b])
                t.envelope_energy[b] = ke;
        }
    }
    if (d.path_every > 0 && (t.samples - 1) % d.path_every == 0)
        t.path.push_back(TrackedPoint{now.time, now.pos});
    t.last = now;
    t.last_touched = touched;
    t.has_last = true;
    const Vec2& p = now.pos;
    if (d.region && (p.x() < d.region_lo.x() || p.x() > d.region_hi.x() ||
                     p.y() < d.region_lo.y() || p.y() > d.region_hi.y())) {
        endTracker(world, k, TrackerState::Exit);
    } else if (!std::isnan(d.rest_energy) || !std::isnan(d.rest_speed)) {
        const bool slow =
            !std::isnan(d.rest_energy) ? ke < d.rest_energy : now.vel.norm() < d.rest_speed;
        if (slow) {
            if (std::isnan(t.rest_since)) t.rest_since = now.time;
            if (now.time - t.rest_since >= d.rest_time) endTracker(world, k, TrackerState::Rest);
        } else {
            t.rest_since = kNotSet;
        }
    }
    if (t.state == TrackerState::Tracking && now.time >= d.end_time)
        endTracker(world, k, TrackerState::Time);
}

/// One sample of tracker k with this step's touches; may halt at a line with an event.
void takeSample(World& world, std::size_t k, const TrackerTouch& touch) {
    Tracker& t = world.trackers.list[k];
    const BodyNow b = readBody(world, t);
    const TrackedState& now = b.state;
    const double ke = translational(b.mass, now.vel) + rotational(b.inertia, now.spin);
    ++t.samples;
    if (t.def.impacts != TrackImpacts::Off) {
        if (touch.kind && !t.touching) {
            // The velocity is the incoming one: the contact's first force acts at the next step.
            const double approach =
                -(now.vel.x() * touch.normal.x() + now.vel.y() * touch.normal.y());
            if (approach >= t.def.impact_min_speed) {
                TrackedImpact imp;
                imp.normal = touch.normal;
                imp.point = touch.point;
                imp.wall = touch.wall;
                imp.segment = touch.segment;
                imp.ball = touch.ball;
                imp.clump = touch.clump;
                imp.groups = touch.groups;
                imp.start = now;
                imp.approach = approach;
                t.impacts.push_back(imp);
                t.open_impact = static_cast<int32_t>(t.impacts.size() - 1);
            }
        } else if (!touch.kind && t.touching) {
            // The first sample without the touch: its velocity holds the touch's last force.
            closeImpact(t, now, true);
        }
        t.touching = touch.kind;
    }
    if (t.has_last && crossLines(world, t, now, touch.any, b.gravity_only, b.mass, b.inertia, 0)) {
        t.pending = now;
        t.pending_touched = touch.any;
        t.pending_free = b.gravity_only;
        t.pending_ke = ke;
        t.pending_mass = b.mass;
        t.pending_inertia = b.inertia;
        return;
    }
    finishSample(world, k, now, touch.any, ke);
}

/// The rest of a sample that halted at a line (after the handler, which did not stop it).
void resumeSample(World& world, std::size_t k) {
    Tracker& t = world.trackers.list[k];
    t.halted = false;
    const TrackedState now = t.pending;
    if (crossLines(world, t, now, t.pending_touched, t.pending_free, t.pending_mass,
                   t.pending_inertia, static_cast<std::size_t>(t.resume_line)))
        return;
    finishSample(world, k, now, t.pending_touched, t.pending_ke);
}

void deliver(World& world, const TrackerEvent& e) {
    if (!world.trackers.handler) return;
    const auto fn = world.trackers.handler;  // copy: the handler may replace itself
    fn(e);
}

void deliverEnd(World& world, std::size_t k) {
    TrackerEvent e;
    e.kind = TrackerEvent::End;
    e.tracker = static_cast<int>(k + 1);
    e.state = world.trackers.list[k].state;
    deliver(world, e);
}

}  // namespace

bool trackedBodyAlive(const World& world, const Tracker& t) {
    if (t.clump.valid()) {
        const auto& cl = world.bodies.clumps;
        return t.clump.index <= cl.size() && cl[t.clump.index - 1].alive &&
               cl[t.clump.index - 1].generation == t.clump.generation;
    }
    // A ball made a pebble of a clump since (Model::createClumpFromBalls) is gone as a body.
    return world.bodies.isAlive(t.ball) &&
           world.bodies.balls.clump[world.bodies.slot_of[t.ball.index - 1]] == kNoClump;
}

double groundHeight(const std::vector<Vec2>& pts, double x, std::size_t* hint) {
    const std::size_t n = pts.size();
    if (x <= pts[0].x()) return pts[0].y();
    if (x >= pts[n - 1].x()) return pts[n - 1].y();
    // The segment lo..lo+1 with x(lo) < x <= x(lo+1), which is unique: the one looked up last
    // (a body moves little in a step), else by bisection.
    std::size_t lo = 0, hi = n - 1;
    if (hint && *hint + 1 < n && pts[*hint].x() < x && x <= pts[*hint + 1].x()) {
        lo = *hint, hi = *hint + 1;
    } else {
        while (hi - lo > 1) {
            const std::size_t mid = (lo + hi) / 2;
            if (pts[mid].x() < x)
                lo = mid;
            else
                hi = mid;
        }
        if (hint) *hint = lo;
    }
    const Vec2& a = pts[lo];
    const Vec2& b = pts[hi];
    if (b.x() == a.x()) return std::min(a.y(), b.y());
    return a.y() + (b.y() - a.y()) * (x - a.x()) / (b.x() - a.x());
}

void endTracker(World& world, std::size_t k, TrackerState state) {
    Trackers& tr = world.trackers;
    Tracker& t = tr.list[k];
    if (t.state != TrackerState::Tracking) return;
    t.state = state;
    t.halted = false;
    closeImpact(t, t.last, false);
    if (t.clump.valid()) {
        if (t.clump.index - 1 < tr.by_clump.size()) tr.by_clump[t.clump.index - 1] = -1;
    } else if (t.ball.index - 1 < tr.by_ball.size()) {
        tr.by_ball[t.ball.index - 1] = -1;
    }
    --tr.live;
}

void firstTrackerSample(World& world, std::size_t index) {
    // Its own scratch: a tracker made by a handler must not overwrite this step's touches.
    std::vector<TrackerTouch> touch;
    scanContacts(world, static_cast<int32_t>(index), touch);
    takeSample(world, index, touch[index]);
}

void updateTrackers(World& world) {
    Trackers& tr = world.trackers;
    const std::size_t n = tr.list.size();
    for (std::size_t k = 0; k < n; ++k) {
        if (tr.list[k].state != TrackerState::Tracking || trackedBodyAlive(world, tr.list[k]))
            continue;
        endTracker(world, k, TrackerState::Deleted);
        deliverEnd(world, k);
    }
    if (tr.live == 0) return;
    scanContacts(world, -1, tr.touch);
    ++tr.updating;
    struct Done {  // also when a handler throws
        Trackers& tr;
        ~Done() { --tr.updating; }
    } done{tr};
    // Handlers may create trackers (sampled from the next step) and delete bodies (their
    // trackers end here): indices, not references, across the calls.
    for (std::size_t k = 0; k < n; ++k) {
        if (tr.list[k].state != TrackerState::Tracking) continue;
        if (!trackedBodyAlive(world, tr.list[k])) {
            endTracker(world, k, TrackerState::Deleted);
            deliverEnd(world, k);
            continue;
        }
        takeSample(world, k, tr.touch[k]);
        while (tr.list[k].halted) {
            TrackerEvent e;
            e.kind = TrackerEvent::Crossing;
            e.tracker = static_cast<int>(k + 1);
            e.line = tr.list[k].resume_line - 1;
            deliver(world, e);
            if (tr.list[k].state != TrackerState::Tracking) break;  // stopped by the handler
            resumeSample(world, k);
        }
        // Ended by its own rules at this sample (one the handler stopped gets no event).
        const TrackerState s = tr.list[k].state;
        if (s == TrackerState::Rest || s == TrackerState::Exit || s == TrackerState::Time)
            deliverEnd(world, k);
    }
}

}  // namespace talus
