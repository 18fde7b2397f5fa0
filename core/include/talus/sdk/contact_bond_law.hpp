// SPDX-License-Identifier: MIT
//
// The steady step of PFC's contact bond (Potyondy & Cundall 2004; the `cbond` model,
// docs/models/cbond.md): a contact that was already touching at its last step, and stays so,
// bonded without breaking or unbonded in compression. What `cbond` does on every other step (a
// bond made, adopted, broken or removed, a touch, a separation with its corner impulses) stays
// in the model; this part is written once, as a template on the state, so that the model's
// FDlaw, its lane law and the host's kernel of it (docs/plugin-abi.md, "Kernels") run the same
// code and give the same bits.
//
//   bonded     F_n = kn (u_n - u_ref),  F_s <- F_s - ks dU_s   (no slip; a step whose trial
//              forces reach cb_tenf in tension or cb_shearf in shear is not steady: it breaks)
//   unbonded   F_n = kn (u_n - u_ref) > 0,  F_s <- F_s - ks dU_s,  |F_s| <= fric F_n
//   energies   strain F_n^2/2kn + F_s^2/2ks; slip the slider's work
#pragma once

#include <cmath>

#include "talus/contact_model.hpp"
#include "talus/sdk/lanes.hpp"
#include "talus/sdk/shear_spring.hpp"

namespace talus::sdk {

struct ContactBondLaw {
    /// The kernel id (ABI 1.3, talus_plugin_kernel): raise it whenever the rows or the step
    /// change.
    static constexpr const char* kKernelId = "talus.sdk.ContactBondLaw/1";

    /// The values the steady step reads and writes, under the model's member names.
    struct State {
        double kn, ks, fric, cb_tenf, cb_shearf, bonded, u_ref_, cb_fn, cb_fs, last_engaged_;
        bool sliding_;
    };

    /// A steady step of `s` (header comment) into `fd`; false, with `s` and `fd` untouched, for
    /// any other step. (S: the model itself, or a State copied from a lane row.)
    template <class S, class Fd>
    __attribute__((always_inline)) static bool steadyStep(S& s, Fd& fd) {
        const double engaged = fd.u_n - s.u_ref_;
        double fn, fs, slip = 0.0;
        bool sliding = false;
        if (s.bonded == 1.0) {
            fn = s.kn * engaged;
            fs = s.cb_fs - s.ks * fd.du_s;
            const bool tension = fn < 0.0 && -fn >= s.cb_tenf;
            const bool shear = !tension && std::fabs(fs) > 0.0 && std::fabs(fs) >= s.cb_shearf;
            if (tension || shear) return false;
        } else {
            if (!(engaged > 0.0) || !(s.last_engaged_ > 0.0)) return false;
            fn = s.kn * engaged;
            fs = s.cb_fs;
            const ShearResult sr = updateShearSpring(fs, s.ks, fd.du_s, s.fric * fn);
            slip = sr.slip_work;
            sliding = sr.sliding;
        }
        s.cb_fn = fn;
        s.cb_fs = fs;
        s.last_engaged_ = engaged;
        if (s.bonded != 1.0) {
            s.sliding_ = sliding;
            if (sliding) fd.flags |= kFdSliding;
        }
        // (+ 0.0: the corner impulses of a touch or a separation, none here, as the full law
        // adds them)
        fd.n_force = s.cb_fn + 0.0;
        fd.s_force = s.cb_fs + 0.0;
        fd.moment = 0.0;
        fd.knest = s.kn;
        fd.ksest = s.ks;
        fd.krest = 0.0;
        if (s.bonded == 1.0) fd.flags |= kFdBonded | kFdKeep;
        if (fd.flags & kFdEnergyOn) {
            fd.energy[kEnergyStrain] = springEnergy(s.cb_fn, s.kn) + springEnergy(s.cb_fs, s.ks);
            fd.energy[kEnergySlip] = slip;
            fd.energy[kEnergyReleased] = 0.0;
        }
        return true;
    }

    // --- lanes: a row is the State's doubles in its order, sliding_ as 0 or 1.
    static constexpr int kLaneStateSize = 11;
    static const char* const* laneStateNames() {
        static const char* const names[kLaneStateSize] = {
            "kn",    "ks",    "fric",  "cb_tenf",      "cb_shearf", "bonded",
            "u_ref", "cb_fn", "cb_fs", "last_engaged", "sliding"};
        return names;
    }
    static void toRow(const State& s, double* r) {
        r[0] = s.kn, r[1] = s.ks, r[2] = s.fric, r[3] = s.cb_tenf, r[4] = s.cb_shearf;
        r[5] = s.bonded, r[6] = s.u_ref_, r[7] = s.cb_fn, r[8] = s.cb_fs, r[9] = s.last_engaged_;
        r[10] = s.sliding_ ? 1.0 : 0.0;
    }
    /// One contact's step in the lanes: the steady step on the row, or declined (false, the row
    /// untouched).
    template <class Fd>
    __attribute__((always_inline)) static bool laneStep(double* r, Fd& fd) {
        State s{r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10] != 0.0};
        if (!steadyStep(s, fd)) return false;
        r[7] = s.cb_fn, r[8] = s.cb_fs, r[9] = s.last_engaged_, r[10] = s.sliding_ ? 1.0 : 0.0;
        return true;
    }
};

}  // namespace talus::sdk
