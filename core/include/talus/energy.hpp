// SPDX-License-Identifier: MIT
// Energy totals (docs/physics/energy.md; thesis A chapter 3 and accuracy-reference 3.6).
// Works put into the model count positive; dissipations count positive.
#pragma once

namespace talus {

struct EnergyTotals {
    double body = 0.0;      ///< work of gravity and applied forces/moments on the balls [J]
    double boundary = 0.0;  ///< work of moving walls on the balls [J]
    double kinetic = 0.0;   ///< current, translation + rotation, at the whole step [J]
    double strain = 0.0;    ///< current, stored in contacts [J]
    double bond = 0.0;      ///< current, stored in bonds [J]
    double slip = 0.0;      ///< accumulated frictional work [J]
    double dashpot = 0.0;   ///< accumulated viscous contact work [J]
    double plastic = 0.0;   ///< accumulated plastic work [J]
    double damping = 0.0;   ///< accumulated local and viscous (law-of-motion) damping work [J]
    double released = 0.0;  ///< strain/bond energy of contacts deleted while loaded [J]
    double initial_kinetic = 0.0;  ///< kinetic energy when tracing was switched on [J]

    /// Energy in minus energy accounted for; zero up to discretisation error.
    double balanceError() const {
        return initial_kinetic + body + boundary -
               (kinetic + strain + bond + slip + dashpot + plastic + damping + released);
    }
};

}  // namespace talus
