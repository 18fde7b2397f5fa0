// SPDX-License-Identifier: MIT
//
// The engine's part of a save file as a table of sections (docs/save-format.md, "Sections"):
// each store of the world writes and reads its own section, in its own file in this folder, and
// Model::saveState / Model::restoreState (api/save.cpp) walk the table in order. A reader checks
// every count, index and enum it reads, and what it names in the sections read before it (the
// table's order is the file's: bodies before the pairs that name them). Not installed.
//
// A section added in a later format version names that version in `since`: a file of an older
// version restores without it (the store keeps what a new model has). A field appended to a
// section is read when SaveReader::version() says the file has it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "talus/save_file.hpp"
#include "world/world.hpp"

namespace talus {

/// What the readers share while a model is restored.
struct RestoreContext {
    World& world;
    PluginRegistry& registry;
    std::vector<std::string>& notes;  ///< what the user should know (another plugin version)
    std::vector<int32_t> rule_versions = {};  ///< per rule: the Version() its data was saved with
};

/// One row of the table: the section's tag, the first format version that has it, and its
/// writer and reader.
struct SaveSection {
    const char* tag;  ///< 4 characters
    uint32_t since;
    void (*write)(const World& world, SaveWriter& w);
    void (*read)(RestoreContext& ctx, SaveReader& r);
};

/// The engine's sections in file order.
const std::vector<SaveSection>& engineSections();

/// Refuses a model with state no section holds (trackers: their records belong to the run that
/// reads them, and their events call back into the script).
void checkSavable(const World& world);

// ---- the sections, one file each
void writeSettings(const World& world, SaveWriter& w);  // SETT  settings.cpp
void readSettings(RestoreContext& ctx, SaveReader& r);
void writeClock(const World& world, SaveWriter& w);  // CLCK  clock.cpp
void readClock(RestoreContext& ctx, SaveReader& r);
void writeBalls(const World& world, SaveWriter& w);  // BALL  balls.cpp
void readBalls(RestoreContext& ctx, SaveReader& r);
void writeClumps(const World& world, SaveWriter& w);  // CLMP  clumps.cpp
void readClumps(RestoreContext& ctx, SaveReader& r);
void writeWalls(const World& world, SaveWriter& w);  // WALL  walls.cpp
void readWalls(RestoreContext& ctx, SaveReader& r);
void writeRules(const World& world, SaveWriter& w);  // RULE  rules.cpp
void readRules(RestoreContext& ctx, SaveReader& r);
void writePairs(const World& world, SaveWriter& w);  // PAIR  pairs.cpp
void readPairs(RestoreContext& ctx, SaveReader& r);
void writeBroadphase(const World& world, SaveWriter& w);  // BRPH  broadphase.cpp
void readBroadphase(RestoreContext& ctx, SaveReader& r);
void writeEnergy(const World& world, SaveWriter& w);  // ENRG  energy.cpp
void readEnergy(RestoreContext& ctx, SaveReader& r);
void writeGuard(const World& world, SaveWriter& w);  // GARD  guard.cpp
void readGuard(RestoreContext& ctx, SaveReader& r);
void writeEvents(const World& world, SaveWriter& w);  // EVNT  events.cpp
void readEvents(RestoreContext& ctx, SaveReader& r);

// ---- shared by the sections
/// A contact model's SaveRestore bytes, length-prefixed (rules and pairs).
void writeModelState(SaveWriter& w, ContactModel& m);
std::vector<uint8_t> readModelState(SaveReader& r);
/// Restores a contact model's state, naming where in the file it failed.
void applyModelState(SaveReader& r, ContactModel& m, const std::vector<uint8_t>& bytes,
                     int32_t version, const std::string& what);
void writeTotals(SaveWriter& w, const EnergyTotals& e);
EnergyTotals readTotals(SaveReader& r);

}  // namespace talus
