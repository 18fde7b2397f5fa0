// SPDX-License-Identifier: MIT
//
// Incremental linear shear spring with a Coulomb slider (PFC linear model;
// 3.2): F_s <- F_s - k_s dU_s, then |F_s| <= mu F_n by scaling, with the slip work of
// PFC's energy tracing. In 2D the shear force is a scalar along t = (-n_y, n_x), so the
// stored force needs no rotation as the contact normal turns.
#pragma once

#include <cmath>

namespace talus::sdk {

struct ShearResult {
    bool sliding = false;
    double slip_work = 0.0;  ///< frictional work this step, >= 0 [J]
};

/// Updates `shear_force` (on end 2, along t) for a shear displacement increment `du_s` [m].
/// `limit` is mu times the normal force the slider sees (>= 0, [N]).
inline ShearResult updateShearSpring(double& shear_force, double ks, double du_s, double limit) {
    ShearResult r;
    const double old_force = shear_force;
    double f = old_force - ks * du_s;
    if (std::fabs(f) > limit) {
        f = std::copysign(limit, f);
        r.sliding = true;
    }
    shear_force = f;
    if (r.sliding && ks > 0.0) {
        const double slip = du_s + (f - old_force) / ks;  // total minus elastic increment
        const double work = -0.5 * (old_force + f) * slip;
        r.slip_work = work > 0.0 ? work : 0.0;
    }
    return r;
}

/// Elastic energy of a linear spring carrying `force` [J]: F^2 / (2k).
inline double springEnergy(double force, double k) {
    return k > 0.0 ? 0.5 * force * force / k : 0.0;
}

}  // namespace talus::sdk
