// SPDX-License-Identifier: MIT
//
// Trackers (Model::createTracker; docs/lua-api.md, "Trackers") against closed forms. A tracker
// samples its body once per step, at the end of the step, so what it sees of a continuous event
// is bounded by one step: the tolerances below are one step's worth of the quantity (a time dt,
// a speed g dt), or round-off where the sample is exact (free flight, constant velocity).
//
//   drop onto a floor   touch at T = sqrt(2 h / g) with speed sqrt(2 g h) (h the gap): the first
//                       sample with an overlap is the first step end after T, and its velocity is
//                       the half-step velocity of the step that closed the gap, g (t - dt/2)
//   the touch's end     a linear spring under gravity touches for (pi + 2 asin(d / A)) / w,
//                       w = sqrt(kn / m), d = m g / kn its static overlap, A = sqrt(d^2 +
//                       (v / w)^2) the amplitude about it (longer than half a period by d)
//   line crossings      in free flight the interpolated state is the parabola's (round-off); a
//                       disk rolling without slipping keeps its speed and spin exactly (no shear
//                       force arises), so it crosses x = c at (c - x0) / v
//   rest                a disk sliding with its spin fixed decelerates at mu g and stops after
//                       v0^2 / (2 mu g), up to the shear spring's stretch when it sticks
#include <catch2/catch.hpp>
#include <cmath>

#include "talus/save_file.hpp"
#include "test_support.hpp"

using namespace talus;
using namespace talus::test;

namespace {

constexpr double kG = 9.81, kRadius = 0.1, kDensity = 2600.0;
constexpr double kEps = std::numeric_limits<double>::epsilon();

/// A floor (wall from x = -50 to 50 m at y = 0) and gravity -g.
std::unique_ptr<Model> floorModel(const std::vector<PropValue>& props, double dt) {
    auto m = makeModel(Vec2(0.0, -kG), props);
    m->timestep() = fixedStep(dt);
    m->createWall(wallOf({Vec2(-50.0, 0.0), Vec2(50.0, 0.0)}));
    return m;
}

TrackerDef impactsOnly(TrackImpacts kind = TrackImpacts::Walls) {
    TrackerDef d;
    d.impacts = kind;
    return d;
}

}  // namespace

TEST_CASE("a dropped ball's impact: time, speed and duration", "[core][trackers]") {
    const double kn = 1e7, h = 2.0;
    for (double dt : {1e-4, 3.7e-4}) {
        auto m = floorModel(linearProps(kn), dt);
        const BallId b = m->createBall(ballAt(Vec2(0.3, h + kRadius), kRadius, kDensity));
        const int id = m->createTracker(b, impactsOnly());
        m->solveTime(0.9);
        const auto& imps = m->trackerImpacts(id);
        REQUIRE(imps.size() == 1);
        const TrackedImpact& imp = imps[0];
        const double T = std::sqrt(2.0 * h / kG), v = std::sqrt(2.0 * kG * h);
        INFO("dt " << dt << ": impact at " << imp.start.time << " s (free fall " << T
                   << " s), approach " << imp.approach << " m/s (" << v << ")");
        // The first step end after the touch.
        CHECK(imp.start.time > T);
        CHECK(imp.start.time <= T + dt * (1.0 + 1e-9));
        // Its velocity is the free-flight half-step velocity of the step that closed the gap,
        // exact to round-off, hence within g dt / 2 of the speed at the touch.
        CHECK(imp.approach == Approx(kG * (imp.start.time - 0.5 * dt)).epsilon(1e-12));
        CHECK(std::fabs(imp.approach - v) <= 0.5 * kG * dt + 1e-12);
        CHECK(imp.normal.x() == Approx(0.0).margin(1e-12));
        CHECK(imp.normal.y() == Approx(1.0).epsilon(1e-15));  // from the floor toward the ball
        CHECK(imp.wall.valid());
        CHECK(imp.segment == 0);
        CHECK(imp.start.pos.x() == 0.3);
        // Undamped: it leaves with about the speed it came with, after the spring's contact
        // time under gravity; both ends of the touch are sampled to one step.
        REQUIRE(imp.closed);
        CHECK(imp.ended);
        const double mass = m->ballMass(b), w = std::sqrt(kn / mass), d = mass * kG / kn;
        const double A = std::sqrt(d * d + (v / w) * (v / w));
        const double duration = (M_PI + 2.0 * std::asin(d / A)) / w;
        const double measured = imp.end.time - imp.start.time;
        INFO("touch lasted " << measured << " s, closed form " << duration << " s");
        CHECK(std::fabs(measured - duration) <= dt * (1.0 + 1e-9));
        CHECK(imp.end.vel.y() == Approx(v).epsilon(0.02));
        report("drop dt %g: impact %.6f s (T %.6f), approach %.6f (v %.6f), duration %.6f (%.6f)\n",
               dt, imp.start.time, T, imp.approach, v, measured, duration);
    }
}

