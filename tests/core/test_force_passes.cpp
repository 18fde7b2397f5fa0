// SPDX-License-Identifier: MIT
//
// The force loop pass by pass (core/src/force/): each pass run alone on a pair the engine made,
// against closed forms and conservation laws.
//   pass 1 (pass_geometry.hpp): overlap, normal and contact point of two disks and of a disk on a
//     segment; the rates of a rigid motion of the pair are zero (objectivity), a pure approach
//     gives u_dot_n = the approach speed;
//   pass 2 (pass_law.hpp): linear's first call is F = kn u_n, and the host's kernel of its law,
//     on a row packed from the contact, gives the same bits as its FDlaw;
//   pass 3 (pass_finish.hpp): the ends get equal and opposite forces (bit for bit) and no net
//     torque about any point; the threads' recorded actions are the same numbers; a pair apart
//     whose fat boxes separated is queued for removal.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "force/pair.hpp"
#include "force/view.hpp"
#include "step/step.hpp"
#include "talus/model.hpp"
#include "world/world.hpp"

using namespace talus;

namespace {

constexpr double kR = 0.01;   // [m]
constexpr double kKn = 1e6;   // [N/m]
constexpr double kDt = 1e-6;  // [s]
using Features = LoopFeatures<false, false, false>;

/// Two disks (or a disk and a wall) with one active contact, after one step of the engine.
struct Scene {
    Model model;
    World& world;
    explicit Scene(bool wall) : world(worldOf(model)) {
        model.setDefaultContactModel("linear", {{"kn", kKn}, {"ks", 0.5 * kKn}, {"fric", 0.5}});
        model.timestep().automatic = false;
        model.timestep().fixed = kDt;
        BallDef a;
        a.pos = Vec2(0.0, 0.0), a.radius = kR, a.density = 2600.0;
        model.createBall(a);
        if (wall) {
            WallDef w;
            w.points = {Vec2(-0.05, -0.999 * kR), Vec2(0.05, -0.999 * kR)};
            model.createWall(w);
        } else {
            BallDef b = a;
            b.pos = Vec2(1.6 * kR, 1.2 * kR);  // 2 kR apart less 1e-4 kR: overlap 2e-6 m
            b.pos *= (2.0 - 1e-4) * kR / b.pos.norm();
            model.createBall(b);
        }
        model.cycle(1);
        REQUIRE(world.contacts.pairs.size() == 1);
        REQUIRE(world.contacts.pairs[0].active);
    }
    StepContext step() const { return beginStep(world); }
    ForceView view(const StepContext& s) {
        // (every rule's contacts through FDlaw here: no kernel rows)
        forceScratch(world).rows.assign(world.contacts.rules.size(), RuleRows{});
        return forceView(world, s, world.contacts.fd_template, 1, false);
    }
};

/// Sets the balls' velocities to the rigid motion v = V + w x (x - c), spin w.
void rigidMotion(Model& m, const Vec2& V, double w, const Vec2& c) {
    for (const BallId id : m.ballIds()) {
        const Vec2 r = m.ballPos(id) - c;
        m.setBallVel(id, V + Vec2(-w * r.y(), w * r.x()));
        m.setBallSpin(id, w);
    }
}

}  // namespace

TEST_CASE("pass 1: two disks, geometry and rates against closed forms") {
    Scene sc(false);
    const auto ids = sc.model.ballIds();
    const Vec2 x1 = sc.model.ballPos(ids[0]), x2 = sc.model.ballPos(ids[1]);
    const double dist = (x2 - x1).norm();
    const StepContext step = sc.step();
    PairEntry e;
    FdBlock fd = sc.world.contacts.fd_template;

    SECTION("geometry") {
        const ForceView v = sc.view(step);
        REQUIRE(geometryPass<Features>(v, 0, e, &fd) == PairStep::Contact);
        const Vec2 n = (x2 - x1) / dist;
        CHECK(e.g.overlap == Approx(2.0 * kR - dist).epsilon(1e-12));
        CHECK(fd.u_n == e.g.overlap);
        CHECK((e.g.normal - n).norm() < 1e-15);
        // The contact point halves the overlap: at r1 - overlap/2 from centre 1, on the line.
        const Vec2 point = x1 + (kR - 0.5 * (2.0 * kR - dist)) * n;
        CHECK((e.g.point - point).norm() < 4 * kR * 1.2e-16);  // a few ulps of the coordinates
    }
    SECTION("a rigid motion of the pair is no deformation") {
        // Translation plus rotation about an arbitrary point: the contact point of each disk moves
        // with it, so the relative rates are zero (to round-off of the velocities' size).
        rigidMotion(sc.model, Vec2(0.3, -0.7), 25.0, Vec2(0.2, -0.1));
        const ForceView v = sc.view(step);
        REQUIRE(geometryPass<Features>(v, 0, e, &fd) == PairStep::Contact);
        const double scale = 0.7 + 25.0 * 0.25;  // |v| the motion gives the disks [m/s]
        CHECK(std::fabs(fd.u_dot_n) < 1e-14 * scale);
        // The shear rate's half-step correction (pass_geometry.hpp) is second order in the turn
        // of the centre line over the step: at most |d| w^3 dt^2 for a rigid rotation w.
        CHECK(std::fabs(fd.u_dot_s) < dist * std::pow(25.0, 3) * kDt * kDt + 1e-14 * scale);
        CHECK(fd.t_dot_rel == 0.0);
    }
    SECTION("a pure approach along the normal") {
        const Vec2 n = (x2 - x1) / dist;
        sc.model.setBallVel(ids[0], 0.25 * n);
        sc.model.setBallVel(ids[1], -0.5 * n);
        const ForceView v = sc.view(step);
        REQUIRE(geometryPass<Features>(v, 0, e, &fd) == PairStep::Contact);
        CHECK(fd.u_dot_n == Approx(0.75).epsilon(1e-14));
        CHECK(std::fabs(fd.u_dot_s) < 1e-14);
        CHECK(fd.du_n == Approx(0.75 * kDt).epsilon(1e-14));
    }
    SECTION("a pair beyond reach is apart") {
        Pair& p = sc.world.contacts.pairs[0];
        p.active = false;  // (as after the contact's end)
        sc.model.setBallPos(ids[1], x1 + 3.0 * kR * (x2 - x1) / dist);
        const ForceView v = sc.view(step);
        CHECK(geometryPass<Features>(v, 0, e, &fd) == PairStep::Apart);
        p.active = true;
    }
}

