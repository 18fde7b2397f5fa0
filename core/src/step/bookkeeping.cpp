// SPDX-License-Identifier: MIT
//
// Phase 5: bookkeeping. Events queued by the force loop (bond breaks) are delivered here, after
// the hot loop and in the order they happened, then the trackers take their sample
// (step/trackers.cpp), then the cycle hooks run (histories, Lua callbacks). Guard findings are
// aggregated over a cycle()/solve() call and reported once.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "step/barriers.hpp"
#include "step/group_energy.hpp"
#include "step/step.hpp"
#include "step/trackers.hpp"
#include "talus/errors.hpp"
#include "world/body_store.hpp"
#include "world/contact_store.hpp"
#include "world/messages.hpp"
#include "world/types.hpp"

namespace talus {

void bookkeeping(World& world, const StepContext& step) {
    if (!world.guard_state.energy_gains.empty()) judgeEnergyGains(world, true);
    if (step.energy) bookWallsBefore(world, step);
    if (step.energy && world.settings.guard.balance != GuardAction::Off) checkBalance(world);
    if (!world.callbacks.events.empty()) {
        // Swap out first: a handler may queue events of its own (delete a ball, break a bond).
        std::vector<Event> events;
        events.swap(world.callbacks.events);
        if (world.callbacks.event_handler)
            for (const Event& e : events) world.callbacks.event_handler(e);
    }
    // The barriers, then the trackers' sample of this step, which sees a body a barrier caught
    // as the barrier saw it; both before the hooks (they read what was recorded).
    if (!world.barriers.list.empty()) applyBarriers(world, step);
    if (world.trackers.live > 0) updateTrackers(world);
    world.barriers.acted.clear();
    if (world.callbacks.hooks.empty()) return;
    // A hook may add or remove hooks: removals only mark (every = 0) while we iterate, and hooks
    // added now first run at the next step.
    ++world.callbacks.hooks_running;
    const std::size_t n = world.callbacks.hooks.size();
    for (std::size_t i = 0; i < n; ++i) {
        if (world.callbacks.hooks[i].every > 0 &&
            world.clock.step % world.callbacks.hooks[i].every == 0) {
            auto fn = world.callbacks.hooks[i].fn;  // copy: the vector may grow during the call
            fn(world.facade);
        }
    }
    if (--world.callbacks.hooks_running == 0)
        world.callbacks.hooks.erase(
            std::remove_if(world.callbacks.hooks.begin(), world.callbacks.hooks.end(),
                           [](const Hook& h) { return h.every == 0; }),
            world.callbacks.hooks.end());
}

namespace {

std::string num(double v) { return messageNumber(v, 4); }

/// The energy the scene holds now: the kinetic energy of its bodies (balls, clumps) and the
/// contacts' strain energy estimated from their forces, F^2 / (2 k) with their models' normal
/// and shear estimates (KnEstimate, KsEstimate: the stiffness for the time step, raised for a
/// dashpot, so an estimate from below); with tracing on, at least the run's throughput (as the
/// balance check's reference). Called only in a step with a finding to judge.
double sceneEnergy(const World& world) {
    const auto& b = world.bodies.balls;
    const bool clumps = world.bodies.hasClumps();
    double energy = 0.0;
    for (std::size_t s = 0; s < b.size(); ++s)
        if (!clumps || b.clump[s] == kNoClump)  // a pebble moves with its clump
            energy +=
                0.5 * (b.mass[s] * b.vel[s].squaredNorm() + b.inertia[s] * b.spin[s] * b.spin[s]);
    for (const ClumpData& c : world.bodies.clumps)
        if (c.alive) energy += 0.5 * (c.mass * c.vel.squaredNorm() + c.inertia * c.spin * c.spin);
    for (const Pair& p : world.contacts.pairs) {
        if (!p.active || !p.model) continue;
        const double kn = p.model->KnEstimate(), ks = p.model->KsEstimate();
        if (kn > 0.0) energy += 0.5 * p.n_force * p.n_force / kn;
        if (ks > 0.0) energy += 0.5 * p.s_force * p.s_force / ks;
    }
    if (world.books.on) {
        const EnergyTotals& e = world.books.snapshot;
        energy = std::max(
            {energy, e.input(), e.kinetic + e.strain + e.bond, world.guard_state.balance.peak});
    }
    return energy;
}

/// Where the energy is: the body with the most kinetic energy now, for a balance finding ("; the
/// most kinetic energy: ball 3 at (x, y), 12 J"). Called only with a finding to report.
std::string mostKinetic(const World& world) {
    const auto& b = world.bodies.balls;
    double most = -1.0;
    std::string who;
    for (std::size_t s = 0; s < b.size(); ++s) {
        if (b.clump[s] != kNoClump) continue;
        const double ke =
            0.5 * (b.mass[s] * b.vel[s].squaredNorm() + b.inertia[s] * b.spin[s] * b.spin[s]);
        if (ke > most) most = ke, who = world.bodies.describeBall(static_cast<uint32_t>(s));
    }
    for (std::size_t i = 0; i < world.bodies.clumps.size(); ++i) {
        const ClumpData& c = world.bodies.clumps[i];
        const double ke = 0.5 * (c.mass * c.vel.squaredNorm() + c.inertia * c.spin * c.spin);
        if (c.alive && ke > most)
            most = ke, who = "clump " + std::to_string(i + 1) + " at " + vecText(c.pos);
    }
    return who.empty() ? std::string()
                       : "; the most kinetic energy: " + who + ", " + num(most) + " J";
}

}  // namespace

void bookWallsBefore(World& world, const StepContext& step) {
    // A moving wall's work on the balls over the second half of this step: the force the force
    // loop just found (at the next snapshot's time) times the velocity the wall moved at in
    // this step, over half of it. It comes before that snapshot; moveWalls books the half
    // after it, with the next step's velocity.
    for (const WallData& w : world.bodies.walls) {
        if (!w.alive || (w.vel.squaredNorm() == 0.0 && w.spin == 0.0)) continue;
        const double work = -(w.force.dot(w.vel) + w.moment * w.spin) * 0.5 * step.dt;
        world.books.acc.boundary += work;
        if (world.books.groups.on) bookWallToGroups(world, w.groups, work);
    }
}

void judgeEnergyGains(World& world, bool may_throw) {
    // A contact's gain is judged against its own peak (endContact); this floor keeps out gains
    // that are nothing on the scale of the scene. The energy books are sums over up to ~1e7
    // steps, each adding terms with a relative round-off of 1e-16: they, and the balance check
    // that reads them, cannot resolve less than ~1e-9 of the energy the scene holds. Contacts
    // that touch for a step or two in a settled pack (their reference a few 1e-11 J, their
    // ends pushed about by their neighbours) gain up to ~1e-10 J that way, ~1e-10 of the
    // pack's energy (docs/physics/guard.md); a contact of an impact that the step does not
    // resolve gains a share of the impact's energy, far above the floor in any scene of fewer
    // than ~1e7 such bodies.
    auto& gains = world.guard_state.energy_gains;
    const double scene = sceneEnergy(world);
    const double floor = 1e-9 * scene;
    const GuardSettings& gs = world.settings.guard;
    for (const auto& gain : gains) {
        if (!(gain.gained > floor)) continue;
        // A contact that made more than severe_created of the energy the whole scene holds (or,
        // traced, has moved) is no resolution error of a pack's contact, pushed about by its
        // neighbours: it made the run's energy (docs/physics/guard.md, "Severe findings").
        const bool severe =
            gs.severe == GuardAction::Error && gain.gained > gs.severe_created * scene;
        if (may_throw && (gs.energy == GuardAction::Error || severe)) {
            const std::string what =
                gain.what +
                (severe ? severeNote("more than " + num(100.0 * gs.severe_created) +
                                     "% of the scene's energy " + num(scene) + " J, severe_created")
                        : std::string());
            gains.clear();
            throw NumericalError("energy created: " + what);
        }
        if (world.guard_state.energy_gain++ == 0) world.guard_state.energy_gain_first = gain.what;
    }
    gains.clear();
}

void checkBalance(World& world) {
    // Each contact is checked by the guard on its own; this check watches the whole model, so
    // that many small errors that add up, and work outside contacts (damping, fixities, walls),
    // cannot go unseen. Reference: the throughput, the larger of the energy put in and the peak
    // mechanical energy, so that a scene that turns its input over many times (a ball bouncing
    // on a vibrating floor) is judged against what it moved, not what it holds now.
    const EnergyTotals& e = world.books.snapshot;  // snapshot at the last whole step
    world.guard_state.balance.peak =
        std::max(world.guard_state.balance.peak, e.kinetic + e.strain + e.bond);
    if (world.clock.step % world.settings.guard.balance_every != 0) return;
    const double throughput = std::max(e.input(), world.guard_state.balance.peak);
    const double error = e.balanceError();
    const double allowed = world.settings.guard.balance_tolerance * throughput;
    if (std::fabs(error) <= allowed) {
        world.guard_state.balance.open = e;
        world.guard_state.balance.open_step = world.clock.step;
        world.guard_state.balance.reported = 0.0;
        return;
    }
    if (std::fabs(error - world.guard_state.balance.reported) <= allowed) return;
    world.guard_state.balance.reported = error;

    // Name the window and the items that moved most in it.
    struct Item {
        const char* name;
        double change;
    };
    const EnergyTotals& o = world.guard_state.balance.open;
    Item items[] = {{"kinetic", e.kinetic - o.kinetic},
                    {"strain", e.strain - o.strain},
                    {"bond", e.bond - o.bond},
                    {"body", e.body - o.body},
                    {"boundary", e.boundary - o.boundary},
                    {"slip", e.slip - o.slip},
                    {"dashpot", e.dashpot - o.dashpot},
                    {"plastic", e.plastic - o.plastic},
                    {"damping", e.damping - o.damping},
                    {"released", e.released - o.released},
                    {"placement", e.placement - o.placement},
                    {"script", e.script - o.script},
                    {"barrier", e.barrier - o.barrier}};
    std::stable_sort(std::begin(items), std::end(items), [](const Item& a, const Item& b) {
        return std::fabs(a.change) > std::fabs(b.change);
    });
    std::string moved;
    for (int k = 0; k < 3; ++k)
        moved += std::string(k ? ", " : "") + items[k].name + " " +
                 (items[k].change >= 0.0 ? "+" : "") + num(items[k].change) + " J";
    const std::string what =
        "energy balance: " + num(std::fabs(error)) + " J " + (error < 0.0 ? "created" : "lost") +
        " (balance_error " + num(error) + " J, " + num(100.0 * std::fabs(error) / throughput) +
        "% of the throughput " + num(throughput) + " J, tolerance " +
        num(100.0 * world.settings.guard.balance_tolerance) + "%) at step " +
        std::to_string(world.clock.step) + " (t = " + num(world.clock.time) + " s); in steps " +
        std::to_string(world.guard_state.balance.open_step) + "-" +
        std::to_string(world.clock.step) + " the items that moved most: " + moved +
        mostKinetic(world);
    // Energy created beyond severe_created of the throughput: no sound run does that.
    const bool severe = world.settings.guard.severe == GuardAction::Error && error < 0.0 &&
                        -error > world.settings.guard.severe_created * throughput;
    if (severe)
        throw NumericalError(what + severeNote("more than " +
                                               num(100.0 * world.settings.guard.severe_created) +
                                               "% of the throughput created, severe_created"));
    if (world.settings.guard.balance == GuardAction::Error) throw NumericalError(what);
    if (world.guard_state.balance.findings++ == 0) world.guard_state.balance.first = what;
    world.guard_state.balance.last = what;
}

void flushWarnings(World& world) {
    // (gains left by a step that did not finish: reported, not thrown, beside its error)
    if (!world.guard_state.energy_gains.empty()) judgeEnergyGains(world, false);
    if (world.guard_state.placed > 0) {
        talus::warn(
            world,
            std::to_string(world.guard_state.placed) +
                " contact(s) started overlapping (bodies created or moved into each other), "
                "holding "
                "energy no traced work put in (" +
                num(world.guard_state.placed_energy) +
                " J in all, booked as the energy item 'placement' when tracing is on); first: " +
                world.guard_state.placed_first);
        world.guard_state.placed = 0;
        world.guard_state.placed_energy = 0.0;
    }
    if (world.guard_state.balance.findings > 0) {
        talus::warn(world, "guard: " + world.guard_state.balance.first +
                               (world.guard_state.balance.findings > 1
                                    ? "; it grew further " +
                                          std::to_string(world.guard_state.balance.findings - 1) +
                                          " time(s), last: " + world.guard_state.balance.last
                                    : std::string()));
        world.guard_state.balance.findings = 0;
    }
    if (world.guard_state.underresolved > 0) {
        talus::warn(
            world,
            "guard: " + std::to_string(world.guard_state.underresolved) +
                " contact(s) had fewer than " + std::to_string(world.settings.guard.min_steps) +
                " steps per contact duration, so their restitution and peak force are not "
                "resolved (An 2006 asks for 10-20 steps per impact); first: " +
                world.guard_state.underresolved_first +
                ". Use the automatic step with its resolution rule, or a smaller fixed step.");
        world.guard_state.underresolved = 0;
    }
    if (world.guard_state.stiffness_lies > 0) {
        talus::warn(world, "guard: " + std::to_string(world.guard_state.stiffness_lies) +
                               " contact(s) were stiffer than their model reported; first: " +
                               world.guard_state.stiffness_lies_first);
        world.guard_state.stiffness_lies = 0;
    }
    if (world.guard_state.energy_gain > 0) {
        talus::warn(world, "guard: " + std::to_string(world.guard_state.energy_gain) +
                               " contact(s) gave back more energy than they took; first: " +
                               world.guard_state.energy_gain_first);
        world.guard_state.energy_gain = 0;
    }
}

}  // namespace talus
