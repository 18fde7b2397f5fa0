// SPDX-License-Identifier: MIT
//
// Phase 2: the law of motion. Central differences (leapfrog) with velocities at half steps:
//   v(t + dt/2) = v(t - dt/2) + (F/m + g) w,   x(t + dt) = x(t) + v(t + dt/2) dt,
// where w = (dt_prev + dt)/2 is the time between the two half steps. With that window a
// constant acceleration is integrated exactly for any sequence of steps (free flight costs no
// accuracy). On the very first cycle the given velocities are taken as values at t, so w = dt/2.
//
// Damping options (docs/physics/damping.md):
//  - PFC local damping: F_i <- F_i - alpha |F_i| sign(v_i) per degree of freedom
//    (the PFC2D manual).
//  - Mass-proportional viscous damping c [1/s], implicit at the time level of the forces
//    (Nejati 2008, eq. 2.41): v+ = ((1 - c w/2) v- + a w) / (1 + c w/2).
//
// Energy (only when traced) is a snapshot at the whole step t, taken here before this step's
// work is booked: the velocity at t is interpolated between the two half-step velocities,
// v(t) = v(t - dt_prev/2) + (v(t + dt/2) - v(t - dt_prev/2)) (dt_prev/2) / w, which is exact
// for a constant acceleration over any step sequence; body work is (m g + F_app) . dx. Free
// flight with a growing automatic step therefore balances to round-off (docs/physics/energy.md).
//
// The loop is compiled in three forms: the plain one (no damping, no energy, no fixity), which
// is what a benchmark or a rockfall run without options executes; the traced one, the plain one
// with the energy snapshot (tracing on, nothing else: a third of the general loop's instructions
// per ball); and the general one. The three give the same motion bit for bit (with keep = 1 and
// gain = w the general update is the plain one).
#include <cmath>
#include <string>

#include "step/body_damping.hpp"
#include "step/group_energy.hpp"
#include "step/step.hpp"
#include "world/body_store.hpp"
#include "world/contact_store.hpp"
#include "world/messages.hpp"
#include "world/types.hpp"

