// SPDX-License-Identifier: MIT
//
// Operations behind the facade that the engine calls too (api/*.cpp): making and removing
// balls, contact-model rules and contact queries, bond memory, group names. Not installed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "step/detection.hpp"  // ruleFor, pairGeometry
#include "world/world.hpp"

namespace talus {

class SaveWriter;
class SaveReader;
/// Marks a cycle or solve call under way for its lifetime; refuses one started while another is
/// (a callback that cycles the model from inside a step would recurse until the stack overflows).
class RunLock {
public:
    RunLock(World& world, const char* what);
    ~RunLock() { m_world.clock.running = false; }
    RunLock(const RunLock&) = delete;
    RunLock& operator=(const RunLock&) = delete;

private:
    World& m_world;
};

/// The bit of a group name (Model::groupIndex); creates it when asked (api/model.cpp).
int groupIndex(World& world, const std::string& name, bool create);

// --- bodies (api/balls.cpp)
BallId createBallIn(World& world, const BallDef& def, uint32_t clump);  // kNoClump: free ball
void removeBall(World& world, BallId id, bool book_energy);
void updateMass(World& world, uint32_t slot);
void refreshPairMasses(World& world, uint32_t slot);

// --- servos (api/servo.cpp)
/// The direction in which a servo moves wall `w` to press the material: `dir` normalised, or
/// when it is NaN the normal of the chord from the wall's first to its last vertex, on the side
/// of the balls' centroid (a closed wall needs `dir`). `who` starts the error messages.
Vec2 servoDirection(const World& world, const WallData& w, Vec2 dir, const std::string& who);
/// The length of a wall's chain (its segments summed) [m].
double chainLength(const World& world, const WallData& w);
/// The servos' section of a save file, "SRVG", written only when the model has servos (files
/// without it restore as before; api/save_servos.cpp).
void saveServos(const World& world, SaveWriter& w);
void restoreServos(World& world, SaveReader& in);
// --- memory (api/memory.cpp)
/// Refuses to grow the model to `balls` balls, or to run it (`what`: "ball", "cycle", "solve"),
/// when the memory it would need, estimated from the bytes a ball and a contact take (measured,
/// docs/results/memory.md), is more than the machine has available (MemAvailable in
/// /proc/meminfo) or than m:guard{memory_limit =}. Reads /proc/meminfo only when the model is
/// about to grow by 64 MiB or more.
void requireMemory(World& world, std::size_t balls, const char* what);

// --- walls (api/walls.cpp)
/// Refuses a ball (or pebble) of `radius` placed with its centre within half its radius of a
/// wall segment: the wall would push it out on whichever side that is (docs/physics/walls.md,
/// "Placing a ball against a wall"). `what` starts the message ("ball", "clump 2 pebble 1").
void requireClearOfWalls(const World& world, const Vec2& centre, double radius,
                         const std::string& what);

// --- contacts (api/contacts.cpp)
/// A model's activity distance, refused unless finite and >= 0 (the force loop tests a pair
/// apart against its rule's, a contact's end against its object's).
double checkedActivity(double activity, const std::string& model);
/// Refuses a rule beyond the 65 535 a model can hold (Pair::rule), naming `what` asked for it.
void requireRuleRoom(const World& world, const char* what);
ContactInfo infoOf(const World& world, std::size_t index);
std::string describePair(const World& world, const Pair& p);

// --- bonds (api/bonds.cpp): which pairs a bond call selects, and the memory of pairs whose
// bond broke or was removed (a rule that bonds on touch, cbond's cb_bond, must not bond them
// again: kFdNoAutoBond at their next first FDlaw).
bool bondSelects(const World& world, const Pair& p, const BondSettings& s, int ga, int gb);
void forgetBond(World& world, std::size_t index);
uint32_t autoBondFlags(const World& world, const Pair& p, const PairCold& c);

}  // namespace talus
