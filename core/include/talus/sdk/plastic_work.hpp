// SPDX-License-Identifier: MIT
//
// A contact's plastic (hysteretic) work, booked step by step and never negative over the
// contact's life. Models that book their plastic work as the work the bodies did on them less
// the change of what they can give back (PFC's energy tracing: <F> du - d(recoverable)) see in
// it, besides their own loss, the central-difference integrator's error of the contact: a step
// across a corner of the law may give a small negative increment that later steps make up, but
// a contact that dissipates nothing (an elastic unloading from a placed overlap) would end with
// a negative total, the integrator's energy shown as "un-dissipated" plastic work. Kept at zero,
// that error shows where every model's does, in the balance (docs/physics/energy.md).
#pragma once

namespace talus::sdk {

struct PlasticWork {
    double total = 0.0;  ///< plastic work of this contact so far [J], >= 0

    /// This step's increment as the model found it; returns the increment to report: the same,
    /// or raised so that the contact's total does not fall below zero.
    double book(double increment) {
        if (total + increment < 0.0) increment = -total;
        total += increment;
        return increment;
    }
};

}  // namespace talus::sdk
