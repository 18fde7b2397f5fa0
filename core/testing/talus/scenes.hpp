// SPDX-License-Identifier: MIT
//
// Scene builders shared by tests and benchmarks (one place, like Box2D's shared/): the library
// talus_testing (core/testing/, not installed).
//
// Dense pack: N polydisperse disks in a box of four walls under gravity, with the linear
// contact model and a normal dashpot. Built on a jittered hexagonal lattice (no overlaps by
// construction), settled, and saved as a plain-text state that both Talus and LAMMPS start
// from, so a benchmark compares the two codes on exactly the same configuration
// (docs/benchmarks.md).
//
// Everything random comes from splitmix64 seeded by `DensePackDef::seed`, never from the
// standard library's distributions, whose output differs between library implementations.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "talus/ids.hpp"

namespace talus {

class Model;

struct DensePackDef {
    int n = 10000;              ///< number of disks
    double r_min = 0.8e-3;      ///< [m] radius uniform in [r_min, r_max]
    double r_max = 1.2e-3;      ///< [m]
    double density = 2600.0;    ///< [kg/m^3]; disk mass rho pi R^2 (unit thickness)
    double kn = 1e6;            ///< [N/m] normal stiffness of every contact
    double ks_ratio = 2.0 / 7;  ///< ks = ks_ratio kn
    double fric = 0.5;          ///< [-] friction coefficient (balls and walls)
    double restitution = 0.5;   ///< [-] normal restitution, through the normal dashpot ratio
    /// Dashpot mode of the linear model. 0 (full: the dashpot may pull) is what LAMMPS
    /// gran/hooke/history does without its `limit_damping` keyword, so it is the default.
    int dp_mode = 0;
    double aspect = 4.0;     ///< box width / box height; a wide, low box settles quickly
    double gravity = 9.81;   ///< [m/s^2], pointing -y
    double timestep = 1e-5;  ///< [s] fixed step
    /// Lattice spacing = 2 r_max (1 + lattice_gap): the largest disks start this far apart.
    double lattice_gap = 0.02;
    uint64_t seed = 1;
    /// Create the disks in a random order (from the seed), so that memory order says nothing
    /// about position, as after a random generation. The geometry does not depend on it.
    bool shuffle = true;
};

/// Normal critical-damping ratio of a linear dashpot for restitution e (the closed form of a linear
/// spring-dashpot). Full dashpot: beta = -ln e / sqrt(pi^2 + ln^2 e). No-tension dashpot (dp_mode 1
/// and 3): the inverse of e = exp(-beta (pi - 2 asin beta) / sqrt(1 - beta^2)), found by bisection.
double dampingRatioForRestitution(double e, bool no_tension = false);

/// What a builder made.
struct DensePack {
    double width = 0.0;         ///< [m] box interior, x in [0, width]
    double height = 0.0;        ///< [m] y in [0, height]
    std::vector<BallId> balls;  ///< in creation order
    WallId floor, right, top, left;
    double weight = 0.0;  ///< [N] total weight of the disks (per unit thickness)
};

/// Fills an empty model: four walls, N disks on a jittered hexagonal lattice, the linear
/// contact model for all contacts, gravity and the fixed step.
DensePack buildDensePack(Model& model, const DensePackDef& def);

/// Settling. The lattice compacts by about a fifth of its height as it falls. The fall runs
/// undamped (local damping would slow free fall) until the kinetic energy has peaked and
/// dropped to a tenth of the peak; then PFC local damping removes the collective vibrations,
/// which the contact dashpots damp only slowly (a mode of frequency w loses energy at about
/// beta w^2 / w_contact). The damping and the stability guard (off while settling) are restored
/// before returning, so later cycles see the plain scene.
struct SettleSettings {
    /// Stop when the mean kinetic energy per disk falls below ke_fraction * m g r (mean mass
    /// and radius): 1e-5 is a mean speed of about 5e-4 m/s, against about 0.5 m/s in the fall.
    double ke_fraction = 1e-5;
    double max_time = 3.0;       ///< [s] simulated-time cap
    double local_damping = 0.7;  ///< PFC local damping after the fall (0 = none)
    int check_every = 200;       ///< steps between checks of the kinetic energy
};

struct SettleResult {
    int64_t steps = 0;
    double time = 0.0;         ///< [s] simulated
    double fall_time = 0.0;    ///< [s] of it undamped
    double ke_per_ball = 0.0;  ///< [J] at the end
    double ke_limit = 0.0;     ///< [J] the threshold
    bool converged = false;    ///< false: stopped by max_time
};

SettleResult settleDensePack(Model& model, const DensePack& pack, const DensePackDef& def,
                             const SettleSettings& settings = SettleSettings{});

/// Mean kinetic energy per ball (translation and spin) [J].
double meanKineticEnergy(const Model& model);

// ---------------------------------------------------------------------- saved state

struct PackBall {
    double radius, x, y, vx, vy, spin;
};

/// A dense pack as a plain list of disks: what both codes start from. Contact history (the
/// shear springs) is not part of it, as LAMMPS data files do not carry it either.
struct PackState {
    DensePackDef def;
    double width = 0.0, height = 0.0;
    std::vector<PackBall> balls;  ///< in creation order
};

PackState capturePackState(const Model& model, const DensePack& pack, const DensePackDef& def);
/// Text file, every number with 17 significant digits (round-trips exactly).
void savePackState(const PackState& state, const std::string& path);
/// Throws InputError for a missing or malformed file.
PackState loadPackState(const std::string& path);
/// True if the state was made from the same scene parameters (everything but `shuffle`, which
/// only orders the file).
bool sameScene(const DensePackDef& a, const DensePackDef& b);

/// Builds the scene of `state` into an empty model (walls, model, gravity, step as for
/// buildDensePack), creating the disks in the state's order.
DensePack buildDensePackFromState(Model& model, const PackState& state);

/// LAMMPS data file (atom_style sphere, units si): Atoms "id type diameter density x y z" and
/// Velocities "id vx vy vz wx wy wz". LAMMPS turns the density column into a sphere mass
/// (4/3 pi R^3 rho); the input script resets it to the disk mass with `set ... density/disc`.
void writeLammpsData(const PackState& state, const std::string& path);

}  // namespace talus
