// SPDX-License-Identifier: MIT
// Size and time of m:save / talus.restore for a dense pack (docs/save-format.md, "Cost").
// Usage: talus_bench_save_restore [N=50000] [steps=1500] [file=/tmp/talus_bench.talus]
// Builds the dense-pack scene of the speed benchmark (core/testing/scenes.cpp) with the disks
// starting almost in touch (lattice gap 1e-3), cycles `steps` fixed steps so that the pack loads
// its contacts under gravity, then saves to `file` and restores it three times each and prints the
// smallest times, the file size and the contacts. A restored model must save to the same bytes
// (checked: the benchmark fails otherwise). Not run by ctest: timings are never asserted.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "talus/model.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/save_file.hpp"
#include "talus/scenes.hpp"

using namespace talus;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
    DensePackDef def;
    def.n = argc > 1 ? std::atoi(argv[1]) : 50000;
    const int steps = argc > 2 ? std::atoi(argv[2]) : 1500;
    const std::string file = argc > 3 ? argv[3] : "/tmp/talus_bench.talus";
    def.lattice_gap = 1e-3;
    Model m;
    buildDensePack(m, def);
    const auto t0 = Clock::now();
    m.cycle(steps);
    const double run = std::chrono::duration<double>(Clock::now() - t0).count();
    double save = 1e300, restore = 1e300;
    std::size_t size = 0;
    for (int k = 0; k < 3; ++k) {
        auto a = Clock::now();
        saveModelFile(m, file);
        save = std::min(save, std::chrono::duration<double>(Clock::now() - a).count());
        a = Clock::now();
        RestoredModel r = restoreModelFile(file, PluginRegistry::global());
        restore = std::min(restore, std::chrono::duration<double>(Clock::now() - a).count());
        if (k == 0) {
            const std::vector<uint8_t> again = saveModelBytes(*r.model);
            size = again.size();
            if (again != saveModelBytes(m)) {
                std::fprintf(stderr, "the restored model does not save to the same bytes\n");
                return 1;
            }
        }
    }
    std::printf("n = %d balls, %zu contacts (%zu broadphase pairs) after %d steps (%.1f s)\n",
                def.n, m.contactCount(true), m.contactCount(false), steps, run);
    std::printf("file %.2f MB (%.0f bytes per ball), save %.3f s, restore %.3f s (best of 3)\n",
                size / 1e6, double(size) / def.n, save, restore);
    return 0;
}
