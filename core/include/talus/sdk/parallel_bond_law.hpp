// SPDX-License-Identifier: MIT
//
// The steady step of the parallel bond (Potyondy & Cundall 2004; the `pbond` model,
// docs/models/pbond.md): a contact that was already touching at its last step, and stays so,
// with its bond intact and not breaking in this step, or unbonded (the linear part alone). What
// `pbond` does on every other step (a first call, a touch, a separation with its closing
// corners, a break, a bond made or removed) stays in the model; this part is written once, as a
// template on the state, so that the model's FDlaw and its lane law (docs/plugin-abi.md, "Lanes";
// and a host's kernel of it, "Kernels") run the same code and give the same bits.
//
//   linear   the linear law's contact step (talus/sdk/linear_law.hpp), lin_mode 0 or 1
//   bond     F_n^b <- F_n^b + kbn du_n,  F_s^b <- F_s^b - kbs dU_s,  M^b <- M^b - kbr dtheta
//            (kbn = pb_kn A, kbs = pb_ks A, kbr = pb_kn I); a step whose trial forces meet the
//            tensile or the shear strength is not steady: it breaks
//   stresses sigma = -F_n^b / A + pb_mcf |M^b| R_b / I (tension +),  tau = |F_s^b| / A
//   shear    tau_c = pb_coh - s tan(pb_fa), s = -F_n^b / A capped at pb_ten
//   energies the linear part's; bond strain F_n^2/2kbn + F_s^2/2kbs + M^2/2kbr
#pragma once

#include <algorithm>
#include <cmath>

#include "talus/contact_model.hpp"
#include "talus/sdk/dashpot.hpp"
#include "talus/sdk/lanes.hpp"
#include "talus/sdk/linear_law.hpp"
#include "talus/sdk/shear_spring.hpp"

namespace talus::sdk {

struct ParallelBondLaw {
    /// The kernel id (ABI 1.3, talus_plugin_kernel): raise it whenever the rows or the step
    /// change.
    static constexpr const char* kKernelId = "talus.sdk.ParallelBondLaw/1";

    /// The bond's peak stresses [Pa]: normal (tension +) and shear.
    struct Stresses {
        double sigma = 0.0, tau = 0.0;
    };
    /// The stresses of forces (fn, fs, m) on the bond of `s` (P&C 2004, the 2D rectangle).
    template <class S>
    __attribute__((always_inline)) static Stresses stresses(const S& s, double fn, double fs,
                                                            double m) {
        if (s.area_ <= 0.0) return Stresses{};
        const double bend =
            s.inertia_ > 0.0 ? s.pb_mcf * std::fabs(m) * s.pb_rad / s.inertia_ : 0.0;
        return Stresses{-fn / s.area_ + bend, std::fabs(fs) / s.area_};
    }
    /// Shear strength tau_c = pb_coh - s tan(pb_fa), s = -fn/A the mean normal stress (tension
    /// +) capped at pb_ten: PFC's Mohr-Coulomb envelope with its tensile cut-off.
    template <class S>
    static double shearStrength(const S& s, double fn) {
        if (s.pb_fa == 0.0 || s.area_ <= 0.0) return s.pb_coh;
        const double mean = std::min(-fn / s.area_, s.pb_ten);
        return s.pb_coh - mean * std::tan(s.pb_fa * M_PI / 180.0);
    }
    /// Whether stresses `st` of normal force `fn` meet the bond's tensile, or its shear, strength.
    template <class S>
    __attribute__((always_inline)) static bool tensionFails(const S& s, const Stresses& st) {
        return st.sigma > 0.0 && st.sigma >= s.pb_ten;
    }
    template <class S>
    __attribute__((always_inline)) static bool shearFails(const S& s, double fn,
                                                          const Stresses& st) {
        return st.tau > 0.0 && st.tau >= shearStrength(s, fn);
    }
    /// How stresses `st` of normal force `fn` break the bond of `s`: tension first.
    enum Failure { kIntact, kTension, kShear };
    template <class S>
    __attribute__((always_inline)) static Failure failure(const S& s, double fn,
                                                          const Stresses& st) {
        if (tensionFails(s, st)) return kTension;
        if (shearFails(s, fn, st)) return kShear;
        return kIntact;
    }
    /// Strain energy in the bond [J]: F_n^2/(2 kbn) + F_s^2/(2 kbs) + M^2/(2 kbr).
    template <class S>
    static double bondEnergy(const S& s) {
        return springEnergy(s.pb_fn, s.kbn_) + springEnergy(s.pb_fs, s.kbs_) +
               springEnergy(s.pb_m, s.kbr_);
    }