TEST_CASE("pass 1: a disk on a segment against closed forms") {
    Scene sc(true);
    const StepContext step = sc.step();
    const BallId id = sc.model.ballIds()[0];
    const Vec2 x = sc.model.ballPos(id);
    sc.model.setBallVel(id, Vec2(0.4, -0.3));
    sc.model.setBallSpin(id, 0.0);
    PairEntry e;
    FdBlock fd = sc.world.contacts.fd_template;
    const ForceView v = sc.view(step);
    REQUIRE(geometryPass<Features>(v, 0, e, &fd) == PairStep::Contact);
    // The segment is the line y = -0.999 r: overlap r - (y + 0.999 r), normal from the ball to
    // the wall, contact point halfway through the overlap.
    const double gap = x.y() + 0.999 * kR;
    CHECK(e.g.overlap == Approx(kR - gap).epsilon(1e-10));
    CHECK((e.g.normal - Vec2(0.0, -1.0)).norm() < 1e-15);
    CHECK(fd.u_dot_n == Approx(0.3).epsilon(1e-14));  // the ball moves into the wall at 0.3
    // Sliding at 0.4 without spin: the wall's contact point moves at -0.4 relative to the ball
    // along t = perp(n) = (1, 0) (the correction for a breathing contact is second order).
    CHECK(fd.u_dot_s == Approx(-0.4).epsilon(1e-6));
}

TEST_CASE("pass 2: linear's first call, and its kernel against its FDlaw") {
    Scene sc(false);
    const auto ids = sc.model.ballIds();
    sc.model.setBallVel(ids[1], Vec2(-0.02, 0.05));  // loading and sliding a little
    sc.model.setBallSpin(ids[0], 2.0);
    const StepContext step = sc.step();
    const ForceView v = sc.view(step);
    PairEntry e;
    FdBlock fd = sc.world.contacts.fd_template;
    REQUIRE(geometryPass<Features>(v, 0, e, &fd) == PairStep::Contact);
    Pair& p = sc.world.contacts.pairs[0];
    PairCold& c = sc.world.contacts.cold[0];
    // After the engine's first step (the contact's first call) the force is kn u_n.
    CHECK(p.n_force == Approx(kKn * c.overlap).epsilon(1e-12));
    // The same contact state both ways: the row packed from the object, FDlaw on the object.
    const Rule& rule = sc.world.contacts.ruleOf(p);
    REQUIRE(rule.kernel == Kernel::Linear);
    const LaneLaw& rows = *rule.factory->lanes;
    std::vector<double> row(static_cast<std::size_t>(rows.state_size));
    REQUIRE(rows.pack(p.model, row.data()) == 1);
    std::string error;
    callLaw(p.model, fd, error);
    REQUIRE(fd.status == 0);
    PairEntry ek;  // pass 1 for a contact on a row: the law's inputs into the entry
    REQUIRE(geometryPass<Features>(v, 0, ek, nullptr) == PairStep::Contact);
    KernelFd kf = kernelBlock(v, p, ek);
    REQUIRE(kernelStep<Kernel::Linear>(row.data(), &c, kf));
    CHECK(kf.n_force == fd.n_force);
    CHECK(kf.s_force == fd.s_force);
    CHECK(kf.moment == fd.moment);
    CHECK(kf.knest == fd.knest);
    CHECK(kf.ksest == fd.ksest);
    CHECK(kf.s_force != 0.0);  // (the shear spring took part)
    // The object and the row hold the same state after the step.
    std::vector<double> after(row.size());
    REQUIRE(rows.pack(p.model, after.data()) == 1);
    for (std::size_t k = 0; k < row.size(); ++k) CHECK(after[k] == row[k]);
}

