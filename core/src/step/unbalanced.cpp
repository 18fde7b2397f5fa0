// SPDX-License-Identifier: MIT
//
// PFC's mechanical ratio (UnbalancedForce): the mean over the free bodies of the magnitude of
// the net force on each (contact + applied + gravity; damping excluded; fixed components left
// out, a body fixed in x and y not counted), over the mean magnitude of the contact forces that
// are not zero. Read from the forces the last force loop left, so it costs one pass over the
// bodies and one over the contacts, and only when asked: by Model::unbalanced (a query) and by
// a servo's equilibrium hold (servo.cpp), which asks every step it runs.
#include <algorithm>
#include <cmath>
#include <limits>

#include "step/step.hpp"
#include "world/body_store.hpp"
#include "world/contact_store.hpp"
#include "world/types.hpp"

namespace talus {

UnbalancedForce unbalancedForce(const World& world) {
    const auto& b = world.bodies.balls;
    UnbalancedForce u;
    double sum = 0.0;
    const auto body = [&](Vec2 f, uint8_t fix) {
        if ((fix & kFixX) && (fix & kFixY)) return;
        if (fix & kFixX) f.x() = 0.0;
        if (fix & kFixY) f.y() = 0.0;
        const double m = f.norm();
        sum += m;
        u.max_unbalanced = std::max(u.max_unbalanced, m);
        ++u.bodies;
    };
    const auto& clumps = world.bodies.clumps;
    std::vector<Vec2> clump_force(clumps.size(), Vec2::Zero());
    for (std::size_t s = 0; s < b.size(); ++s) {
        if (b.clump[s] != kNoClump) {
            clump_force[b.clump[s]] += b.force[s];
            continue;
        }
        body(b.force[s] + b.fapp[s] + b.mass[s] * world.settings.gravity, b.fixity[s]);
    }
    for (std::size_t k = 0; k < clumps.size(); ++k) {
        const ClumpData& c = clumps[k];
        if (!c.alive) continue;
        body(clump_force[k] + c.fapp + c.mass * world.settings.gravity, c.fixity);
    }
    double csum = 0.0;
    for (const Pair& p : world.contacts.pairs) {
        if (!p.active || (p.n_force == 0.0 && p.s_force == 0.0)) continue;
        csum += std::sqrt(p.n_force * p.n_force + p.s_force * p.s_force);
        ++u.contacts;
    }
    u.mean_unbalanced = u.bodies > 0 ? sum / static_cast<double>(u.bodies) : 0.0;
    u.mean_contact = u.contacts > 0 ? csum / static_cast<double>(u.contacts) : 0.0;
    // No contact force at all: nothing is held in equilibrium by contacts (balls in flight, or
    // not yet touching), so the ratio is infinite and solve{ratio} does not stop on it.
    u.ratio = u.mean_contact > 0.0 ? u.mean_unbalanced / u.mean_contact
                                   : std::numeric_limits<double>::infinity();
    return u;
}

}  // namespace talus
