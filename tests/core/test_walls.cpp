// SPDX-License-Identifier: MIT
//
// Walls (accuracy-reference 3.3, core/src/narrowphase.hpp): end-point regions, shared vertices
// of a chain (convex: one contact, concave: two), crossing a vertex, and moving and rotating
// walls with energy tracing. All with the linear model and the default automatic step unless
// said otherwise.
//
// Common tolerances, from the single-impact measurements at the default step (test_bounce.cpp):
// an undamped impact resolved in 30 steps has |e - 1| <= 1e-4 (bound 2e-4 here); the sampled
// peak force reads low by at most 1 - cos(pi/60) = 1.4e-3 (bound 2e-3).
#include <catch2/catch.hpp>

#include "test_support.hpp"

using namespace talus;
using namespace talus::test;

namespace {

constexpr double kR = 0.1, kRho = 2600.0, kKn = 1e7;

Vec2 dirDeg(double deg) {
    const double a = deg * M_PI / 180.0;
    return Vec2(std::cos(a), std::sin(a));
}

}  // namespace

TEST_CASE("end-point contact: radial normal, restitution 1", "[core][walls]") {
    // Segment (-1,0)-(0,0) with a free end at the origin. A ball comes at the end straight along
    // the direction u (angle phi from +x); beyond the end (centre x > 0) the closest point is the
    // end point, so the normal is radial: n = -u (ball -> wall), and the impact is a head-on
    // impact on a point: restitution 1, no tangential velocity.
    for (double phi : {-60.0, -30.0, 0.0, 30.0, 60.0}) {
        auto m = makeModel(Vec2::Zero(), linearProps(kKn));
        m->createWall(wallOf({Vec2(-1.0, 0.0), Vec2(0.0, 0.0)}));
        const Vec2 u = dirDeg(phi);
        const double v0 = 1.0;
        const BallId b = m->createBall(ballAt(u * (kR + 0.013), kR, kRho, -v0 * u));
        const Episode ep = runEpisode(*m, b);
        REQUIRE(ep.ended);
        INFO("phi " << phi << " normal " << ep.normals.front().transpose() << " v_out "
                    << ep.v_out.transpose());
        CHECK(ep.max_contacts == 1);
        CHECK((ep.normals.front() + u).norm() < 1e-12);
        CHECK(ep.v_out.dot(u) / v0 == Approx(1.0).margin(2e-4));
        CHECK(std::fabs(cross(u, ep.v_out)) < 1e-12);
        const double m_ball = m->ballMass(b);
        CHECK(ep.peak_force == Approx(v0 * std::sqrt(kKn * m_ball)).epsilon(2e-3));
    }
}

