// SPDX-License-Identifier: MIT
//
// The single-contact rig (docs/plugin-guide.md, "Test it with the rig"). Two modes:
//  - runImpact: one impact, ball on a wall or ball on a ball, any model and properties, normal or
//    oblique, with spin, run to separation with the full engine; returns rebound velocities,
//    restitution, duration, peak force, maximum overlap, steps in contact and the energies.
//  - driveContact: a contact driven through a prescribed overlap (and shear) history without
//    dynamics; returns the force trace, for checking a law against its formula.
// Plugin authors use it to check their model; calibration workflows and the tests use it.
#pragma once

#include <string>
#include <vector>

#include "talus/energy.hpp"
#include "talus/model.hpp"
#include "talus/vec.hpp"

namespace talus {

struct ImpactSetup {
    std::string model = "linear";
    std::vector<PropValue> props;
    bool ball_target = false;  ///< false: ball on a wall; true: ball on a ball
    MassMode mass_mode = MassMode::Disk;
    double radius = 0.1;         ///< impactor radius [m]
    double density = 2600.0;     ///< impactor density [kg/m^3]
    double target_radius = 0.1;  ///< target ball radius [m] (ball_target)
    double target_density = 2600.0;
    double normal_speed = 1.0;      ///< approach speed of the impactor along the normal [m/s]
    double tangential_speed = 0.0;  ///< impactor velocity along the tangent [m/s]
    double spin = 0.0;              ///< impactor spin [rad/s]
    double target_speed = 0.0;      ///< target ball velocity along the normal, toward the impactor
    double target_spin = 0.0;
    double gap = -1.0;          ///< initial gap [m]; < 0: 1e-3 of the impactor radius
    TimestepSettings timestep;  ///< automatic by default
    GuardSettings guard;
    int64_t max_steps = 10000000;
    bool keep_trace = false;  ///< fill ImpactResult::trace
};

struct TracePoint {
    double time = 0.0;
    double overlap = 0.0;
    double normal_force = 0.0;
    double shear_force = 0.0;
    double moment = 0.0;
};

struct ImpactResult {
    bool separated = false;                ///< false: the contact had not ended after max_steps
    double vn_in = 0.0, vn_out = 0.0;      ///< relative normal velocity of the centres (+ approach)
    double vt_in = 0.0, vt_out = 0.0;      ///< impactor tangential velocity (relative, centres)
    double slip_in = 0.0, slip_out = 0.0;  ///< relative tangential velocity of the contact points
    double spin_out = 0.0, target_spin_out = 0.0;
    double restitution = 0.0;             ///< normal: -vn_out / vn_in
    double tangential_restitution = 0.0;  ///< vt_out / vt_in (0 when vt_in = 0)
    double rebound_angle = 0.0;           ///< of the impactor's velocity from the normal [rad]
    double contact_point_angle = 0.0;     ///< tan^-1(slip_out / vn_out) [rad]
    double duration = 0.0;        ///< touch to separation (overlap back to 0), interpolated [s]
    double force_duration = 0.0;  ///< touch to the end of the compressive force [s]
    double peak_force = 0.0;      ///< largest normal force [N]
    double max_overlap = 0.0;     ///< largest overlap [m]
    int64_t steps_in_contact = 0;
    double timestep = 0.0;                     ///< the step used at first touch [s]
    std::string step_rule;                     ///< which rule set it
    double energy_in = 0.0, energy_out = 0.0;  ///< kinetic energy before/after [J]
    EnergyTotals energy;                       ///< whole-model energies at the end
    std::vector<TracePoint> trace;
};

/// Runs one impact. Throws InputError/PluginError/NumericalError like the engine does.
ImpactResult runImpact(const ImpactSetup& setup,
                       PluginRegistry& registry = PluginRegistry::global());

struct DriveSetup {
    std::string model = "linear";
    std::vector<PropValue> props;
    bool ball_target = false;
    double radius = 0.1, target_radius = 0.1;  ///< [m]
    double mass = 1.0, target_mass = 1.0;      ///< [kg] (mass_eff follows)
    double dt = 1e-6;                          ///< time between samples [s]
    std::vector<double> overlap;               ///< u_n at each sample [m]
    std::vector<double> shear;                 ///< shear displacement at each sample [m] (optional)
};

struct DriveResult {
    std::vector<TracePoint> trace;
    std::vector<double> knest;
    double strain = 0.0, slip = 0.0, dashpot = 0.0, plastic = 0.0;  ///< energies at the end [J]
};

/// Drives a fresh contact of `model` through the overlap history (no dynamics).
DriveResult driveContact(const DriveSetup& setup,
                         PluginRegistry& registry = PluginRegistry::global());

/// Writes a trace as CSV (time, overlap, normal_force, shear_force, moment).
void writeTraceCsv(const std::vector<TracePoint>& trace, const std::string& path);

}  // namespace talus