TEST_CASE("impacts slower than min_speed are not recorded; the touch still counts",
          "[core][trackers]") {
    auto m = floorModel(linearProps(1e7, 0.0, 0.0, 0.9), 1e-4);  // heavily damped: one bounce
    const BallId b = m->createBall(ballAt(Vec2(0.0, 0.5 + kRadius), kRadius, kDensity));
    TrackerDef d = impactsOnly();
    d.impact_min_speed = std::sqrt(2.0 * kG * 0.5) + 0.1;  // above the drop's speed
    const int id = m->createTracker(b, d);
    m->solveTime(1.0);
    CHECK(m->trackerImpacts(id).empty());
    d.impact_min_speed = 1.0;
    auto m2 = floorModel(linearProps(1e7, 0.0, 0.0, 0.9), 1e-4);
    const BallId b2 = m2->createBall(ballAt(Vec2(0.0, 0.5 + kRadius), kRadius, kDensity));
    const int id2 = m2->createTracker(b2, d);
    m2->solveTime(1.0);
    REQUIRE(m2->trackerImpacts(id2).size() == 1);  // the rebound is slower than 1 m/s
}

TEST_CASE("a ball crossing a line in free flight: the parabola's state", "[core][trackers]") {
    // Exact for any step: the samples lie on the parabola (free fall is exact to round-off,
    // test_free_fall.cpp) and the interpolation is the parabola through them.
    auto m = makeModel(Vec2(0.0, -kG), linearProps(1e7));
    m->timestep() = fixedStep(7.3e-3);
    const Vec2 x0(0.0, 10.0), v0(3.0, 4.0);
    const BallId b = m->createBall(ballAt(x0, kRadius, kDensity, v0));
    TrackerDef d;
    const double c = 2.2;  // the line x = c, crossed toward +x (from below to above)
    d.lines.push_back(TrackLine{Vec2(c, -100.0), Vec2(c, 100.0), false});
    d.lines.push_back(TrackLine{Vec2(c + 1.0, 100.0), Vec2(c + 1.0, -100.0), false});  // reversed
    const int id = m->createTracker(b, d);
    m->cycle(300);
    const auto& cs = m->trackerCrossings(id);
    REQUIRE(cs.size() == 1);  // the reversed line counts crossings toward -x only
    const double t = (c - x0.x()) / v0.x();
    const TrackedCrossing& k = cs[0];
    CHECK(k.line == 0);
    CHECK(k.time == Approx(t).epsilon(1e-12));
    CHECK(k.pos.x() == Approx(c).epsilon(1e-12));
    CHECK(k.pos.y() == Approx(x0.y() + v0.y() * t - 0.5 * kG * t * t).epsilon(1e-12));
    CHECK(k.vel.x() == Approx(v0.x()).epsilon(1e-12));
    CHECK(k.vel.y() == Approx(v0.y() - kG * t).epsilon(1e-11));
    const double mass = m->ballMass(b);
    CHECK(k.ke_trans == Approx(0.5 * mass * k.vel.squaredNorm()).epsilon(1e-15));
    CHECK(k.ke_rot == 0.0);
}