TEST_CASE("pass 3: action and reaction, and the threads' record of them") {
    Scene sc(false);
    const auto ids = sc.model.ballIds();
    sc.model.setBallSpin(ids[0], 3.0);
    sc.model.setBallVel(ids[1], Vec2(0.1, 0.2));
    const StepContext step = sc.step();
    PairEntry e;
    FdBlock fd = sc.world.contacts.fd_template;
    ForceView v = sc.view(step);
    REQUIRE(geometryPass<Features>(v, 0, e, &fd) == PairStep::Contact);
    std::string error;
    callLaw(sc.world.contacts.pairs[0].model, fd, error);
    fd.moment = 1e-4;  // a model moment (rolling resistance, a bond) goes to both ends too
    auto& b = sc.world.bodies.balls;
    std::fill(b.force.begin(), b.force.end(), Vec2::Zero());
    std::fill(b.moment.begin(), b.moment.end(), 0.0);
    // A copy of the pair's state, for the threads' delivery below.
    const Pair before = sc.world.contacts.pairs[0];
    ForceSums sums;
    ForceThreadPart part;
    finishContact<Features, Delivery::Direct>(v, sums, 0, e, fd, kNoTouch, part);
    const Vec2 f1 = b.force[0], f2 = b.force[1];
    CHECK(f1.x() == -f2.x());
    CHECK(f1.y() == -f2.y());
    CHECK(f2.norm() == Approx(std::hypot(fd.n_force, fd.s_force)).epsilon(1e-14));
    // No net torque about the origin: the moments plus the forces' moments about it.
    const double torque = b.moment[0] + b.moment[1] + cross(b.pos[0], f1) + cross(b.pos[1], f2);
    CHECK(std::fabs(torque) < 1e-15 * (std::fabs(b.moment[0]) + std::fabs(b.moment[1]) +
                                       f2.norm() * (b.pos[0].norm() + b.pos[1].norm())));
    CHECK(part.finite_check == fd.n_force + fd.s_force + fd.moment + fd.knest + fd.ksest);

    // The threads' delivery records the same numbers for the gather (end 1's negated).
    sc.world.contacts.pairs[0] = before;
    ForceScratch& scratch = forceScratch(sc.world);
    scratch.actions.assign(1, PairAction{});
    v.actions = scratch.actions.data();
    finishContact<Features, Delivery::Serial>(v, sums, 0, e, fd, kNoTouch, part);
    const PairAction& act = scratch.actions[0];
    CHECK(0.0 + act.add[0][0] == f1.x());
    CHECK(0.0 + act.add[0][1] == f1.y());
    CHECK(0.0 + act.add[0][2] == b.moment[0]);
    CHECK(act.add[1][0] == f2.x());
    CHECK(act.add[1][1] == f2.y());
    CHECK(act.add[1][2] == b.moment[1]);

    // A thread adds onto the ball it owns at once and records only the other end's action.
    const double m1 = b.moment[0], m2 = b.moment[1];
    sc.world.contacts.pairs[0] = before;
    std::fill(b.force.begin(), b.force.end(), Vec2::Zero());
    std::fill(b.moment.begin(), b.moment.end(), 0.0);
    scratch.route.assign(b.size(), kRouteShared);
    scratch.route[0] = 1;
    v.route = scratch.route.data();
    const double untouched = 7.0;
    scratch.actions.assign(1, PairAction{{{untouched, untouched, untouched}, {0.0, 0.0, 0.0}}});
    ForceThreadPart owner;
    owner.index = 1;
    finishContact<Features, Delivery::Parallel>(v, sums, 0, e, fd, kNoTouch, owner);
    CHECK(b.force[0] == f1);
    CHECK(b.moment[0] == m1);
    CHECK(b.force[1] == Vec2::Zero());
    CHECK(b.moment[1] == 0.0);
    CHECK(act.add[0][0] == untouched);
    CHECK(act.add[0][2] == untouched);
    CHECK(act.add[1][0] == f2.x());
    CHECK(act.add[1][1] == f2.y());
    CHECK(act.add[1][2] == m2);
}

TEST_CASE("pass 3: a pair apart whose fat boxes separated is removed") {
    Scene sc(false);
    const auto ids = sc.model.ballIds();
    auto& b = sc.world.bodies.balls;
    const StepContext step = sc.step();
    ForceView v = sc.view(step);
    sc.world.contacts.to_remove.clear();
    ForceThreadPart part;
    // Not moved: kept whatever the boxes say (only re-inserted bodies are checked).
    finishApart<Features, Delivery::Direct>(v, 0, PairStep::Apart, part);
    CHECK(sc.world.contacts.to_remove.empty());
    // Moved, and its fat box now far from the other's.
    sc.world.contacts.ball_moved[1] = 1;
    b.fat[1] = Box{b.pos[0] + Vec2(10 * kR, 10 * kR), b.pos[0] + Vec2(11 * kR, 11 * kR)};
    finishApart<Features, Delivery::Direct>(v, 0, PairStep::Apart, part);
    REQUIRE(sc.world.contacts.to_remove.size() == 1);
    CHECK(sc.world.contacts.to_remove[0] == 0u);
    (void)ids;
}