TEST_CASE("shared vertex of a convex chain: one contact, no double push", "[core][walls]") {
    // A roof /\ and a step (a convex corner): a ball coming radially onto the shared vertex must
    // see exactly one contact, i.e. rebound like a single contact: restitution 1 (not more), and
    // peak force v0 sqrt(k m) and duration pi sqrt(m/k) of ONE spring. A double push would show
    // as 2 contacts, peak force x sqrt(2) and duration / sqrt(2) (e still ~1, so e alone would
    // not catch it).
    struct Shape {
        const char* name;
        std::vector<Vec2> points;
        Vec2 approach;  // unit vector from the vertex to the incoming ball
    };
    const std::vector<Shape> shapes = {
        {"roof", {Vec2(-1.0, -1.0), Vec2(0.0, 0.0), Vec2(1.0, -1.0)}, Vec2(0.0, 1.0)},
        {"roof, oblique", {Vec2(-1.0, -1.0), Vec2(0.0, 0.0), Vec2(1.0, -1.0)}, dirDeg(80.0)},
        {"step", {Vec2(-1.0, 0.0), Vec2(0.0, 0.0), Vec2(0.0, -1.0)}, dirDeg(45.0)},
        {"step, reversed", {Vec2(0.0, -1.0), Vec2(0.0, 0.0), Vec2(-1.0, 0.0)}, dirDeg(45.0)},
    };
    for (const Shape& sh : shapes) {
        auto m = makeModel(Vec2::Zero(), linearProps(kKn));
        m->createWall(wallOf(sh.points));
        const double v0 = 1.0;
        const BallId b =
            m->createBall(ballAt(sh.approach * (kR + 0.021), kR, kRho, -v0 * sh.approach));
        const Episode ep = runEpisode(*m, b);
        REQUIRE(ep.ended);
        const double mass = m->ballMass(b);
        const double duration = ep.t_last - ep.t_first;  // loaded steps: T - dt < . <= T
        const double T = linearDuration(mass, kKn), dt = T / 30.0;
        INFO(sh.name << ": contacts " << ep.max_contacts << ", e " << ep.v_out.dot(sh.approach) / v0
                     << ", peak " << ep.peak_force << ", duration " << duration);
        CHECK(ep.max_contacts == 1);
        CHECK(ep.v_out.dot(sh.approach) / v0 == Approx(1.0).margin(2e-4));
        CHECK(ep.peak_force == Approx(v0 * std::sqrt(kKn * mass)).epsilon(2e-3));
        CHECK(duration > T - 2.0 * dt);
        CHECK(duration < T + dt);
    }
}

TEST_CASE("concave corner: a resting ball carries two contacts that balance its weight",
          "[core][walls]") {
    // V-shaped chain (-1,1)-(0,0)-(1,1); a ball released slightly off-centre (clear of both
    // faces), frictionless, settles with local damping at the bottom: two face contacts, normals
    // at +-45 deg, each carrying m g / (2 cos 45 deg) = m g / sqrt(2), resultant = m g upward.
    const double g = 9.81;
    auto m = makeModel(Vec2(0.0, -g), linearProps(kKn));
    m->createWall(wallOf({Vec2(-1.0, 1.0), Vec2(0.0, 0.0), Vec2(1.0, 1.0)}));
    const BallId b = m->createBall(ballAt(Vec2(0.004, kR * std::sqrt(2.0) + 0.01), kR, kRho));
    m->damping().local = 0.7;
    m->solveTime(2.0);
    const double W = m->ballMass(b) * g;
    const auto cs = m->contacts();
    REQUIRE(cs.size() == 2);
    // Settled: velocity tiny against the impact scale sqrt(2 g * 2 mm) ~ 0.2 m/s.
    CHECK(m->ballVel(b).norm() < 1e-6);
    CHECK(std::fabs(m->ballPos(b).x()) < 1e-6);
    for (const auto& c : cs) {
        INFO("normal " << c.normal.transpose() << " force " << c.normal_force);
        CHECK(c.normal_force == Approx(W / std::sqrt(2.0)).epsilon(1e-6));
        CHECK(std::fabs(std::fabs(c.normal.x()) - std::sqrt(0.5)) < 1e-6);
        CHECK(c.normal.y() == Approx(-std::sqrt(0.5)).epsilon(1e-6));
    }
    CHECK(cs[0].segment != cs[1].segment);
    const Vec2 f = m->ballForce(b);
    CHECK(std::fabs(f.x()) < 1e-6 * W);
    CHECK(f.y() == Approx(W).epsilon(1e-6));
}