    /// The time-step estimates the law hands back (the bond's springs beside the linear ones).
    struct Estimates {
        double kn, ks, kr;
    };

    /// A steady step of `s` (header comment) into `fd`; false, with `s` untouched, for any other
    /// step (the caller has excluded a first call, a bond made or removed since the last step,
    /// and a contact that was not touching). S: the model itself, or a State from a lane row.
    template <class S, class Fd>
    __attribute__((always_inline)) static bool steadyStep(S& s, Fd& fd, const Estimates& est) {
        if ((fd.flags & kFdFirstCall) || !(fd.u_n > 0.0) || fd.mass_eff != s.mass_eff_)
            return false;
        const bool bonded = s.bonded == 1.0;
        double fn = 0.0, fs = 0.0, m = 0.0;
        Stresses st;
        if (bonded) {
            // The trial forces first: a break leaves everything to the model's full law.
            // the overlap's own increment, not u_dot_n dt (LinearLaw::contactStep says why)
            fn = s.pb_fn + s.kbn_ * (fd.u_n - s.last_overlap_);
            fs = s.pb_fs - s.kbs_ * fd.du_s;
            m = s.pb_m - s.kbr_ * fd.dtheta;
            st = stresses(s, fn, fs, m);
            if (failure(s, fn, st) != kIntact) return false;
        }
        // The linear part of a touching contact (LinearLaw::linearForces): the dashpots' load
        // from the rest of the model (the bond's forces are this contact's, not the rest's),
        // then the contact step.
        DashpotLoad other{};
        if (s.cn_ > 0.0 || s.cs_ > 0.0) {
            const double inv_n = s.cn_ > 0.0 ? s.inv_mass_eff_ : 0.0;
            const double inv_s = s.cs_ > 0.0 ? fd.inv_mass_eff_s : 0.0;
            other =
                lessParallelSprings(s.history_.observe(fd, inv_n, inv_s), fn, -fs, inv_n, inv_s);
        }
        const double overlap_increment = fd.u_n - s.last_overlap_;
        s.last_overlap_ = fd.u_n;
        const LinearLaw::Forces lin =
            LinearLaw::contactStep(s, fd, other, false, s.lin_mode == 1.0, overlap_increment);
        if (bonded) {
            s.pb_fn = fn;
            s.pb_fs = fs;
            s.pb_m = m;
            s.pb_sigma = st.sigma;
            s.pb_tau = st.tau;
        }
        // (+ 0.0: the corners of a bond made at touch or broken, none here, as the full law
        // adds them)
        fd.n_force = lin.fn + s.pb_fn + 0.0;
        fd.s_force = lin.fs + s.pb_fs + 0.0;
        fd.moment = s.pb_m + 0.0;
        fd.knest = est.kn;
        fd.ksest = est.ks;
        fd.krest = est.kr;
        if (bonded) fd.flags |= kFdBonded | kFdKeep;
        if (fd.flags & kFdEnergyOn) {
            fd.energy[kEnergyStrain] = lin.strain;
            fd.energy[kEnergySlip] = lin.slip;
            fd.energy[kEnergyDashpot] = lin.dash;
            fd.energy[kEnergyBondStrain] = bondEnergy(s);
            fd.energy[kEnergyReleased] = 0.0 + lin.released;
        }
        return true;
    }

