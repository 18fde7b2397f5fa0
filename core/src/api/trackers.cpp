// SPDX-License-Identifier: MIT
//
// The facade, trackers: creating one on a ball or a clump (with every option checked), stopping
// and forgetting them, and reading their records (docs/lua-api.md, "Trackers"). The data is
// world/trackers.hpp, the per-step sample step/trackers.cpp.
#include "step/trackers.hpp"

#include <cmath>
#include <string>

#include "api/input_checks.hpp"
#include "talus/errors.hpp"
#include "talus/model.hpp"
#include "world/body_store.hpp"
#include "world/messages.hpp"

namespace talus {

const char* trackerStateName(TrackerState s) {
    switch (s) {
        case TrackerState::Tracking:
            return "tracking";
        case TrackerState::Rest:
            return "rest";
        case TrackerState::Exit:
            return "exit";
        case TrackerState::Time:
            return "time";
        case TrackerState::Deleted:
            return "deleted";
        case TrackerState::Stopped:
            return "stopped";
    }
    return "?";
}

namespace {

std::string num(double v) { return messageNumber(v); }

/// Refuses what a tracker cannot use, naming the option ("tracker: ...").
void checkDef(const TrackerDef& d) {
    if (!(d.impact_min_speed >= 0.0) || !std::isfinite(d.impact_min_speed))
        throw InputError("tracker: impacts.min_speed must be a finite speed >= 0 m/s (got " +
                         num(d.impact_min_speed) + ")");
    for (std::size_t j = 0; j < d.lines.size(); ++j) {
        const std::string what = "tracker: lines[" + std::to_string(j + 1) + "]";
        requireCoordinate(what + ".from", d.lines[j].from);
        requireCoordinate(what + ".to", d.lines[j].to);
        if (!((d.lines[j].to - d.lines[j].from).norm() > 0.0))
            throw InputError(what + " has zero length (from " + vecText(d.lines[j].from) + " to " +
                             vecText(d.lines[j].to) + "): a line needs two distinct points");
    }
    const bool energy = !std::isnan(d.rest_energy), speed = !std::isnan(d.rest_speed);
    if (energy && speed) throw InputError("tracker: rest takes energy or speed, not both");
    if (energy && (!(d.rest_energy > 0.0) || !std::isfinite(d.rest_energy)))
        throw InputError("tracker: rest.energy must be a finite energy > 0 J (got " +
                         num(d.rest_energy) + ")");
    if (speed && (!(d.rest_speed > 0.0) || !std::isfinite(d.rest_speed)))
        throw InputError("tracker: rest.speed must be a finite speed > 0 m/s (got " +
                         num(d.rest_speed) + ")");
    if (!(d.rest_time >= 0.0) || !std::isfinite(d.rest_time))
        throw InputError("tracker: rest.time must be a finite time >= 0 s (got " +
                         num(d.rest_time) + ")");
    if (d.region) {
        // Infinite bounds are allowed (a region open to one side); NaN and lo > hi are not.
        const Vec2 &lo = d.region_lo, &hi = d.region_hi;
        if (std::isnan(lo.x()) || std::isnan(lo.y()) || std::isnan(hi.x()) || std::isnan(hi.y()) ||
            !(lo.x() <= hi.x()) || !(lo.y() <= hi.y()))
            throw InputError("tracker: region needs lo <= hi in x and y (got lo " + vecText(lo) +
                             ", hi " + vecText(hi) + ")");
    }
    if (std::isnan(d.end_time))
        throw InputError("tracker: time (the end time) must be a number of seconds (got nan)");
    if (d.envelope_bins < 0 || d.envelope_bins > 10000000)
        throw InputError("tracker: envelope.bins must be from 1 to 1e7 (got " +
                         std::to_string(d.envelope_bins) + ")");
    if (d.envelope_bins > 0) {
        if (!std::isfinite(d.envelope_x0))
            throw InputError("tracker: envelope.x0 must be finite (got " + num(d.envelope_x0) +
                             ")");
        if (!(d.envelope_dx > 0.0) || !std::isfinite(d.envelope_dx))
            throw InputError("tracker: envelope.dx must be a finite length > 0 m (got " +
                             num(d.envelope_dx) + ")");
        if (d.ground.size() < 2)
            throw InputError("tracker: envelope.ground needs at least 2 points (got " +
                             std::to_string(d.ground.size()) + ")");
        for (std::size_t k = 0; k < d.ground.size(); ++k) {
            requireCoordinate("tracker: envelope.ground point " + std::to_string(k + 1),
                              d.ground[k]);
            if (k > 0 && d.ground[k].x() < d.ground[k - 1].x())
                throw InputError("tracker: envelope.ground: x must not decrease (point " +
                                 std::to_string(k + 1) + " at x = " + num(d.ground[k].x()) +
                                 " follows x = " + num(d.ground[k - 1].x()) + ")");
        }
    }
    if (d.path_every < 0)
        throw InputError("tracker: path must be a number of samples >= 1 (got " +
                         std::to_string(d.path_every) + ")");
}

/// Adds a tracker for the body (ball or clump), fills what it derives from its def, and takes
/// its first sample.
int addTracker(World& world, BallId ball, ClumpId clump, const TrackerDef& def) {
    checkDef(def);
    Trackers& tr = world.trackers;
    Tracker t;
    t.def = def;
    t.ball = ball;
    t.clump = clump;
    for (const TrackLine& line : def.lines) {
        const Vec2 d = line.to - line.from;
        const double length = d.norm();
        t.line_dir.push_back(d / length);
        t.line_length.push_back(length);
    }
    if (def.envelope_bins > 0) {
        t.envelope_height.assign(static_cast<std::size_t>(def.envelope_bins), kNotSet);
        t.envelope_energy.assign(static_cast<std::size_t>(def.envelope_bins), kNotSet);
    }
    const auto index = static_cast<int32_t>(tr.list.size());
    std::vector<int32_t>& map = clump.valid() ? tr.by_clump : tr.by_ball;
    const std::size_t at = (clump.valid() ? clump.index : ball.index) - 1;
    if (map.size() <= at) map.resize(at + 1, -1);
    if (map[at] >= 0) {
        const std::string body = clump.valid() ? "clump " + std::to_string(clump.index)
                                               : "ball " + std::to_string(ball.index);
        throw InputError("tracker: " + body + " already has a live tracker (tracker " +
                         std::to_string(map[at] + 1) + "): stop it first");
    }
    tr.list.push_back(std::move(t));
    map[at] = index;
    ++tr.live;
    firstTrackerSample(world, static_cast<std::size_t>(index));
    return index + 1;
}

const Tracker& trackerAt(const World& world, int id) {
    if (id < 1 || static_cast<std::size_t>(id) > world.trackers.list.size())
        throw InputError("tracker " + std::to_string(id) + " does not exist (" +
                         std::to_string(world.trackers.list.size()) + " tracker(s))");
    return world.trackers.list[static_cast<std::size_t>(id - 1)];
}

}  // namespace

int Model::createTracker(BallId ball, const TrackerDef& def) {
    World& world = *m_world;
    const uint32_t s = world.bodies.slotOf(ball);  // throws for an unknown or stale id
    if (world.bodies.balls.clump[s] != kNoClump)
        throw InputError("tracker: ball " + std::to_string(ball.index) + " is a pebble of clump " +
                         std::to_string(world.bodies.balls.clump[s] + 1) + ": track the clump");
    return addTracker(world, ball, ClumpId{}, def);
}

int Model::createTracker(ClumpId clump, const TrackerDef& def) {
    World& world = *m_world;
    world.bodies.clumpIndex(clump);  // throws for an unknown or stale id
    return addTracker(world, BallId{}, clump, def);
}

void Model::stopTracker(int id) {
    World& world = *m_world;
    trackerAt(world, id);
    endTracker(world, static_cast<std::size_t>(id - 1), TrackerState::Stopped);
}

void Model::clearTrackers() {
    Trackers& tr = m_world->trackers;
    if (tr.updating > 0)
        throw InputError(
            "tracker: the trackers cannot be cleared inside a tracker event handler (stop the "
            "tracker there, clear them after the run call)");
    tr.list.clear();
    tr.by_ball.clear();
    tr.by_clump.clear();
    tr.touch.clear();
    tr.live = 0;
}

std::size_t Model::trackerCount() const { return m_world->trackers.list.size(); }

TrackerStatus Model::trackerStatus(int id) const {
    const Tracker& t = trackerAt(*m_world, id);
    TrackerStatus s;
    s.ball = t.ball;
    s.clump = t.clump;
    s.state = t.state;
    s.samples = t.samples;
    s.last = t.last;
    s.rest_since = t.rest_since;
    return s;
}

const TrackerDef& Model::trackerDef(int id) const { return trackerAt(*m_world, id).def; }
const std::vector<TrackedImpact>& Model::trackerImpacts(int id) const {
    return trackerAt(*m_world, id).impacts;
}
const std::vector<TrackedCrossing>& Model::trackerCrossings(int id) const {
    return trackerAt(*m_world, id).crossings;
}
const std::vector<double>& Model::trackerEnvelopeHeight(int id) const {
    return trackerAt(*m_world, id).envelope_height;
}
const std::vector<double>& Model::trackerEnvelopeEnergy(int id) const {
    return trackerAt(*m_world, id).envelope_energy;
}
const std::vector<TrackedPoint>& Model::trackerPath(int id) const {
    return trackerAt(*m_world, id).path;
}

void Model::setTrackerHandler(std::function<void(const TrackerEvent&)> fn) {
    m_world->trackers.handler = std::move(fn);
}

}  // namespace talus
