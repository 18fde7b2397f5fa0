// SPDX-License-Identifier: MIT
//
// The force loop's test switches (core/testing/force_switches.hpp).
#include "force/force.hpp"
#include "force_switches.hpp"
#include "world/lanes.hpp"
#include "world/world.hpp"

namespace talus::testing {

void setKernels(Model& model, bool on) {
    World& world = worldOf(model);
    if (!on) leaveAllLanes(world);
    world.settings.kernels = on;
}

bool kernels(const Model& model) { return worldOf(model).settings.kernels; }

int forceThreads(const Model& model, std::size_t npairs) {
    return talus::forceThreads(worldOf(model), npairs);
}

}  // namespace talus::testing
