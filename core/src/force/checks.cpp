// SPDX-License-Identifier: MIT
//
// The checks of what a contact model returned (docs/plugin-abi.md): a failed law, a non-finite
// output, energies that break the ABI's contract, and a contact whose bodies passed through each
// other. Rare paths, kept out of the loop so that its body stays small.
#include <cmath>
#include <string>

#include "api/operations.hpp"
#include "force/force.hpp"
#include "talus/errors.hpp"
#include "world/messages.hpp"

namespace talus {

namespace {

std::string num(double v) { return messageNumber(v); }

/// Why the energy partitions of one FDlaw break the ABI's contract (docs/plugin-abi.md,
/// "Energies"), or empty. Every partition must be finite. Dissipation (slip, dashpot, plastic)
/// cannot be negative in total, but a single step's increment may be: the shipped models book
/// the trapezoidal work of the leapfrog's forces minus the change of the stored energy, so the
/// quadrature error of the time integration (O(dt^2), either sign; measured up to 0.5% of the
/// step's energy scale for `power` and `hysdamp` at 30 steps per impact) and the settling of the
/// last half step at separation land in these items, which keeps the balance closed. So the
/// check is on the run's total of each kind (`totals`, before this step): it may not fall below
/// zero by more than 1% (the guard's default energy tolerance) of the energy scale `scale`
/// (stored energies before and after, |F| |du| of every component, and the total itself).
/// The rare path: called only when an increment is < 0 or a sum is not finite.
std::string energyContractViolation(const FdBlock& fd, double scale, const double* totals) {
    static const char* const names[kEnergyCount] = {"strain",  "slip",        "dashpot",
                                                    "plastic", "bond_strain", "released"};
    for (int k = 0; k < kEnergyCount; ++k)
        if (!std::isfinite(fd.energy[k]))
            return std::string("energy partition '") + names[k] + "' is " + num(fd.energy[k]);
    for (int k : {kEnergySlip, kEnergyDashpot, kEnergyPlastic}) {
        const double total = totals[k];
        // (1e-300 J: an absolute floor, so that subnormal round-off is not a breach)
        if (total + fd.energy[k] < -0.01 * (scale + std::fabs(total)) - 1e-300)
            return std::string("negative ") + names[k] + " energy increment " + num(fd.energy[k]) +
                   " J takes the run's total " + names[k] + " dissipation to " +
                   num(total + fd.energy[k]) +
                   " J (dissipation is >= 0; the step's energy scale is " + num(scale) + " J)";
    }
    return {};
}

template <bool kAuto, bool kEnergy, bool kGuard>
void forceLoop(World& world);

}  // namespace

void checkEnergyContract(World& world, const Pair& p, double strain_old, double bond_old,
                         const FdBlock& fd, double fn_old, double fs_old, double m_old,
                         const EnergyTotals& before) {
    const double scale = std::fabs(strain_old) + std::fabs(bond_old) +
                         std::fabs(fd.energy[kEnergyStrain]) +
                         std::fabs(fd.energy[kEnergyBondStrain]) +
                         (std::fabs(fn_old) + std::fabs(fd.n_force)) * std::fabs(fd.du_n) +
                         (std::fabs(fs_old) + std::fabs(fd.s_force)) * std::fabs(fd.du_s) +
                         (std::fabs(m_old) + std::fabs(fd.moment)) * std::fabs(fd.dtheta);
    const double totals[kEnergyCount] = {0.0, before.slip, before.dashpot, before.plastic,
                                         0.0, 0.0};
    const std::string why = energyContractViolation(fd, scale, totals);
    if (!why.empty()) {
        const std::string what = "contact model '" + world.contacts.ruleOf(p).model_name +
                                 "' at step " + std::to_string(world.clock.step) + " on " +
                                 describePair(world, p) + ": " + why;
        // NaN stops the run. A negative total warns once per rule: contacts
        // born overlapping and the half-step settling at separation make it
        // happen in sound runs (docs/plugin-abi.md, "Energies").
        if (why.compare(0, 9, "negative ") != 0) throw PluginError(what);
        // While the books wait to open (tracing just switched on over loaded contacts,
        // law_of_motion.cpp), this step's items are not theirs and there is no run total yet:
        // in a pack a dashpot's increment may be negative for a step (its rate predicted from
        // the neighbours' last push), which a total of one step cannot absorb.
        if (world.books.stage == EnergyBooks::Stage::Waiting) return;
        if (!world.contacts.ruleOf(p).warned_negative_dissipation) {
            world.contacts.ruleOf(p).warned_negative_dissipation = true;
            talus::warn(world, what + " (warned once per contact_model rule)");
        }
    }
}

void reportFailedLaw(const World& world, const Pair& p, const FdBlock& fd) {
    throw PluginError("contact model '" + world.contacts.ruleOf(p).model_name +
                      "' failed at step " + std::to_string(world.clock.step) + " on " +
                      describePair(world, p) + ": " + (fd.error ? fd.error : "(no message)"));
}

void findNonFiniteContact(const World& world) {
    // The force loop only sums the models' outputs; find the first contact that made the sum
    // non-finite (its stored values are this step's).
    for (const Pair& p : world.contacts.pairs)
        if (p.active &&
            !std::isfinite(p.n_force + p.s_force + p.moment + world.contacts.coldOf(p).knest +
                           world.contacts.coldOf(p).ksest))
            throwNonFinite(world, describePair(world, p) + ": FDlaw returned normal force " +
                                      num(p.n_force) + ", shear force " + num(p.s_force) +
                                      ", moment " + num(p.moment) + ", knest " +
                                      num(world.contacts.coldOf(p).knest) + ", ksest " +
                                      num(world.contacts.coldOf(p).ksest) + " at overlap " +
                                      num(world.contacts.coldOf(p).overlap));
    throwNonFinite(
        world, "a contact model returned a non-finite value (the contact ended in the same step)");
}

void reportPassThrough(const World& world, const Pair& p, const ContactGeometry& g) {
    throw NumericalError("at step " + std::to_string(world.clock.step) +
                         " (t = " + num(world.clock.time) + " s): " + describePair(world, p) +
                         ": the contact normal reversed within one step, so one body passed "
                         "through the other (overlap " +
                         num(g.overlap) +
                         " m); the contact is too soft for this impact or the step too large");
}

}  // namespace talus