    // --- lanes: a row holds the constants the step reads, then the state it writes.
    static constexpr int kConstants = 23;
    static constexpr int kLaneStateSize = kConstants + 11 + DashpotHistory::kLaneStateSize;
    static const char* const* laneStateNames() {
        static const char* const names[kLaneStateSize] = {
            "kn",        "ks",       "fric",     "mass_eff", "inv_mass_eff", "cn",
            "cs",        "knest",    "ksest",    "krest",    "modes",        "lin_mode",
            "bonded",    "kbn",      "kbs",      "kbr",      "area",         "inertia",
            "pb_rad",    "pb_mcf",   "pb_ten",   "pb_coh",   "pb_fa",        "lin_fn",
            "lin_fs",    "dp_fn",    "dp_fs",    "lin_slip", "last_overlap", "pb_fn",
            "pb_fs",     "pb_m",     "pb_sigma", "pb_tau",   "dp_dt_prev",   "dp_rate_n",
            "dp_rate_s", "dp_est_n", "dp_est_s"};
        return names;
    }
    /// Row <- the model `s` (its estimates `est`): what toLane writes.
    template <class S>
    static void toRow(const S& s, const Estimates& est, double* r) {
        r[0] = s.kn, r[1] = s.ks, r[2] = s.fric, r[3] = s.mass_eff_, r[4] = s.inv_mass_eff_;
        r[5] = s.cn_, r[6] = s.cs_, r[7] = est.kn, r[8] = est.ks, r[9] = est.kr;
        r[10] = (s.no_tension_ ? 1.0 : 0.0) + (s.no_shear_dp_sliding_ ? 2.0 : 0.0);
        r[11] = s.lin_mode, r[12] = s.bonded, r[13] = s.kbn_, r[14] = s.kbs_, r[15] = s.kbr_;
        r[16] = s.area_, r[17] = s.inertia_, r[18] = s.pb_rad, r[19] = s.pb_mcf;
        r[20] = s.pb_ten, r[21] = s.pb_coh, r[22] = s.pb_fa;
        r[23] = s.lin_fn, r[24] = s.lin_fs, r[25] = s.dp_fn, r[26] = s.dp_fs, r[27] = s.lin_slip;
        r[28] = s.last_overlap_, r[29] = s.pb_fn, r[30] = s.pb_fs, r[31] = s.pb_m;
        r[32] = s.pb_sigma, r[33] = s.pb_tau;
        s.history_.toLane(r, 34);
    }
    /// The model `s` <- row: the state the step writes (the constants never change in the
    /// lanes: a write of a property takes the contact out).
    template <class S>
    static void fromRow(const double* r, S& s) {
        s.lin_fn = r[23], s.lin_fs = r[24], s.dp_fn = r[25], s.dp_fs = r[26], s.lin_slip = r[27];
        s.last_overlap_ = r[28], s.pb_fn = r[29], s.pb_fs = r[30], s.pb_m = r[31];
        s.pb_sigma = r[32], s.pb_tau = r[33];
        s.history_.fromLane(r, 34);
    }

    /// A lane row's values under the names the steady step reads and writes, copied in and out
    /// (in registers, not through the row).
    struct State {
        double kn, ks, fric, mass_eff_, inv_mass_eff_, cn_, cs_;
        bool no_tension_, no_shear_dp_sliding_;
        double lin_mode, bonded, kbn_, kbs_, kbr_, area_, inertia_, pb_rad, pb_mcf, pb_ten, pb_coh,
            pb_fa;
        double lin_fn, lin_fs, dp_fn, dp_fs, lin_slip, last_overlap_;
        double pb_fn, pb_fs, pb_m, pb_sigma, pb_tau;
        DashpotHistory history_;
    };
    /// One contact's step in the lanes: the steady step on the row, or declined (false, the row
    /// untouched).
    template <class Fd>
    __attribute__((always_inline)) static bool laneStep(double* r, Fd& fd) {
        if (!(fd.u_n > 0.0) || fd.mass_eff != r[3]) return false;
        const double modes = r[10];
        State s;
        s.kn = r[0], s.ks = r[1], s.fric = r[2], s.mass_eff_ = r[3], s.inv_mass_eff_ = r[4];
        s.cn_ = r[5], s.cs_ = r[6];
        s.no_tension_ = modes == 1.0 || modes == 3.0, s.no_shear_dp_sliding_ = modes >= 2.0;
        s.lin_mode = r[11], s.bonded = r[12], s.kbn_ = r[13], s.kbs_ = r[14], s.kbr_ = r[15];
        s.area_ = r[16], s.inertia_ = r[17], s.pb_rad = r[18], s.pb_mcf = r[19];
        s.pb_ten = r[20], s.pb_coh = r[21], s.pb_fa = r[22];
        s.lin_fn = r[23], s.lin_fs = r[24], s.dp_fn = r[25], s.dp_fs = r[26], s.lin_slip = r[27];
        s.last_overlap_ = r[28], s.pb_fn = r[29], s.pb_fs = r[30], s.pb_m = r[31];
        s.pb_sigma = r[32], s.pb_tau = r[33];
        const bool dashpots = s.cn_ > 0.0 || s.cs_ > 0.0;
        if (dashpots) s.history_.fromLane(r, 34);
        if (!steadyStep(s, fd, Estimates{r[7], r[8], r[9]})) return false;
        r[23] = s.lin_fn, r[24] = s.lin_fs, r[25] = s.dp_fn, r[26] = s.dp_fs, r[27] = s.lin_slip;
        r[28] = s.last_overlap_;
        if (s.bonded == 1.0)
            r[29] = s.pb_fn, r[30] = s.pb_fs, r[31] = s.pb_m, r[32] = s.pb_sigma, r[33] = s.pb_tau;
        if (dashpots) s.history_.toLane(r, 34);
        return true;
    }
};

}  // namespace talus::sdk