namespace {

/// A ball of radius r on a two-segment chain through the origin whose segments make the angle
/// 2 |kink_deg| (0: collinear; > 0: convex /\ ; < 0: concave \/).
struct Crossing {
    double worst = 0.0;  ///< largest |F - F_ref| / F_ref between x = -window and x = window
    std::size_t max_contacts = 0;
    double x_end = 0.0;
};

std::unique_ptr<Model> chainScene(double kink_deg, double fric, double g, BallId& b, double x0) {
    const double r = 0.05, s = std::tan(kink_deg * M_PI / 180.0);
    auto m = makeModel(Vec2(0.0, -g), linearProps(kKn, kKn, fric));
    // The ball starts pre-loaded (at its static overlap), so a contact that unloads later gives
    // back energy it never "took" and the energy guard says so; that is expected here.
    m->setWarningHandler([](const std::string&) {});
    m->createWall(wallOf({Vec2(-1.0, -s), Vec2(0.0, 0.0), Vec2(1.0, -s)}));
    // Placed on the left segment at its static overlap m g cos(a) / k (so that the contact
    // exists from the first step), held in x, settled with local damping.
    const Vec2 n = Vec2(-s, 1.0).normalized();
    const double mass = diskMass(kRho, r);
    const double overlap = mass * g * n.y() / kKn;
    BallDef bd = ballAt(Vec2(x0, x0 * s) + (r - overlap) * n, r, kRho);
    bd.fixity = kFixX | kFixSpin;
    b = m->createBall(bd);
    m->damping().local = 0.7;
    m->solveTime(1.0);
    m->damping().local = 0.0;
    return m;
}

/// Free crossing of a level chain at speed v, sliding (fric = 0) or rolling (spin = -v/r).
Crossing crossLevel(double v, bool rolling) {
    BallId b;
    auto m = chainScene(0.0, rolling ? 0.5 : 0.0, 9.81, b, -0.3);
    m->setBallFixity(b, 0);
    m->setBallVel(b, Vec2(v, 0.0));
    if (rolling) m->setBallSpin(b, -v / m->ballRadius(b));
    Crossing out;
    const double f_ref = m->ballForce(b).norm();
    while (m->ballPos(b).x() < 0.1 && m->time() < 100.0) {
        m->cycle(1);
        out.max_contacts = std::max(out.max_contacts, m->contacts().size());
        if (m->ballPos(b).x() < -0.1) continue;
        out.worst = std::max(out.worst, std::fabs(m->ballForce(b).norm() - f_ref) / f_ref);
    }
    out.x_end = m->ballPos(b).x();
    return out;
}

/// Quasi-static crossing: the ball's x-velocity is held at v by fixity (velocity preserved), y is
/// free under gravity; F_y compared with the weight between x = -window and x = window.
Crossing crossHeld(double kink_deg, double v, double window) {
    const double g = 9.81;
    BallId b;
    auto m = chainScene(kink_deg, 0.0, g, b, -3.0 * window);
    m->setBallFixity(b, kFixX | kFixSpin);
    m->setBallVel(b, Vec2(v, m->ballVel(b).y()));
    const double W = m->ballMass(b) * g;
    Crossing out;
    while (m->ballPos(b).x() < window && m->time() < 1000.0) {
        m->cycle(1);
        out.max_contacts = std::max(out.max_contacts, m->contacts().size());
        if (m->ballPos(b).x() < -window) continue;
        out.worst = std::max(out.worst, std::fabs(m->ballForce(b).y() - W) / W);
    }
    out.x_end = m->ballPos(b).x();
    return out;
}

}  // namespace

TEST_CASE("crossing the vertex of a straight chain: no force spike", "[core][walls]") {
    // Two collinear segments: the contact moves from one segment to the next with the same
    // overlap, so the force is continuous; the new contact starts with a fresh shear spring,
    // which on a level surface carries (almost) nothing. Bound: 1e-3 of the weight (the ball
    // moves on a resting overlap m g / k ~ 2e-5 m; any transfer glitch of one step's travel,
    // v dt ~ 7e-5 m, would show as a large fraction).
    for (bool rolling : {false, true}) {
        const Crossing c = crossLevel(0.5, rolling);
        report("vertex crossing, collinear, %s at 0.5 m/s: worst |F - F_rest|/F_rest = %.3e\n",
               rolling ? "rolling" : "sliding", c.worst);
        INFO((rolling ? "rolling" : "sliding") << " worst " << c.worst);
        REQUIRE(c.x_end >= 0.1);
        CHECK(c.max_contacts == 1);
        CHECK(c.worst < 1e-3);
    }
}

