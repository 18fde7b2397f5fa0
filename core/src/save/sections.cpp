// SPDX-License-Identifier: MIT
//
// The table of the engine's sections (sections.hpp) and what they share: a contact model's
// state through its SaveRestore, written length-prefixed (talus/save_object.hpp).
#include "save/sections.hpp"

#include <string>

#include "talus/errors.hpp"
#include "talus/save_object.hpp"

namespace talus {

const std::vector<SaveSection>& engineSections() {
    // File order: what a reader checks against comes first (the group names before the rules
    // that name groups, the bodies before the pairs and trees that name them, the rules before
    // the pairs whose objects they clone).
    static const std::vector<SaveSection> table = {
        {"SETT", 1, writeSettings, readSettings},      // settings.cpp
        {"CLCK", 1, writeClock, readClock},            // clock.cpp
        {"BALL", 1, writeBalls, readBalls},            // balls.cpp
        {"CLMP", 1, writeClumps, readClumps},          // clumps.cpp
        {"WALL", 1, writeWalls, readWalls},            // walls.cpp
        {"RULE", 1, writeRules, readRules},            // rules.cpp
        {"PAIR", 1, writePairs, readPairs},            // pairs.cpp
        {"BRPH", 1, writeBroadphase, readBroadphase},  // broadphase.cpp
        {"ENRG", 1, writeEnergy, readEnergy},          // energy.cpp
        {"GARD", 1, writeGuard, readGuard},            // guard.cpp
        {"EVNT", 1, writeEvents, readEvents},          // events.cpp
    };
    return table;
}

void checkSavable(const World& world) {
    // Trackers are not saved (docs/save-format.md): their records belong to the run that reads
    // them, and their events call back into the script.
    if (!world.trackers.list.empty())
        throw InputError("save: the model has " + std::to_string(world.trackers.list.size()) +
                         " tracker(s), which are not saved; read their records and clear them "
                         "(m:clear_trackers()) before saving");
    // Barriers are not saved yet (docs/rockfall.md, "Barriers"): refused rather than dropped.
    if (!world.barriers.list.empty())
        throw InputError("save: the model has " + std::to_string(world.barriers.list.size()) +
                         " barrier(s), which are not saved yet (what they caught would be lost)");
}

void writeModelState(SaveWriter& w, ContactModel& m) {
    const std::vector<uint8_t> bytes = saveContactModel(m);
    w.u64(bytes.size());
    w.bytes(bytes.data(), bytes.size());
}

std::vector<uint8_t> readModelState(SaveReader& r) {
    std::vector<uint8_t> bytes(r.count(1, "contact model state"));
    r.bytes(bytes.data(), bytes.size());
    return bytes;
}

void applyModelState(SaveReader& r, ContactModel& m, const std::vector<uint8_t>& bytes,
                     int32_t version, const std::string& what) {
    try {
        restoreContactModel(m, bytes, version);
    } catch (const InputError& e) {
        r.fail(what + ": " + e.what());
    }
}

}  // namespace talus
