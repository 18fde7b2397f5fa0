// SPDX-License-Identifier: MIT
//
// The facade, barriers: creating one (every field checked) and reading what it caught
// (docs/rockfall.md, "Barriers"). The data is world/barriers.hpp, the per-step check
// step/barriers.cpp.
#include <cmath>
#include <string>

#include "api/input_checks.hpp"
#include "talus/errors.hpp"
#include "talus/model.hpp"
#include "world/messages.hpp"
#include "world/world.hpp"

namespace talus {

int Model::createBarrier(const BarrierDef& def) {
    World& world = *m_world;
    const std::string what = "barrier" + (def.name.empty() ? std::string() : " '" + def.name + "'");
    requireCoordinate(what + ": from", def.from);
    requireCoordinate(what + ": to", def.to);
    const double length = (def.to - def.from).norm();
    if (!(length > 0.0))
        throw InputError(what + " has zero length (from " + vecText(def.from) + " to " +
                         vecText(def.to) + "): a barrier needs two distinct points");
    if (!(def.energy >= 0.0) || !std::isfinite(def.energy))
        throw InputError(what + ": energy (its capacity) must be a finite energy >= 0 J (got " +
                         messageNumber(def.energy) + ")");
    Barrier b;
    b.info.def = def;
    b.dir = (def.to - def.from) / length;
    b.length = length;
    world.barriers.list.push_back(std::move(b));
    return static_cast<int>(world.barriers.list.size());
}

std::size_t Model::barrierCount() const { return m_world->barriers.list.size(); }

BarrierInfo Model::barrierInfo(int id) const {
    const auto& list = m_world->barriers.list;
    if (id < 1 || static_cast<std::size_t>(id) > list.size())
        throw InputError("barrier " + std::to_string(id) + " does not exist (" +
                         std::to_string(list.size()) + " barrier(s))");
    return list[static_cast<std::size_t>(id - 1)].info;
}

}  // namespace talus
