// SPDX-License-Identifier: MIT
//
// Contact detection (detection.cpp): the broadphase trees, the narrowphase against wall
// segments, and the pairs they make, with what making, removing and re-ordering them needs.
// Not installed.
#pragma once

#include <cstddef>
#include <cstdint>

#include "step/narrowphase.hpp"
#include "world/world.hpp"

namespace talus {

void initBroadphase(World& world);
void rebuildBallTree(World& world);
void insertBall(World& world, uint32_t slot);
void insertSegment(World& world, uint32_t seg);
void addPairsForBall(World& world, uint32_t slot);
void addPairsForSegment(World& world, uint32_t seg);
void clearMovedFlags(World& world);
Box ballBox(const World& world, uint32_t slot);
Box segmentBox(const World& world, uint32_t seg);
/// Ball against wall segment `seg` with the chain's shared-vertex rule (narrowphase.hpp).
bool segmentGeometry(const World& world, uint32_t seg, const Vec2& centre, double radius,
                     ContactGeometry& g);
/// The segment of seg's chain that holds a ball seg gives up (-1: none).
int32_t wallHolder(const World& world, uint32_t seg, const Vec2& centre, double radius);
/// The rule of a pair whose ends are in these groups: the most specific, the latest on a tie.
const Rule& ruleFor(const World& world, uint64_t groups1, uint64_t groups2);
/// Geometry of a pair now (for queries and messages): normal, overlap, contact point.
bool pairGeometry(const World& world, const Pair& p, Vec2& normal, double& overlap, Vec2& point);
bool makePair(World& world, uint32_t ball_slot, uint32_t other, bool other_is_segment);
void removePair(World& world, std::size_t index);
ContactModel* cloneFor(World& world, const Pair& p, double mass_eff);
PropBlock propBlockFor(const World& world, const Pair& p, double mass_eff);
double tangentialInverseMass(const World& world, const Pair& p);
void refreshRule(World& world, Pair& p);
void resetPair(World& world, Pair& p);
void swapPairState(World& world, std::size_t i, std::size_t j);
bool handOverWallContact(World& world, std::size_t index);
bool adoptWallContact(World& world, std::size_t index);
void sortBalls(World& world);
void repackContactObjects(World& world);

}  // namespace talus
