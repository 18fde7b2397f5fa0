// SPDX-License-Identifier: MIT
// Energy totals (docs/physics/energy.md; An 2006, chapter 3, and the PFC2D manual's energy
// tracing). Works put into the model count positive; dissipations count positive.
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
    double deleted = 0.0;   ///< kinetic energy of balls deleted while tracing [J]
    double initial_kinetic = 0.0;  ///< kinetic energy when tracing was switched on [J]
    /// Strain and bond energy the contacts held when tracing was switched on: what their models
    /// report at the first step after, less the work the bodies did on them in that step plus
    /// what they dissipated in it [J].
    double initial_strain = 0.0;
    /// Strain energy of contacts that started overlapping (bodies created or moved into each
    /// other): energy no traced work put in, booked as an input when such a contact forms [J].
    double placement = 0.0;
    /// Work done on a group's bodies by contacts with bodies outside it, less the group's share
    /// of what those contacts stored and dissipated (docs/physics/energy.md, "Energy per
    /// group"). Always 0 for the whole model; the exchanged items of a partition sum to 0 [J].
    double exchanged = 0.0;
    /// Work done by the script between steps: the change of the kinetic energy (and of the
    /// damping and fixity work the next snapshot splits) that setting a velocity, spin, mass,
    /// fixity, applied load or gravity, adding a body, or making or releasing a clump caused
    /// (docs/physics/energy.md, "Work done by the script") [J].
    double script = 0.0;
    /// Kinetic energy taken by barriers (docs/rockfall.md, "Barriers"): what the next snapshot
    /// takes for a body less what it would have taken without the barrier's action [J].
    double barrier = 0.0;

    /// Energy put in so far: the initial kinetic and strain energy, the placement energy and the
    /// positive parts of the body, boundary, exchanged and script work [J].
    double input() const {
        return initial_kinetic + initial_strain + placement + (body > 0.0 ? body : 0.0) +
               (boundary > 0.0 ? boundary : 0.0) + (exchanged > 0.0 ? exchanged : 0.0) +
               (script > 0.0 ? script : 0.0);
    }

    /// Energy in minus energy accounted for; zero up to discretisation error.
    double balanceError() const {
        return initial_kinetic + initial_strain + placement + body + boundary + exchanged + script -
               (kinetic + strain + bond + slip + dashpot + plastic + damping + released + deleted +
                barrier);
    }
};

}  // namespace talus
