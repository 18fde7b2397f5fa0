// SPDX-License-Identifier: MIT
// libFuzzer target for the save-file reader (docs/save-format.md). The checksum check is off so
// that mutated bytes reach the section parsers (with it, almost every mutation stops at the
// checksum). A restore must end in an InputError or a model; a model it accepts must save and
// restore again. Built with clang -fsanitize=fuzzer,address,undefined (tests/fuzz/CMakeLists.txt);
// the seed corpus is a small model's save file, written by LLVMFuzzerInitialize into
// $TALUS_FUZZ_SEED_DIR when that is set.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "talus/errors.hpp"
#include "talus/model.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/save_file.hpp"

using namespace talus;

namespace {

std::vector<uint8_t> seedFile() {
    ModelDef def;
    def.gravity = Vec2(0.0, -9.81);
    Model m(def);
    m.setDefaultContactModel("linear",
                             {{"kn", 1e6}, {"ks", 5e5}, {"fric", 0.5}, {"dp_nratio", 0.2}});
    WallDef box;
    box.points = {Vec2(0.0, 1.0), Vec2(0.0, 0.0), Vec2(1.0, 0.0), Vec2(1.0, 1.0)};
    m.createWall(box);
    for (int i = 0; i < 3; ++i) {
        BallDef b;
        b.pos = Vec2(0.2 + 0.3 * i, 0.1 + 0.05 * i);
        b.radius = 0.1;
        b.density = 2600.0;
        b.groups = {i ? "a" : "b"};
        m.createBall(b);
    }
    ClumpDef c;
    c.pebbles = {{Vec2(0.0, 0.0), 0.06}, {Vec2(0.08, 0.0), 0.05}};
    c.pos = Vec2(0.5, 0.6);
    c.density = 2600.0;
    m.createClump(c);
    m.setEnergyTracing(true);
    m.cycle(100);
    return saveModelBytes(m);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    if (const char* dir = std::getenv("TALUS_FUZZ_SEED_DIR")) {
        const std::vector<uint8_t> seed = seedFile();
        const std::string path = std::string(dir) + "/seed.talus";
        if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
            std::fwrite(seed.data(), 1, seed.size(), f);
            std::fclose(f);
        }
    }
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    RestoredModel r;
    try {
        r = restoreModelBytes(data, size, "fuzz", PluginRegistry::global(), false);
    } catch (const InputError&) {
        return 0;  // refused: what the reader must do with a bad file
    } catch (const PluginError&) {
        return 0;  // a model name in the file that no plugin offers
    }
    // Accepted: the model must be consistent enough to save and restore again.
    const std::vector<uint8_t> again = saveModelBytes(*r.model, r.host);
    restoreModelBytes(again.data(), again.size(), "fuzz, saved again", PluginRegistry::global());
    return 0;
}
