// SPDX-License-Identifier: MIT
//
// Free fall. Central differences with the velocity window w = (dt_prev + dt)/2 integrate a
// constant acceleration exactly for any sequence of steps (the first
// step uses w = dt/2 and takes the given velocity as the value at t0):
//   x(t) = x0 + v0 t + g t^2/2,   v(t_n + dt/2) = v0 + g (t_n + dt/2).
// So the only error allowed is floating-point round-off. Bound used below: every step adds a
// rounding error of at most a few ulp of the position and of the time, so after N steps
//   |x_num - x_exact| <= c N eps (|x| + |v| t + |g| t^2)
// with c = 8 (generous; the measured worst is reported with TALUS_TEST_REPORT=1). A scheme error
// of even O(dt^2) per step would exceed this by orders of magnitude (dt = 1e-3, g = 9.81:
// g dt^2 / 2 = 5e-6 m per step against eps |x| ~ 2e-15 m).
#include <catch2/catch.hpp>
#include <set>

#include "test_support.hpp"

using namespace talus;
using namespace talus::test;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

struct FallScene {
    Vec2 g{0.3, -9.81};
    Vec2 x0{0.25, 40.0};
    Vec2 v0{1.5, 4.0};
    double radius = 0.1;
    std::unique_ptr<Model> model;
    BallId ball;

    explicit FallScene(const TimestepSettings& ts) {
        ModelDef def;
        def.gravity = g;
        model = std::make_unique<Model>(def);
        model->setDefaultContactModel("linear", linearProps(1e6, 1e6));
        model->timestep() = ts;
        ball = model->createBall(ballAt(x0, radius, 2600.0, v0));
        // A far-away ball so that the scene is not trivially empty (never touched).
        model->createBall(ballAt(Vec2(-1000.0, -1000.0), radius, 2600.0));
    }
    Vec2 exactPos(double t) const { return x0 + v0 * t + 0.5 * g * t * t; }
    Vec2 exactVel(double t) const { return v0 + g * t; }
    /// Round-off bound after n steps at time t (see the file comment).
    double bound(int64_t n, double t) const {
        const double scale = exactPos(t).norm() + v0.norm() * t + g.norm() * t * t;
        return 8.0 * static_cast<double>(std::max<int64_t>(n, 1)) * kEps * scale;
    }
};

/// Checks position and half-step velocity against the parabola at the model's time.
void checkExact(const FallScene& s, int64_t steps_done, double& worst_rel) {
    const Model& m = *s.model;
    const double t = m.time();
    const Vec2 dx = m.ballPos(s.ball) - s.exactPos(t);
    const double tol = s.bound(steps_done, t);
    INFO("t = " << t << " steps = " << steps_done << " |dx| = " << dx.norm() << " tol = " << tol);
    CHECK(dx.norm() <= tol);
    // Velocity at the half step after the last position: t - dt/2.
    const Vec2 dv = m.ballVel(s.ball) - s.exactVel(t - 0.5 * m.lastTimestep());
    CHECK(dv.norm() <=
          8.0 * static_cast<double>(steps_done) * kEps * (s.v0.norm() + s.g.norm() * t));
    worst_rel = std::max(worst_rel, dx.norm() / tol);
}

}  // namespace

TEST_CASE("free fall is exact with a fixed step", "[core][free_fall]") {
    for (double dt : {1e-4, 1e-3, 7.3e-3}) {
        FallScene s(fixedStep(dt));
        double worst = 0.0;
        int64_t done = 0;
        for (int block = 0; block < 10; ++block) {
            s.model->cycle(200);
            done += 200;
            checkExact(s, done, worst);
        }
        CHECK(s.model->lastStepRule() == StepRule::Fixed);
        CHECK(s.model->lastTimestep() == dt);
        report("free fall fixed dt=%g: worst |dx|/bound = %.3g after %lld steps\n", dt, worst,
               static_cast<long long>(done));
    }
}

TEST_CASE("free fall is exact with the automatic step, which varies", "[core][free_fall]") {
    FallScene s(TimestepSettings{});
    std::set<double> steps;
    std::set<StepRule> rules;
    const int hook = s.model->addCycleHook(1, [&](Model& m) {
        steps.insert(m.lastTimestep());
        rules.insert(m.lastStepRule());
    });
    double worst = 0.0;
    int64_t done = 0;
    for (int block = 0; block < 20; ++block) {
        s.model->cycle(100);
        done += 100;
        checkExact(s, done, worst);
    }
    s.model->removeCycleHook(hook);
    // The test only means something if the step actually varied: the free-flight step follows
    // the kinematic rule (stay inside the broadphase fat box) and the growth limit.
    CHECK(steps.size() >= 3);
    CHECK((rules.count(StepRule::Kinematic) + rules.count(StepRule::Growth)) >= 1);
    CHECK(rules.count(StepRule::Resolution) == 0);
    CHECK(rules.count(StepRule::Stability) == 0);
    report("free fall automatic: %zu distinct steps (%g .. %g s), worst |dx|/bound = %.3g\n",
           steps.size(), *steps.begin(), *steps.rbegin(), worst);
}

TEST_CASE("solveTime lands exactly on the requested time and stays exact", "[core][free_fall]") {
    SECTION("automatic step") {
        FallScene s(TimestepSettings{});
        double worst = 0.0, target = 0.0;
        int64_t before = 0;
        for (double d : {0.0137, 0.25, 1.0 / 3.0, 0.5, 1e-5, 0.9}) {
            target += d;
            s.model->solveTime(d);
            // solveTime caps the last step at the time left, so the clock is exact to round-off
            // of the sum of the steps.
            const int64_t n = s.model->step();
            CHECK(std::fabs(s.model->time() - target) <=
                  4.0 * static_cast<double>(n) * kEps * target);
            checkExact(s, n, worst);
            CHECK(n > before);
            before = n;
        }
        report("solveTime automatic: time error %.3g s after %lld steps, worst |dx|/bound %.3g\n",
               s.model->time() - target, static_cast<long long>(s.model->step()), worst);
    }
    SECTION("fixed step that does not divide the duration") {
        FallScene s(fixedStep(1e-3));
        double worst = 0.0;
        s.model->solveTime(0.12345);
        // 123 whole steps and one shortened to 0.45e-3 s.
        CHECK(s.model->step() == 124);
        CHECK(s.model->lastTimestep() == Approx(0.45e-3).epsilon(1e-9));
        CHECK(std::fabs(s.model->time() - 0.12345) <= 1e-15);
        checkExact(s, s.model->step(), worst);
        // The next cycle is back at the fixed step.
        s.model->cycle(1);
        CHECK(s.model->lastTimestep() == 1e-3);
        checkExact(s, s.model->step(), worst);
    }
}
