// SPDX-License-Identifier: MIT
// Mass properties of a clump (a rigid body made of possibly overlapping disks): pure geometry,
// 2D, unit thickness. See docs/physics/clumps.md "Mass properties" and
// docs/physics/clumps.md for the method and tests/core/test_clump_mass.cpp for the reference
// values.
#pragma once

#include <vector>

#include "talus/vec.hpp"

namespace talus {

/// One disk of a clump, in any frame (the clump's frame for a template).
struct Pebble {
    Vec2 pos{0.0, 0.0};
    double radius = 0.0;
};

/// Geometric mass properties per unit density and unit thickness.
struct MassProps {
    double area = 0.0;          ///< [m^2] (mass per unit density and thickness)
    Vec2 centroid{0.0, 0.0};    ///< [m], in the frame of the pebbles
    double polar_moment = 0.0;  ///< [m^4] polar second moment about the centroid
};

/// Physical mass properties of a clump of unit thickness.
struct RigidMass {
    double mass = 0.0;        ///< [kg/m]
    Vec2 centroid{0.0, 0.0};  ///< [m]
    double inertia = 0.0;     ///< [kg m^2/m] about the centroid
};

/// How a clump's mass properties are obtained (PFC's modes; Union is the default).
enum class ClumpMassMode {
    Union,     ///< exact union of the disks, overlaps counted once (unionMassProps)
    Direct,    ///< user-given {mass, centroid, inertia}; pebbles only shape the surface
    PlainSum,  ///< sum over pebbles, overlaps counted repeatedly (PFC 3.x; sumMassProps)
};

/// Exact area, centroid and polar moment of the union of the disks (Green's theorem over the
/// arcs of each circle that no other disk covers, integrated in closed form). Disks inside
/// another are skipped; duplicates count once. Throws InputError on an empty list, a radius
/// <= 0 or non-finite, or a non-finite position (naming the pebble index).
///
/// Disk (unit thickness) only: a union of *spheres* is not supported. The engine must refuse
/// clumps in MassMode::Sphere with a clear error rather than mix the two.
MassProps unionMassProps(const std::vector<Pebble>& pebbles);

/// Plain sum over the pebbles (PFC 3.x): A = sum pi r^2, area-weighted centroid, and
/// J = sum (A_i r_i^2 / 2 + A_i |x_i - x_c|^2) (parallel axes). Same input checks.
MassProps sumMassProps(const std::vector<Pebble>& pebbles);

/// Union or plain-sum properties by mode (Direct has no geometric value: InputError).
MassProps clumpMassProps(const std::vector<Pebble>& pebbles, ClumpMassMode mode);

/// Mass per unit thickness at density rho [kg/m^3]: m = rho A, I = rho J. Throws InputError
/// unless rho is positive and finite.
RigidMass scaledToDensity(const MassProps& props, double density);

}  // namespace talus
