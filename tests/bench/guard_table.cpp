// SPDX-License-Identifier: MIT
//
// What the stability guard does with a model that under-reports its stiffness: the test plugin
// `liar` (tests/plugins/liar) is a linear spring kn that reports knest = kn / lie and a contact
// duration to match. For each lie, 200 impacts (ball on a wall, 1 m/s, kn = 1e8 N/m, R = 0.1 m,
// default step rules) at phases of first touch spread over a step, each run once per guard check
// set to Error. Prints the table of docs/physics/guard.md. Not run by ctest.
#include <algorithm>
#include <cstdio>

#include "talus/errors.hpp"
#include "talus/impact_rig.hpp"

using namespace talus;

namespace {

ImpactSetup impact(double lie, double gap) {
    ImpactSetup s;
    s.model = "liar";
    s.props = {{"kn", 1e8}, {"lie", lie}};
    s.radius = 0.1;
    s.density = 2600.0;
    s.normal_speed = 1.0;
    s.gap = gap;
    s.guard = GuardSettings::allOff();
    return s;
}

bool stops(ImpactSetup s) {
    try {
        runImpact(s);
    } catch (const NumericalError&) {
        return true;
    }
    return false;
}

}  // namespace

int main() {
    std::printf(
        "| lie | steps per impact | restitution range | impacts creating > 1%% energy | "
        "stopped by the energy check | by the stiffness check | by the resolution check |\n"
        "|---|---|---|---|---|---|---|\n");
    for (double lie : {1000.0, 100.0, 30.0, 10.0, 3.0, 1.0}) {
        const int n = 200;
        int created = 0, by_energy = 0, by_stiffness = 0, by_resolution = 0;
        double e_min = 1e300, e_max = 0.0;
        long s_min = 1L << 40, s_max = 0;
        for (int i = 0; i < n; ++i) {
            // Gaps spread over many steps' travel: the phase of first touch runs through a step.
            const double gap = 1e-4 * (0.1 + 0.9 * i / double(n)) * (lie >= 100.0 ? 10.0 : 1.0);
            const ImpactResult r = runImpact(impact(lie, gap));
            e_min = std::min(e_min, r.restitution), e_max = std::max(e_max, r.restitution);
            s_min = std::min(s_min, long(r.steps_in_contact));
            s_max = std::max(s_max, long(r.steps_in_contact));
            created += r.restitution * r.restitution > 1.01;
            ImpactSetup s = impact(lie, gap);
            s.guard.energy = GuardAction::Error;
            by_energy += stops(s);
            s = impact(lie, gap);
            s.guard.stiffness = GuardAction::Error;
            by_stiffness += stops(s);
            s = impact(lie, gap);
            s.guard.resolution = GuardAction::Error;
            by_resolution += stops(s);
        }
        std::printf("| %g | %ld-%ld | %.3f - %.3f | %d / %d | %d | %d | %d |\n", lie, s_min, s_max,
                    e_min, e_max, created, n, by_energy, by_stiffness, by_resolution);
    }
    return 0;
}
