// SPDX-License-Identifier: MIT
//
// Bytes of a contact model's saved state (SaveRestore through BinarySaveObject), the record a
// contact would carry when it migrates to another MPI rank (docs/scaling.md). The layout is the
// same for the prototype and every per-contact object, so the prototype is measured.
//
//   g++ -std=c++17 -Icore/include scripts/bench/contact_state_bytes.cpp
//       BUILD/core/libtalus_core.a -ldl -o contact_state_bytes      (one line)
//   TALUS_PLUGIN_PATH=BUILD/plugins ./contact_state_bytes linear hertz ...
#include <cstdio>

#include "talus/plugin_registry.hpp"
#include "talus/save_object.hpp"

int main(int argc, char** argv) {
    auto& registry = talus::PluginRegistry::global();
    for (int i = 1; i < argc; ++i) {
        const talus::ModelFactory& factory = registry.find(argv[i]);
        auto prototype = registry.createPrototype(factory);
        std::printf("%s: SaveRestore %zu bytes, ObjectSize %zu bytes\n", argv[i],
                    talus::saveContactModel(*prototype).size(), prototype->ObjectSize());
    }
    return 0;
}