TEST_CASE("a disk rolling across a line: time, speed and spin", "[core][trackers]") {
    // Rolling without slipping (v = -w r) no shear force arises and the disk keeps its speed.
    // Its contact point sits d/2 inside the rim (d = m g / kn, the static overlap), so it rolls
    // on r - d/2: speed and spin settle within d/r of the set values, and the crossing time with
    // them.
    const double kn = 1e8, dt = 2e-5, v = 2.0;
    auto m = floorModel(linearProps(kn, 0.5 * kn, 0.5, 0.7), dt);
    const BallId b = m->createBall(ballAt(Vec2(0.0, kRadius), kRadius, kDensity));
    // Settle onto the floor first (damped), then roll.
    m->solveTime(0.2);
    m->setBallVel(b, Vec2(v, 0.0));
    m->setBallSpin(b, -v / kRadius);
    const double t0 = m->time(), x0 = m->ballPos(b).x();
    const double rel = 2.0 * m->ballMass(b) * kG / kn / kRadius;  // 2 d / r
    TrackerDef d;
    const double c = 1.0;
    d.lines.push_back(TrackLine{Vec2(c, -1.0), Vec2(c, 1.0), false});
    const int id = m->createTracker(b, d);
    m->solveTime(0.8);
    const auto& cs = m->trackerCrossings(id);
    REQUIRE(cs.size() == 1);
    const TrackedCrossing& k = cs[0];
    const double t = (c - x0) / v;
    CHECK(std::fabs(k.time - (t0 + t)) <= rel * t);
    // On the line to the interpolation's own error in contact: a dt^2 / 8 with the measured
    // acceleration (the velocity's change over a step, round-off here).
    CHECK(k.pos.x() == Approx(c).margin(1e-9));
    CHECK(k.vel.x() == Approx(v).epsilon(rel));
    CHECK(std::fabs(k.vel.y()) <= rel * v);
    CHECK(k.spin == Approx(-v / kRadius).epsilon(rel));
    const double inertia = m->ballInertia(b);
    CHECK(k.ke_rot == Approx(0.5 * inertia * k.spin * k.spin).epsilon(1e-15));
    report("rolling: crossed at %.9f s (exact %.9f, tolerance %.2e), v %.12f, spin %.9f\n", k.time,
           t0 + t, rel * t, k.vel.x(), k.spin);
}

TEST_CASE("a sliding disk comes to rest where friction stops it", "[core][trackers]") {
    const double kn = 1e8, ks = 5e7, mu = 0.4, dt = 2e-5, v0 = 3.0, v_rest = 0.02, t_rest = 0.2;
    // dp_mode 2: no shear dashpot while sliding (it would add to the friction force).
    auto m = floorModel(linearProps(kn, ks, mu, 0.7, 0.7, 2), dt);
    const BallId b = m->createBall(ballAt(Vec2(-2.0, kRadius), kRadius, kDensity));
    m->setBallFixity(b, kFixSpin);  // slides: no rolling
    m->solveTime(0.2);              // settled on the floor (damped)
    const Vec2 p0 = m->ballPos(b);
    const double t0 = m->time();
    m->setBallVel(b, Vec2(v0, 0.0));
    TrackerDef d;
    d.rest_speed = v_rest;
    d.rest_time = t_rest;
    d.end_time = t0 + 10.0;
    const int id = m->createTracker(b, d);
    while (m->trackerStatus(id).state == TrackerState::Tracking) m->cycle(1000);
    const TrackerStatus s = m->trackerStatus(id);
    REQUIRE(s.state == TrackerState::Rest);
    const double mass = m->ballMass(b);
    const double stop = p0.x() + v0 * v0 / (2.0 * mu * kG);
    // Coulomb sliding at a constant deceleration is integrated exactly; where it sticks the
    // shear spring holds up to the friction force, a stretch of mu m g / ks (and it rings
    // within that). The push is a half-step velocity and friction acts from the step after it:
    // up to one step of travel, v0 dt, more.
    const double stretch = mu * mass * kG / ks;
    INFO("rest at x = " << s.last.pos.x() << ", friction stops it at " << stop << " (stretch "
                        << stretch << ")");
    CHECK(std::fabs(s.last.pos.x() - stop) <= 2.0 * stretch + v0 * dt);
    CHECK(s.last.pos.y() == Approx(p0.y()).epsilon(1e-9));
    // Slow from when the speed fell below v_rest, (v0 - v_rest) / (mu g) after the push (the
    // spring's ringing after it sticks stays below mu g / sqrt(ks / m) = 5e-3 m/s < v_rest),
    // and ended rest_time later, at the first step after it.
    const double slow = t0 + (v0 - v_rest) / (mu * kG);
    CHECK(std::fabs(s.rest_since - slow) <= 2.0 * dt);
    CHECK(s.last.time >= s.rest_since + t_rest);
    CHECK(s.last.time <= s.rest_since + t_rest + dt * (1.0 + 1e-9));
    report("rest: x %.6f (stop %.6f, stretch %.2e), since %.6f (%.6f)\n", s.last.pos.x(), stop,
           stretch, s.rest_since, slow);
}

