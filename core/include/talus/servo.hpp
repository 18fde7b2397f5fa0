// SPDX-License-Identifier: MIT
//
// A servo over a set of walls (Model::addServo; docs/lua-api.md "Servos"): the walls move together,
// each along its own direction at one common speed, so that what they measure together follows
// a target: a stress or a force (PFC's servo gain), or a strain rate or a velocity (loading
// platens). The engine sets the speed every step (core/src/step/servo.cpp); the script sets the
// target once. One such servo drives the platens of a compression test, each wall of a box
// vessel, and the segments of a circular vessel shrinking about its centre.
#pragma once

#include <cstdint>
#include <vector>

#include "talus/ids.hpp"
#include "talus/model_types.hpp"
#include "talus/vec.hpp"

namespace talus {

/// A servo's handle: 1-based index (0 = none).
struct ServoId {
    uint32_t index = 0;
    bool valid() const { return index != 0; }
};

/// What a servo holds.
enum class ServoControl : uint8_t {
    Stress,    ///< the walls' summed push over the loaded length [Pa] (PFC's gain)
    Force,     ///< the walls' summed push [N] (PFC's gain)
    Rate,      ///< a strain rate [1/s]: each wall moves at rate * gauge / 2
    Velocity,  ///< each wall's speed along its direction [m/s]
};

/// A servo's settings. Speeds are along each wall's direction `dirs[k]` (into the material:
/// compression positive).
struct ServoSettings {
    std::vector<WallId> walls;  ///< at least one; a wall belongs to one servo at a time
    /// Per wall, the direction it moves to press the material; empty, or an entry of NaN: the
    /// wall's normal toward the balls' centroid (as WallServoSettings::dir).
    std::vector<Vec2> dirs;
    ServoControl control = ServoControl::Stress;
    double target = 0.0;  ///< Pa, N, 1/s or m/s by `control`
    /// Stress: the loaded length [m]. NaN: the gap between `span[0]` and `span[1]` when they
    /// are given (updated every step: the side walls of a biaxial test between the platens),
    /// else the walls' chain lengths summed.
    double length = kNotSet;
    WallId span[2];
    /// Rate: the length the strain refers to [m]; NaN: the gap between walls[0] and walls[1]
    /// when the servo is set (two platens).
    double gauge = kNotSet;
    /// Steps over which the speed (rate, velocity) or the target (stress, force, from what the
    /// walls measured at the first step) rises linearly to its value; 0: at once.
    int64_t ramp = 0;
    double alpha = 0.5;  ///< stress, force: PFC's relaxation factor, in (0, 2)
    double vmax = 1.0;   ///< [m/s] the speed cap
    bool on = true;
    /// Rate, velocity: the equilibrium hold, off when NaN. When PFC's mechanical ratio (mean
    /// unbalanced force over mean contact force, UnbalancedForce) rises above `hold_ratio`, the
    /// walls stand still and the model relaxes (a crack cascade runs its course at fixed
    /// strain); they move on at the target once it is at or below `hold_resume` (NaN: the same
    /// limit), their speed rising again over `ramp` steps. A hold lasts at most
    /// `hold_max_steps` steps; then the walls move until the ratio falls to `hold_resume`, so a
    /// test always ends.
    double hold_ratio = kNotSet;
    double hold_resume = kNotSet;
    int64_t hold_max_steps = 0;
};

/// A servo's settings (directions, gauge resolved) and its state after the last step.
struct ServoState {
    ServoSettings settings;
    int64_t steps = 0;           ///< steps run since the servo was set
    double start = kNotSet;      ///< stress, force: what the walls measured at the first step
    double force = 0.0;          ///< the walls' summed push [N] (last force loop)
    double stress = 0.0;         ///< force / length [Pa] (stress control; else NaN)
    double length = kNotSet;     ///< the loaded length of that stress [m]
    double knest = 0.0;          ///< the walls' contact stiffness summed [N/m]
    double speed = 0.0;          ///< the speed set for the last step [m/s]
    double displacement = 0.0;   ///< how far each wall moved along its direction since set [m]
    std::vector<double> forces;  ///< each wall's push [N]
    // the equilibrium hold (settings.hold_ratio set)
    double ratio = kNotSet;    ///< the mechanical ratio at the last step
    int64_t held = 0;          ///< steps the walls stood still since the servo was set
    int64_t holds = 0;         ///< holds begun
    int64_t holds_capped = 0;  ///< holds ended by hold_max_steps, not by the ratio
    int64_t hold_run = 0;      ///< steps of the hold under way (0: moving)
    int64_t since_hold = -1;   ///< steps moved since the last hold ended (-1: none yet)
    bool capped = false;       ///< the last hold hit its cap: moving until the ratio falls
};

}  // namespace talus