// Quasi-static crossings of a kinked chain: the ball's horizontal velocity is held at
// v = 5 mm/s, so inertia plays no part except at a concave kink, where the centre path must turn
// by the kink angle 2 alpha: a small impact with normal speed v sin(2 alpha) and force
// v sin(2 alpha) sqrt(k m) = 1.2% of the weight for alpha = 1 deg. The force must stay within 5%
// of the weight; a vertex that pushes twice would add ~100%.
TEST_CASE("crossing a straight or slightly convex vertex slowly: no force spike", "[core][walls]") {
    for (double kink : {0.0, 0.2, 1.0, 10.0}) {
        const Crossing c = crossHeld(kink, 0.005, 0.01);
        report(
            "vertex crossing held at 5 mm/s, convex %.1f deg: worst |F_y - W|/W = %.3e, max "
            "contacts %zu\n",
            kink, c.worst, c.max_contacts);
        INFO("kink " << kink << " worst " << c.worst);
        REQUIRE(c.x_end >= 0.01);
        CHECK(c.max_contacts == 1);
        // The 10-degree roof tilts the normal by up to 10 degrees: F_y = W holds only on
        // average; on the faces the y-force is W exactly (fixity takes the x-part).
        CHECK(c.worst < (kink > 5.0 ? 0.2 : 0.05));
    }
}

TEST_CASE("crossing a slightly concave vertex slowly: no force spike", "[core][walls]") {
    // Both faces of a concave corner can legitimately hold a ball (the V-corner test), and at the
    // bottom of a valley they share the weight. If the second face's contact started only when
    // the centre passed over that face (as an earlier version did), it would start with an
    // overlap of delta_0 - 2 tan(alpha)^2 r, delta_0 = m g / k being the overlap on the first
    // face: for alpha = 0.2 deg the force jumped towards 2 m g, a kick at every slightly concave
    // vertex of a digitised profile. Each face now measures the distance to its own closest point,
    // vertex included (narrowphase.hpp), so the second contact grows from zero. Bound as for the
    // convex case: 5%.
    for (double kink : {-1.0, -0.2}) {
        const Crossing c = crossHeld(kink, 0.005, 0.01);
        report(
            "vertex crossing held at 5 mm/s, concave %.1f deg: worst |F_y - W|/W = %.3e, max "
            "contacts %zu\n",
            -kink, c.worst, c.max_contacts);
        INFO("concave " << -kink << " deg: worst " << c.worst);
        REQUIRE(c.x_end >= 0.01);
        CHECK(c.worst < 0.05);
    }
}

TEST_CASE("a wall moving at constant velocity: boundary work equals the energy gained",
          "[core][walls]") {
    // A vertical wall at x = 0 moving at +v_w hits a ball at rest (no gravity). In the wall frame
    // this is an impact at v_w, so the ball leaves at (1 + e) v_w, and with energy tracing the
    // work of the wall (energy-boundary) is the kinetic energy gained plus what the dashpot took.
    // The boundary work is booked from the wall force of the previous step times the wall's
    // motion in this one, the same impulse window the balls use, so the identity holds to the
    // O(dt^2) bookkeeping of a resolved impact: bound 1e-3 of the energy gained (measured ~1e-5).
    for (double beta : {0.0, 0.3}) {
        const double v_w = 0.5;
        auto m = makeModel(Vec2::Zero(), linearProps(kKn, 0.0, 0.0, beta));
        WallDef w = wallOf({Vec2(0.0, -1.0), Vec2(0.0, 1.0)});
        w.vel = Vec2(v_w, 0.0);
        m->createWall(w);
        const BallId b = m->createBall(ballAt(Vec2(kR + 0.05, 0.0), kR, kRho));
        m->setEnergyTracing(true);
        const Episode ep = runEpisode(*m, b);
        REQUIRE(ep.ended);
        m->cycle(5);  // energies are a snapshot one step behind: let them catch up in flight
        const double e = restitutionFull(beta);
        CHECK(ep.v_out.x() / v_w == Approx(1.0 + e).epsilon(beta > 0 ? 5e-3 : 2e-4));
        CHECK(std::fabs(ep.v_out.y()) < 1e-12);
        const EnergyTotals en = m->energies();
        const double gained = en.kinetic - en.initial_kinetic;
        report(
            "moving wall beta %.1f: v_out/v_w %.6f (exact %.6f), boundary %.6g J, dKE %.6g J, "
            "dashpot %.6g J, balance error %.3e J\n",
            beta, ep.v_out.x() / v_w, 1.0 + e, en.boundary, gained, en.dashpot, en.balanceError());
        CHECK(gained == Approx(0.5 * m->ballMass(b) * ep.v_out.squaredNorm()).epsilon(1e-12));
        CHECK(en.boundary > 0.0);
        CHECK(std::fabs(en.boundary - gained - en.dashpot) < 1e-3 * gained);
        CHECK(std::fabs(en.balanceError()) < 1e-3 * gained);
    }
}