TEST_CASE("a clump's impact is one touch, whichever pebbles touch", "[core][trackers]") {
    auto m = floorModel(linearProps(1e7, 0.0, 0.0, 0.5), 1e-4);
    ClumpDef cd;
    cd.pebbles = {Pebble{Vec2(-0.15, 0.0), 0.1}, Pebble{Vec2(0.15, 0.0), 0.1},
                  Pebble{Vec2(0.0, 0.1), 0.1}};
    cd.pos = Vec2(0.0, 1.0);
    cd.density = kDensity;
    const ClumpId c = m->createClump(cd);
    const int id = m->createTracker(c, impactsOnly());
    m->solveTime(0.6);
    const auto& imps = m->trackerImpacts(id);
    // Both lower pebbles reach the floor at the same step (the clump falls flat): one impact.
    REQUIRE(!imps.empty());
    CHECK(imps[0].start.pos.x() == Approx(m->clumpPos(c).x()).margin(1e-9));
    CHECK(imps[0].normal.y() == 1.0);
    for (std::size_t k = 1; k < imps.size(); ++k)
        CHECK(imps[k].start.time > imps[k - 1].end.time);  // touches do not overlap
    // A pebble cannot be tracked alone.
    const auto pebbles = m->clumpPebbleIds(c);
    CHECK_THROWS_WITH(
        m->createTracker(pebbles[0], TrackerDef{}),
        Catch::Contains("is a pebble of clump") && Catch::Contains("track the clump"));
}

TEST_CASE("impacts of bodies, and of walls only", "[core][trackers]") {
    // Ball a falls onto ball b resting on the floor: a's impacts with bodies see b, with walls
    // nothing (a never reaches the floor).
    auto m = floorModel(linearProps(1e7, 0.0, 0.0, 0.7), 1e-4);
    const BallId b = m->createBall(ballAt(Vec2(0.0, kRadius), kRadius, kDensity));
    m->addBallGroup(b, "target");
    const BallId a = m->createBall(ballAt(Vec2(0.0, 1.0), kRadius, kDensity));
    TrackerDef bodies = impactsOnly(TrackImpacts::Bodies);
    const int ia = m->createTracker(a, bodies);
    const int ib = m->createTracker(b, impactsOnly(TrackImpacts::Walls));
    m->solveTime(0.5);
    const auto& ra = m->trackerImpacts(ia);
    REQUIRE(!ra.empty());
    CHECK(ra[0].ball == b);
    CHECK(!ra[0].wall.valid());
    CHECK(ra[0].normal.y() == Approx(1.0).margin(1e-9));  // from b toward a
    CHECK(ra[0].groups == (uint64_t(1) << m->groupIndex("target", false)));
    // b sits on the floor from the start: its touch began at its first sample, slower than
    // anything (approach 0): recorded with the default min_speed 0.
    const auto& rb = m->trackerImpacts(ib);
    REQUIRE(!rb.empty());
    CHECK(rb[0].wall.valid());
}

TEST_CASE("trackers only read: a tracked run is bit-identical to an untracked one",
          "[core][trackers]") {
    auto run = [](bool tracked) {
        auto m = floorModel(linearProps(1e7, 5e6, 0.5, 0.3), 1e-4);
        std::vector<BallId> balls;
        for (int k = 0; k < 6; ++k)
            balls.push_back(m->createBall(
                ballAt(Vec2(0.05 * k, 0.3 + 0.25 * k), kRadius, kDensity, Vec2(0.3, 0.0))));
        if (tracked) {
            TrackerDef d = impactsOnly(TrackImpacts::Any);
            d.lines.push_back(TrackLine{Vec2(0.2, -1.0), Vec2(0.2, 5.0), false});
            d.rest_speed = 0.01;
            d.rest_time = 0.1;
            d.envelope_bins = 10;
            d.envelope_x0 = -1.0;
            d.envelope_dx = 0.2;
            d.ground = {Vec2(-50.0, 0.0), Vec2(50.0, 0.0)};
            d.path_every = 7;
            for (BallId b : balls) m->createTracker(b, d);
        }
        m->cycle(4000);
        std::vector<double> out;
        for (BallId b : balls) {
            out.push_back(m->ballPos(b).x()), out.push_back(m->ballPos(b).y());
            out.push_back(m->ballVel(b).x()), out.push_back(m->ballSpin(b));
        }
        return out;
    };
    CHECK(run(true) == run(false));
}