namespace talus {

namespace {

std::string text(double v) { return messageNumber(v); }

void moveBallsPlain(World& world, const StepContext& step);
void moveBallsTraced(World& world, const StepContext& step);
void moveBallsGeneral(World& world, const StepContext& step);

void closeBooks(World& world, const StepContext& step, double lead, double kinetic, double body,
                double damping, double driven);

}  // namespace

void lawOfMotion(World& world, const StepContext& step) {
    world.clock.window = step.window;
    // Clumps need the general loop (it skips their pebbles; moveClumps moves them).
    const bool general = step.groups || world.settings.damping.local > 0.0 ||
                         world.settings.damping.viscous > 0.0 || world.bodies.fixed_balls > 0 ||
                         world.bodies.hasClumps();
    if (step.groups) gatherExchangeStart(world);  // rates before the update (group_energy.cpp)
    if (general)
        moveBallsGeneral(world, step);
    else if (step.energy)
        moveBallsTraced(world, step);
    else
        moveBallsPlain(world, step);
    world.clock.first_cycle = false;
    world.clock.time += step.dt;
    ++world.clock.step;
}

namespace {

/// The plain update: no damping, no energy, no fixity. Every ball's update is its own: with
/// threads (as many as the force loop took, over the same static ranges of balls as its gather,
/// so each thread reads the forces it wrote) the result is the same bit for bit.
void moveBallsPlain(World& world, const StepContext& step) {
    auto& b = world.bodies.balls;
    const std::size_t n = b.size();
    const double dt = step.dt;
    const double w = step.window;
    const Vec2 g = world.settings.gravity;
    Vec2* pos = b.pos.data();
    Vec2* vel = b.vel.data();
    const Vec2* force = b.force.data();
    const Vec2* fapp = b.fapp.data();
    double* spin = b.spin.data();
    double* angle = b.angle.data();
    const double* moment = b.moment.data();
    const double* mapp = b.mapp.data();
    const double* inv_mass = b.inv_mass.data();
    const double* inv_inertia = b.inv_inertia.data();
    const int threads = world.clock.threads;
    (void)threads;
    bool finite = true;
    TALUS_OMP(omp parallel for num_threads(threads) schedule(static) reduction(&& : finite) if (threads > 1))
    for (std::size_t s = 0; s < n; ++s) {
        const Vec2 v = vel[s] + ((force[s] + fapp[s]) * inv_mass[s] + g) * w;
        const double om = spin[s] + (moment[s] + mapp[s]) * inv_inertia[s] * w;
        vel[s] = v;
        spin[s] = om;
        pos[s] += v * dt;
        angle[s] += om * dt;
        finite = finite && std::isfinite(v.x() + v.y() + om);
    }
    if (!finite) reportNonFiniteBall(world);
}

/// The weight of the old half-step velocity's step in the velocity at the whole step t.
double snapshotLead(const StepContext& step) {
    return step.window > 0.0 ? 0.5 * step.dt_prev / step.window : 0.0;
}

/// The plain update with the snapshot's kinetic energy at t and the body work; the sums on one
/// thread, in ball order, as the general loop makes them.
void moveBallsTraced(World& world, const StepContext& step) {
    auto& b = world.bodies.balls;
    const std::size_t n = b.size();
    const double dt = step.dt;
    const double w = step.window;
    const Vec2 g = world.settings.gravity;
    const double lead = snapshotLead(step);
    double kinetic = 0.0, body = 0.0, finite_check = 0.0;
    for (std::size_t s = 0; s < n; ++s) {
        const Vec2 v_old = b.vel[s];
        const double w_old = b.spin[s];
        const Vec2 v = v_old + ((b.force[s] + b.fapp[s]) * b.inv_mass[s] + g) * w;
        const double om = w_old + (b.moment[s] + b.mapp[s]) * b.inv_inertia[s] * w;
        b.vel[s] = v;
        b.spin[s] = om;
        b.pos[s] += v * dt;
        b.angle[s] += om * dt;
        finite_check += v.x() + v.y() + om;
        const double m = b.mass[s];
        const Vec2 v_now = v_old + (v - v_old) * lead;
        const double om_now = w_old + (om - w_old) * lead;
        kinetic += 0.5 * (m * v_now.squaredNorm() + b.inertia[s] * om_now * om_now);
        body += ((m * g + b.fapp[s]).dot(v) + b.mapp[s] * om) * dt;
    }
    if (!std::isfinite(finite_check)) reportNonFiniteBall(world);
    closeBooks(world, step, lead, kinetic, body, 0.0, 0.0);
}

/// The general loop's energy sums, added ball by ball.
struct MotionSums {
    double kinetic = 0.0, body = 0.0, damping = 0.0, driven = 0.0;
};

/// What one ball's update of the general loop does to the books: the kinetic energy at t, the
/// body work, the damping's work and a fixity's reaction work.
struct BallUpdate {
    uint32_t s;
    Vec2 v_old, v, f, fd;  // velocities before and after; the force; local damping's force
    double w_old, om, mom, md;
    double cx, cy, cw;  // viscous damping coefficient per degree of freedom
};

void bookBall(World& world, const StepContext& step, double lead, const BallUpdate& u,
              MotionSums& sums) {
    const auto& b = world.bodies.balls;
    const Vec2 g = world.settings.gravity;
    const uint32_t s = u.s;
    const uint8_t fix = b.fixity[s];
    const double m = b.mass[s];
    const double inertia = b.inertia[s];
    const Vec2 v_now = u.v_old + (u.v - u.v_old) * lead;
    const double om_now = u.w_old + (u.om - u.w_old) * lead;
    const double ke = 0.5 * (m * v_now.squaredNorm() + inertia * om_now * om_now);
    const double work = ((m * g + b.fapp[s]).dot(u.v) + b.mapp[s] * u.om) * step.dt;
    sums.kinetic += ke;
    sums.body += work;
    // Local damping on the velocity at t, viscous on the mean of the half steps
    // (body_damping.hpp). Without damping its work is zero, left out.
    double damp = 0.0;
    if (world.settings.damping.local > 0.0 || world.settings.damping.viscous > 0.0) {
        const Vec2 v_mid = 0.5 * (u.v_old + u.v);
        const double om_mid = 0.5 * (u.w_old + u.om);
        damp = dampingWork(step.window, u.fd, u.md, v_now, om_now, v_mid, om_mid, m, inertia, u.cx,
                           u.cy, u.cw);
        sums.damping += damp;
    }
    double react = 0.0;
    if (fix) {
        // A fixed component moves at its set velocity whatever acts on it: the fixity supplies
        // the reaction R = -(everything else), and R's work goes into `boundary`, like a wall's
        // (docs/physics/energy.md). R acts as an impulse R w at the rate v, split at the snapshot
        // like the damping impulse below (the trapezoidal rule: second order, as the rest of the
        // balance).
        const Vec2 load = u.f + m * g;
        if (fix & kFixX) react -= load.x() * u.v.x();
        if (fix & kFixY) react -= load.y() * u.v.y();
        if (fix & kFixSpin) react -= u.mom * u.om;
        sums.driven += react * step.window;
    }
    if (step.groups) bookBodyToGroups(world, b.groups[s], ke, work, damp, react * step.window);
}

/// The general update: PFC local damping, mass-proportional viscous damping, fixities, clumps
/// (their pebbles skipped here: moveClumps), energy with groups.
void moveBallsGeneral(World& world, const StepContext& step) {
    auto& b = world.bodies.balls;
    const std::size_t n = b.size();
    const double dt = step.dt;
    const double w = step.window;
    const Vec2 g = world.settings.gravity;
    const double lead = snapshotLead(step);
    const double alpha = world.settings.damping.local;
    const double c = world.settings.damping.viscous;
    const double keep = (1.0 - 0.5 * c * w) / (1.0 + 0.5 * c * w);
    const double gain = w / (1.0 + 0.5 * c * w);
    MotionSums sums;
    double finite_check = 0.0;  // the new rates summed: non-finite if one of them is
    const uint32_t* pebble = world.bodies.hasClumps() ? b.clump.data() : nullptr;
    for (std::size_t s = 0; s < n; ++s) {
        if (pebble && pebble[s] != kNoClump) continue;  // moved with its clump (moveClumps)
        BallUpdate u{static_cast<uint32_t>(s),
                     b.vel[s],
                     Vec2::Zero(),
                     b.force[s] + b.fapp[s],
                     Vec2::Zero(),
                     b.spin[s],
                     0.0,
                     b.moment[s] + b.mapp[s],
                     0.0,
                     c,
                     c,
                     c};
        const uint8_t fix = b.fixity[s];
        if (alpha > 0.0) {
            // PFC applies the damping to the unbalanced force including gravity.
            const Vec2 unbalanced = u.f + b.mass[s] * g;
            u.fd = Vec2(localDamping(alpha, unbalanced.x(), u.v_old.x()),
                        localDamping(alpha, unbalanced.y(), u.v_old.y()));
            u.md = localDamping(alpha, u.mom, u.w_old);
        }
        const Vec2 acc = (u.f + u.fd) * b.inv_mass[s] + g;
        const double ang = (u.mom + u.md) * b.inv_inertia[s];
        u.v = keep * u.v_old + gain * acc;
        u.om = keep * u.w_old + gain * ang;
        // Damping coefficients per degree of freedom: a fixed component is driven, not damped.
        if (fix) {
            if (fix & kFixX) u.v.x() = u.v_old.x(), u.fd.x() = 0.0, u.cx = 0.0;
            if (fix & kFixY) u.v.y() = u.v_old.y(), u.fd.y() = 0.0, u.cy = 0.0;
            if (fix & kFixSpin) u.om = u.w_old, u.md = 0.0, u.cw = 0.0;
        }
        b.vel[s] = u.v;
        b.spin[s] = u.om;
        b.pos[s] += u.v * dt;
        b.angle[s] += u.om * dt;
        finite_check += u.v.x() + u.v.y() + u.om;
        if (step.energy) bookBall(world, step, lead, u, sums);
    }
    if (pebble)  // clump_motion.cpp
        moveClumps(world, step, sums.kinetic, sums.body, sums.damping, sums.driven);
    // (a clump's pebbles take its rates: a non-finite clump shows in the scan's balls)
    if (!std::isfinite(finite_check) || pebble) {
        bool finite = true;
        for (std::size_t s = 0; s < n && finite; ++s)
            finite = std::isfinite(b.vel[s].x() + b.vel[s].y() + b.spin[s]);
        if (!finite) reportNonFiniteBall(world);
    }
    if (step.energy)
        closeBooks(world, step, lead, sums.kinetic, sums.body, sums.damping, sums.driven);
}

void closeBooks(World& world, const StepContext& step, double lead, double kinetic, double body,
                double damping, double driven) {
    // Finite velocities can still overflow the energy books: a spin of 1e296 rad/s (an applied
    // moment of 1e300 N m, stress suite) has a kinetic energy of inf. A body far from every
    // contact then ran on with inf in the balance and no word.
    if (!std::isfinite(kinetic + body + damping + driven))
        reportNonFiniteEnergy(world, kinetic, body, damping, driven);
    EnergyBooks& books = world.books;
    // Impulses applied now span the window around t: the damping, the fixities' reactions
    // and the contact dashpots of the last force loop (forces at t). The kinetic energy at t
    // holds the share of their effect before t, so the snapshot holds the same share of
    // their work, the rest comes after it. (Booking a dashpot's whole work at once puts
    // the books half a step's dissipation ahead during an impact.) Where the books open, at
    // t, the share before t is not theirs: it is in the kinetic energy they start from.
    const double before = books.opening > 0 ? 0.0 : lead;
    books.stage = EnergyBooks::Stage::Open;
    if (books.opening > 0) openBooks(world, kinetic);
    books.acc.damping += damping * before;
    books.acc.boundary += driven * before;
    books.acc.dashpot += books.dashpot_pending * before;
    books.snapshot = books.acc;
    books.snapshot.kinetic = kinetic;
    if (books.stage != EnergyBooks::Stage::Waiting) {
        books.acc.body += body;
        books.acc.boundary += driven * (1.0 - lead);
        books.acc.damping += damping * (1.0 - lead);
        books.acc.dashpot += books.dashpot_pending * (1.0 - lead);
    }
    books.dashpot_pending = 0.0;
    if (step.groups) groupSnapshot(world, lead);
    if (books.opening > 0) {
        --books.opening;
        // The run-level check starts where the books do.
        world.guard_state.balance = GuardState::BalanceWatch{};
        world.guard_state.balance.open = books.snapshot;
        world.guard_state.balance.open_step = world.clock.step;
    }
}

}  // namespace

/// Tracing was switched on (api/energy.cpp, books.opening): the books open at the present whole
/// step t of this snapshot, from the kinetic energy at t (the half-step velocities
/// interpolated, as every snapshot does) and what the contacts hold at t, and from nothing
/// else: whatever was booked before t goes. Opened at the step after the switch, the kinetic
/// energy at t needs the velocity after it; so the books could not open when tracing was
/// switched on, between two steps, where only the half-step velocities are known (their
/// kinetic energy is off from that at t by m v a dt / 2: 1.7% of the throughput in free fall).
/// What loaded contacts hold at t only their models know, and they say it only while tracing
/// is on: then this snapshot waits (Stage::Waiting: it books nothing, its balance is zero) and
/// the books open at the next one, from what the contacts reported at that step.
void openBooks(World& world, double kinetic) {
    EnergyBooks& books = world.books;
    const bool waiting = books.opening == 2;
    const double strain = books.acc.strain, bond = books.acc.bond;
    books.acc = EnergyTotals{};
    books.acc.initial_kinetic = kinetic;
    books.acc.kinetic = kinetic;
    if (!waiting) {
        books.acc.strain = strain;
        books.acc.bond = bond;
        books.acc.initial_strain = strain + bond;
    }
    books.stage = waiting ? EnergyBooks::Stage::Waiting : EnergyBooks::Stage::Opened;
}

void reportNonFiniteBall(const World& world) {
    const auto& b = world.bodies.balls;
    for (std::size_t s = 0; s < b.size(); ++s) {
        const Vec2& v = b.vel[s];
        if (std::isfinite(v.x() + v.y() + b.spin[s] + b.pos[s].x() + b.pos[s].y())) continue;
        throwNonFinite(world, world.bodies.describeBall(static_cast<uint32_t>(s)) + ": velocity (" +
                                  text(v.x()) + ", " + text(v.y()) + "), spin " + text(b.spin[s]) +
                                  ", contact force (" + text(b.force[s].x()) + ", " +
                                  text(b.force[s].y()) + ")");
    }
}

void reportNonFiniteEnergy(const World& world, double kinetic, double body, double damping,
                           double driven) {
    // Name the first body whose kinetic energy 1/2 (m v^2 + I w^2) overflows.
    const auto& b = world.bodies.balls;
    auto overflows = [](double m, const Vec2& v, double inertia, double om) {
        return !std::isfinite(0.5 * (m * v.squaredNorm() + inertia * om * om));
    };
    std::string who;
    for (std::size_t s = 0; s < b.size() && who.empty(); ++s) {
        if (world.bodies.hasClumps() && b.clump[s] != kNoClump) continue;
        if (overflows(b.mass[s], b.vel[s], b.inertia[s], b.spin[s]))
            who = world.bodies.describeBall(static_cast<uint32_t>(s)) + ": velocity (" +
                  text(b.vel[s].x()) + ", " + text(b.vel[s].y()) + "), spin " + text(b.spin[s]) +
                  ", ";
    }
    for (std::size_t i = 0; i < world.bodies.clumps.size() && who.empty(); ++i) {
        const ClumpData& c = world.bodies.clumps[i];
        if (c.alive && overflows(c.mass, c.vel, c.inertia, c.spin))
            who = "clump " + std::to_string(i + 1) + ": velocity (" + text(c.vel.x()) + ", " +
                  text(c.vel.y()) + "), spin " + text(c.spin) + ", ";
    }
    // No kinetic energy overflows: the work of an applied load did (body work F.v dt or M w dt
    // with a finite but huge load). Name the body carrying the largest applied load.
    double largest = 0.0;
    std::string loaded;
    for (std::size_t s = 0; s < b.size(); ++s) {
        const double load = b.fapp[s].norm() + std::fabs(b.mapp[s]);
        if (!(world.bodies.hasClumps() && b.clump[s] != kNoClump) && load > largest)
            largest = load, loaded = world.bodies.describeBall(static_cast<uint32_t>(s)) +
                                     ": applied force (" + text(b.fapp[s].x()) + ", " +
                                     text(b.fapp[s].y()) + "), moment " + text(b.mapp[s]) + ", ";
    }
    for (std::size_t i = 0; i < world.bodies.clumps.size(); ++i) {
        const ClumpData& c = world.bodies.clumps[i];
        const double load = c.fapp.norm() + std::fabs(c.mapp);
        if (c.alive && load > largest)
            largest = load, loaded = "clump " + std::to_string(i + 1) + ": applied force (" +
                                     text(c.fapp.x()) + ", " + text(c.fapp.y()) + "), moment " +
                                     text(c.mapp) + ", ";
    }
    if (who.empty()) who = loaded;
    throwNonFinite(world, who + "the energy of this step overflows (kinetic " + text(kinetic) +
                              " J, body work " + text(body) + " J, damping " + text(damping) +
                              " J, fixity work " + text(driven) + " J)");
}

void moveWalls(World& world, const StepContext& step) {
    const double dt = step.dt;
    for (std::size_t i = 0; i < world.bodies.walls.size(); ++i) {
        WallData& w = world.bodies.walls[i];
        if (!w.alive || (w.vel.squaredNorm() == 0.0 && w.spin == 0.0)) continue;
        if (world.books.on) {
            // Work done on the balls: minus the force they exert on the wall times its motion,
            // over the step the wall moves in. That force is the last force loop's (at t, the
            // snapshot's time), its impulse applied over the window around t: its share before
            // t, with the velocity the wall moved at then, was booked after that loop
            // (bookWallsBefore, bookkeeping.cpp); here the share after t, with this step's
            // velocity, over half this step. (Booking the whole window with this step's
            // velocity, as before 2026-11-28, was off by F (v - v_before) dt / 2 in every step
            // a servo changed the wall's velocity.)
            const double work = -(w.force.dot(w.vel) + w.moment * w.spin) * 0.5 * dt;
            world.books.acc.boundary += work;
            if (world.books.groups.on) bookWallToGroups(world, w.groups, work);
        }
        const Vec2 shift = w.vel * dt;
        const double ca = std::cos(w.spin * dt), sa = std::sin(w.spin * dt);
        for (uint32_t k = 0; k < w.vertex_count; ++k) {
            Vec2& p = world.bodies.vertices[w.first_vertex + k];
            const Vec2 r = p - w.center;
            p = w.center + Vec2(ca * r.x() - sa * r.y(), sa * r.x() + ca * r.y()) + shift;
        }
        w.center += shift;
    }
}

}  // namespace talus