TEST_CASE("a rotating wall: exact kinematics and boundary work", "[core][walls]") {
    // A paddle (0,0)-(1,0) turning at omega about the origin hits a ball resting above it at
    // (x, y) (no gravity, frictionless, undamped). Rigid-body limit: the paddle touches the ball
    // when its angle theta satisfies y cos(theta) - x sin(theta) = R; the contact point is then at
    // d = x cos(theta) + y sin(theta) from the pivot and moves at omega d along the paddle's
    // normal, so the ball leaves at 2 omega d. The normal turns by omega t_c ~ 9e-4 rad during
    // the contact (kn = 1e9), which bounds the departure from it (bound 3e-3). The boundary work
    // (wall moment times rotation) must equal the kinetic energy gained (bound 1e-3 relative, as
    // for the translating wall). The wall's vertices are rotated exactly: by omega t about the
    // centre after time t.
    const double omega = 1.0, x = 0.5, y = kR + 0.02;
    auto m = makeModel(Vec2::Zero(), linearProps(1e9));
    WallDef w = wallOf({Vec2(0.0, 0.0), Vec2(1.0, 0.0)});
    w.spin = omega;
    w.center = Vec2(0.0, 0.0);
    const WallId wid = m->createWall(w);
    const BallId b = m->createBall(ballAt(Vec2(x, y), kR, kRho));
    m->setEnergyTracing(true);
    const Episode ep = runEpisode(*m, b);
    REQUIRE(ep.ended);
    m->cycle(5);
    const double t = m->time();
    const auto pts = m->wallPoints(wid);
    CHECK((pts[0] - Vec2(0.0, 0.0)).norm() < 1e-15);
    CHECK((pts[1] - dirDeg(omega * t * 180.0 / M_PI)).norm() < 1e-12);
    const double speed = ep.v_out.norm();
    const double theta = std::acos(kR / std::hypot(x, y)) - std::atan2(x, y);
    const double d = x * std::cos(theta) + y * std::sin(theta);
    const EnergyTotals en = m->energies();
    const double gained = en.kinetic - en.initial_kinetic;
    report(
        "rotating wall: speed / (2 omega d) = %.6f, direction error %.2e rad, boundary %.6g J, "
        "dKE %.6g J, balance error %.3e J\n",
        speed / (2.0 * omega * d), std::atan2(-ep.v_out.x(), ep.v_out.y()) - theta, en.boundary,
        gained, en.balanceError());
    CHECK(speed / (2.0 * omega * d) == Approx(1.0).epsilon(3e-3));
    CHECK(std::atan2(-ep.v_out.x(), ep.v_out.y()) == Approx(theta).margin(3e-3));
    CHECK(en.boundary > 0.0);
    CHECK(std::fabs(en.boundary - gained) < 1e-3 * gained);
}