TEST_CASE("a tracked body that is deleted ends its tracker; its records stay", "[core][trackers]") {
    auto m = floorModel(linearProps(1e7), 1e-4);
    const BallId b = m->createBall(ballAt(Vec2(0.0, 0.3), kRadius, kDensity));
    const int id = m->createTracker(b, impactsOnly());
    std::vector<TrackerEvent> events;
    m->setTrackerHandler([&](const TrackerEvent& e) { events.push_back(e); });
    m->solveTime(0.3);
    REQUIRE(m->trackerImpacts(id).size() >= 1);
    const std::size_t n = m->trackerImpacts(id).size();
    m->deleteBall(b);
    m->cycle(1);
    CHECK(m->trackerStatus(id).state == TrackerState::Deleted);
    CHECK(m->trackerImpacts(id).size() == n);
    REQUIRE(events.size() == 1);
    CHECK(events[0].kind == TrackerEvent::End);
    CHECK(events[0].state == TrackerState::Deleted);
    // A stale id is refused with the engine's own message.
    CHECK_THROWS_WITH(m->createTracker(b, TrackerDef{}), Catch::Contains("was deleted"));
}

TEST_CASE("an event line halts the sample until the handler has run", "[core][trackers]") {
    // The handler stops the tracker at the first line: the second line, just behind it and
    // crossed in the same step, is not looked at, and no later sample is taken.
    auto m = makeModel(Vec2(0.0, 0.0), linearProps(1e7));
    m->timestep() = fixedStep(1e-2);
    const BallId b = m->createBall(ballAt(Vec2(0.0, 0.0), kRadius, kDensity, Vec2(1.0, 0.0)));
    TrackerDef d;
    d.lines.push_back(TrackLine{Vec2(0.5, -1.0), Vec2(0.5, 1.0), true});
    d.lines.push_back(TrackLine{Vec2(0.501, -1.0), Vec2(0.501, 1.0), false});
    d.lines.push_back(TrackLine{Vec2(0.7, -1.0), Vec2(0.7, 1.0), false});
    const int id = m->createTracker(b, d);
    int calls = 0;
    m->setTrackerHandler([&](const TrackerEvent& e) {
        ++calls;
        CHECK(e.kind == TrackerEvent::Crossing);
        CHECK(e.line == 0);
        CHECK(m->trackerCrossings(id).back().line == 0);
        m->stopTracker(e.tracker);
    });
    m->cycle(100);
    CHECK(calls == 1);
    CHECK(m->trackerCrossings(id).size() == 1);
    CHECK(m->trackerStatus(id).state == TrackerState::Stopped);
    // Without a stop, the rest of the sample follows: both near lines are crossed.
    const BallId b2 = m->createBall(ballAt(Vec2(0.0, 0.5), kRadius, kDensity, Vec2(1.0, 0.0)));
    const int id2 = m->createTracker(b2, d);
    m->setTrackerHandler([&](const TrackerEvent&) {});
    m->cycle(100);
    CHECK(m->trackerCrossings(id2).size() == 3);
}

