// SPDX-License-Identifier: MIT
//
// Phase 5: bookkeeping. Events queued by the force loop (bond breaks) are delivered here, after
// the hot loop and in the order they happened, then the cycle hooks run (histories, Lua
// callbacks). Guard findings are aggregated over a cycle()/solve() call and reported once.
// Also: energy tracing switches and the profile report.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "body_store.hpp"
#include "contact_store.hpp"
#include "engine.hpp"
#include "model_internal.hpp"
#include "talus/errors.hpp"

namespace talus {

void bookkeeping(World& world) {
    if (world.books.on && world.settings.guard.balance != GuardAction::Off) checkBalance(world);
    if (!world.callbacks.events.empty()) {
        // Swap out first: a handler may cycle the model or queue events of its own.
        std::vector<Event> events;
        events.swap(world.callbacks.events);
        if (world.callbacks.event_handler)
            for (const Event& e : events) world.callbacks.event_handler(e);
    }
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

int Model::addCycleHook(int64_t every, std::function<void(Model&)> fn) {
    World& world = *m_world;
    if (every <= 0) throw InputError("hook: 'every' must be >= 1");
    world.callbacks.hooks.push_back(Hook{world.callbacks.next_hook, every, std::move(fn)});
    return world.callbacks.next_hook++;
}

void Model::removeCycleHook(int handle) {
    World& world = *m_world;
    for (std::size_t i = 0; i < world.callbacks.hooks.size(); ++i)
        if (world.callbacks.hooks[i].handle == handle) {
            if (world.callbacks.hooks_running > 0)
                world.callbacks.hooks[i].every = 0;  // erased after the hooks of this step have run
            else
                world.callbacks.hooks.erase(world.callbacks.hooks.begin() +
                                            static_cast<std::ptrdiff_t>(i));
            return;
        }
}

namespace {

std::string num(double v) { return messageNumber(v, 4); }

}  // namespace

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
                    {"placement", e.placement - o.placement}};
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
        std::to_string(world.clock.step) + " the items that moved most: " + moved;
    if (world.settings.guard.balance == GuardAction::Error) throw NumericalError(what);
    if (world.guard_state.balance.findings++ == 0) world.guard_state.balance.first = what;
    world.guard_state.balance.last = what;
}

void flushWarnings(World& world) {
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
                "resolved (thesis A asks for 10-20 steps per impact); first: " +
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

void Model::setEnergyTracing(bool on) {
    World& world = *m_world;
    if (on && !world.books.on) {
        world.books.acc = EnergyTotals{};
        const auto& b = world.bodies.balls;
        double ke = 0.0;
        for (std::size_t s = 0; s < b.size(); ++s)
            if (b.clump[s] == kNoClump)  // a pebble's motion is its clump's (below)
                ke += 0.5 *
                      (b.mass[s] * b.vel[s].squaredNorm() + b.inertia[s] * b.spin[s] * b.spin[s]);
        for (const ClumpData& c : world.bodies.clumps)
            if (c.alive) ke += 0.5 * (c.mass * c.vel.squaredNorm() + c.inertia * c.spin * c.spin);
        world.books.acc.initial_kinetic = ke;
        world.books.acc.kinetic = ke;
        world.books.dashpot_pending = 0.0;
        world.books.strain_baseline_pending = false;
        for (const Pair& p : world.contacts.pairs) world.books.strain_baseline_pending |= p.active;
        world.guard_state.balance = GuardState::BalanceWatch{};
        world.guard_state.balance.open = world.books.acc;
        world.guard_state.balance.open_step = world.clock.step;
        // Models report stored energy only while tracing is on; until the next step it is not
        // known.
        world.books.acc.strain = 0.0;
        for (auto& c : world.contacts.cold) c.strain = c.bond = 0.0;
        world.books.snapshot = world.books.acc;
        world.books.on = true;
        world.books.groups = EnergyBooks::GroupBooks{};
        openGroupBooks(world);
    }
    world.books.on = on;
    if (!on) world.books.groups = EnergyBooks::GroupBooks{};  // tracing off: no group books
}

EnergyTotals Model::energies() const {
    const World& world = *m_world;
    if (!world.books.on)
        throw InputError("energies: energy tracing is off (call energy{on = true} first)");
    return world.books.snapshot;
}

std::string Profile::report(std::size_t balls) const {
    std::ostringstream os;
    const double tot = total();
    auto line = [&](const char* name, double t) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "  %-20s %10.4f s  %5.1f%%  %8.2f ns/ball-step\n", name, t,
                      tot > 0 ? 100.0 * t / tot : 0.0,
                      (cycles > 0 && balls > 0) ? 1e9 * t / double(cycles) / double(balls) : 0.0);
        os << buf;
    };
    os << "profile over " << cycles << " cycles:\n";
    line("timestep", timestep);
    line("law of motion", motion);
    line("contact detection", detection);
    line("force-displacement", force_displacement);
    line("bookkeeping", bookkeeping);
    line("total", tot);
    os << "  broadphase re-insertions " << proxy_moves << ", pairs created " << pairs_created
       << ", contacts created " << contacts_created << ", batched laws " << batched_laws
       << ", lane steps " << lane_steps << " (declined " << lane_declined << ")"
       << ", threaded steps " << threaded_steps << "\n";
    return os.str();
}

}  // namespace talus
