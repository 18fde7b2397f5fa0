// SPDX-License-Identifier: MIT
//
// Phase 5: bookkeeping. Events queued by the force loop (bond breaks) are delivered here, after
// the hot loop and in the order they happened, then the cycle hooks run (histories, Lua
// callbacks). Guard findings are aggregated over a cycle()/solve() call and reported once.
// Also: energy tracing switches and the profile report.
#include <algorithm>
#include <cstdio>
#include <sstream>

#include "model_internal.hpp"
#include "talus/errors.hpp"

namespace talus {

void Model::bookkeeping() {
    if (!m_events.empty()) {
        // Swap out first: a handler may cycle the model or queue events of its own.
        std::vector<Event> events;
        events.swap(m_events);
        if (m_event_handler)
            for (const Event& e : events) m_event_handler(e);
    }
    if (m_hooks.empty()) return;
    // A hook may add or remove hooks: removals only mark (every = 0) while we iterate, and hooks
    // added now first run at the next step.
    ++m_hooks_running;
    const std::size_t n = m_hooks.size();
    for (std::size_t i = 0; i < n; ++i) {
        if (m_hooks[i].every > 0 && m_step % m_hooks[i].every == 0) {
            auto fn = m_hooks[i].fn;  // copy: the vector may grow during the call
            fn(*this);
        }
    }
    if (--m_hooks_running == 0)
        m_hooks.erase(std::remove_if(m_hooks.begin(), m_hooks.end(),
                                     [](const Hook& h) { return h.every == 0; }),
                      m_hooks.end());
}

int Model::addCycleHook(int64_t every, std::function<void(Model&)> fn) {
    if (every <= 0) throw InputError("hook: 'every' must be >= 1");
    m_hooks.push_back(Hook{m_next_hook, every, std::move(fn)});
    return m_next_hook++;
}

void Model::removeCycleHook(int handle) {
    for (std::size_t i = 0; i < m_hooks.size(); ++i)
        if (m_hooks[i].handle == handle) {
            if (m_hooks_running > 0)
                m_hooks[i].every = 0;  // erased after the hooks of this step have run
            else
                m_hooks.erase(m_hooks.begin() + static_cast<std::ptrdiff_t>(i));
            return;
        }
}

void Model::flushWarnings() {
    if (m_underresolved > 0) {
        warn("guard: " + std::to_string(m_underresolved) + " contact(s) had fewer than " +
             std::to_string(m_guard.min_steps) +
             " steps per contact duration, so their restitution and peak force are not "
             "resolved (thesis A asks for 10-20 steps per impact); first: " +
             m_underresolved_first +
             ". Use the automatic step with its resolution rule, or a smaller fixed step.");
        m_underresolved = 0;
    }
    if (m_stiffness_lies > 0) {
        warn(
            "guard: " + std::to_string(m_stiffness_lies) +
            " contact(s) were stiffer than their model reported; first: " + m_stiffness_lies_first);
        m_stiffness_lies = 0;
    }
    if (m_energy_gain > 0) {
        warn("guard: " + std::to_string(m_energy_gain) +
             " contact(s) gave back more energy than they took; first: " + m_energy_gain_first);
        m_energy_gain = 0;
    }
}

void Model::setEnergyTracing(bool on) {
    if (on && !m_energy_on) {
        m_energy_acc = EnergyTotals{};
        const auto& b = *m_balls;
        double ke = 0.0;
        for (std::size_t s = 0; s < b.size(); ++s)
            ke += 0.5 * (b.mass[s] * b.vel[s].squaredNorm() + b.inertia[s] * b.spin[s] * b.spin[s]);
        m_energy_acc.initial_kinetic = ke;
        m_energy_acc.kinetic = ke;
        // Models report stored energy only while tracing is on; until the next step it is not
        // known.
        m_energy_acc.strain = 0.0;
        for (auto& c : m_cold) c.strain = c.bond = 0.0;
        m_energy = m_energy_acc;
    }
    m_energy_on = on;
}

EnergyTotals Model::energies() const {
    if (!m_energy_on)
        throw InputError("energies: energy tracing is off (call energy{on = true} first)");
    return m_energy;
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
       << ", contacts created " << contacts_created << "\n";
    return os.str();
}

}  // namespace talus