TEST_CASE("trackers refuse bad input with clear errors", "[core][trackers]") {
    auto m = floorModel(linearProps(1e7), 1e-4);
    const BallId b = m->createBall(ballAt(Vec2(0.0, 1.0), kRadius, kDensity));
    TrackerDef d;
    d.lines.push_back(TrackLine{Vec2(1.0, 2.0), Vec2(1.0, 2.0), false});
    CHECK_THROWS_WITH(m->createTracker(b, d),
                      Catch::Contains("lines[1] has zero length") && Catch::Contains("(1, 2)"));
    d = TrackerDef{};
    d.rest_speed = 0.1;
    d.rest_energy = 1.0;
    CHECK_THROWS_WITH(m->createTracker(b, d), Catch::Contains("energy or speed, not both"));
    d = TrackerDef{};
    d.rest_speed = -1.0;
    CHECK_THROWS_WITH(m->createTracker(b, d), Catch::Contains("rest.speed"));
    d = TrackerDef{};
    d.region = true;
    d.region_lo = Vec2(1.0, 0.0);
    d.region_hi = Vec2(0.0, 1.0);
    CHECK_THROWS_WITH(m->createTracker(b, d), Catch::Contains("region needs lo <= hi"));
    d = TrackerDef{};
    d.envelope_bins = 4;
    d.envelope_dx = 1.0;
    d.ground = {Vec2(0.0, 0.0), Vec2(-1.0, 0.0)};
    CHECK_THROWS_WITH(m->createTracker(b, d), Catch::Contains("x must not decrease"));
    d.ground = {Vec2(0.0, 0.0), Vec2(1.0, 0.0)};
    d.envelope_dx = 0.0;
    CHECK_THROWS_WITH(m->createTracker(b, d), Catch::Contains("envelope.dx"));
    CHECK(m->trackerCount() == 0);  // nothing was made by a refused call
    const int id = m->createTracker(b, TrackerDef{});
    CHECK_THROWS_WITH(m->createTracker(b, TrackerDef{}),
                      Catch::Contains("already has a live tracker (tracker 1)"));
    CHECK_THROWS_WITH(m->trackerStatus(id + 1), Catch::Contains("tracker 2 does not exist"));
    m->stopTracker(id);
    CHECK_NOTHROW(m->createTracker(b, TrackerDef{}));  // a stopped tracker frees the body
}

TEST_CASE("the envelope keeps the greatest height and energy per bin", "[core][trackers]") {
    // A projectile over flat ground: in each bin the greatest height is the parabola's greatest
    // sampled height there, and the energy is constant (free flight, no spin).
    auto m = makeModel(Vec2(0.0, -kG), linearProps(1e7));
    const double dt = 1e-3;
    m->timestep() = fixedStep(dt);
    const Vec2 v0(2.0, 5.0);
    const BallId b = m->createBall(ballAt(Vec2(0.0, 1.0), kRadius, kDensity, v0));
    TrackerDef d;
    d.envelope_bins = 4;
    d.envelope_x0 = 0.0;
    d.envelope_dx = 0.5;
    d.ground = {Vec2(-10.0, 0.5), Vec2(10.0, 0.5)};
    const int id = m->createTracker(b, d);
    m->cycle(900);  // until x = 1.8 (bins 0..3)
    const auto& hmax = m->trackerEnvelopeHeight(id);
    const auto& emax = m->trackerEnvelopeEnergy(id);
    REQUIRE(hmax.size() == 4);
    // The apex (t = v_y / g, x = 1.019 m) is in bin 2: its height is the apex's within one
    // step's rise there (g dt^2 / 2).
    const double apex = 1.0 + v0.y() * v0.y() / (2.0 * kG) - 0.5;
    CHECK(std::fabs(hmax[2] - apex) <= 0.5 * kG * dt * dt + 1e-12);
    const double ke = 0.5 * m->ballMass(b) * v0.squaredNorm();  // the release's: the greatest
    CHECK(emax[0] == Approx(ke).epsilon(1e-12));
    for (std::size_t k = 0; k < 4; ++k) {
        CHECK(!std::isnan(hmax[k]));
        CHECK(emax[k] <= ke * (1.0 + 1e-12));
    }
}

TEST_CASE("a model with trackers refuses to save", "[core][trackers]") {
    auto m = floorModel(linearProps(1e7), 1e-4);
    const BallId b = m->createBall(ballAt(Vec2(0.0, 1.0), kRadius, kDensity));
    m->createTracker(b, TrackerDef{});
    SaveWriter w;
    CHECK_THROWS_WITH(m->saveState(w), Catch::Contains("tracker(s), which are not saved"));
    m->clearTrackers();
    CHECK_NOTHROW(m->saveState(w));
}
