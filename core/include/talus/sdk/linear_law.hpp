// SPDX-License-Identifier: MIT
//
// The PFC linear law as a building block: the state, the force-displacement law and the
// time-step contract of the `linear` model (docs/models/linear.md), shared by every model that
// is "linear plus something" (`rrlinear` adds a rolling-resistance moment).
//
//   normal:  F_n^l = kn u_n                       (secant, absolute; no tension)
//   shear:   F_s^l <- F_s^l - ks dU_s,  |F_s^l| <= fric F_n^l      (the PFC linear model)
//   dashpot: F^d = c (rate), c_n = 2 dp_nratio sqrt(m* kn), c_s = 2 dp_sratio sqrt(m* ks)
//            (PFC's coefficients; the implicit solve of the shear dashpot uses the tangential
//            effective mass, rotation included, FdBlock::inv_mass_eff_s)
//   dp_mode: 0 full; 1 total normal force >= 0; 2 shear dashpot off while sliding; 3 = 1 and 2
//
// kn, ks and fric are inherited from the ends when they define them (springs in series,
// friction minimum), as PFC2D 3.x did with ball and wall properties.
// The dashpots use the implicit, impulse-exact scheme of talus/sdk/dashpot.hpp.
//
// Use: a model derives from ModelBase<Model> and from LinearLaw, puts linearSettableProps<Model>()
// and linearStateProps<Model>() into its property table, and calls the linear* members from its
// own inherit, onPropChanged, fdlaw and saveRestoreState. The data members keep the order the
// `linear` model had (its hot values in the first cache lines; the force loop prefetches
// three: core/src/force/pair.hpp, prefetchModel).
#pragma once

#include <algorithm>
#include <cmath>

#include "talus/contact_model.hpp"
#include "talus/sdk/corners.hpp"
#include "talus/sdk/dashpot.hpp"
#include "talus/sdk/lanes.hpp"
#include "talus/sdk/model_base.hpp"
#include "talus/sdk/shear_spring.hpp"

namespace talus::sdk {

/// Names of the linear law's dp_mode values.
inline const char* const* linearDpModeNames() {
    static const char* const names[] = {"full", "no_tension", "no_shear_slip",
                                        "no_tension_no_shear_slip", nullptr};
    return names;
}

class LinearLaw {
public:
    // properties (PFC names)
    double kn = 0.0;    // [N/m]
    double ks = 0.0;    // [N/m]
    double fric = 0.0;  // [-]
    // state (read-only)
    double lin_fn = 0.0;    // linear normal force [N]
    double lin_fs = 0.0;    // linear shear force [N]
    double dp_fn = 0.0;     // normal dashpot force [N]
    double dp_fs = 0.0;     // shear dashpot force [N]
    double lin_slip = 0.0;  // 1 while sliding
    // per-contact derived values (not properties), cached so FDlaw needs no square root
    double mass_eff_ = 0.0, inv_mass_eff_ = 0.0;
    double cn_ = 0.0, cs_ = 0.0;  // dashpot coefficients [N s/m]
    double knest_ = 0.0, ksest_ = 0.0;
    bool no_tension_ = false, no_shear_dp_sliding_ = false;
    bool touching_ = false;
    double last_overlap_ = 0.0;
    DashpotHistory history_;  // the rest of the model's push on the dashpots' rates
    // Dashpot properties last: FDlaw reads only what setMass derives from them, and the force
    // loop prefetches an object's first three cache lines (core/src/force/pair.hpp, prefetchModel).
    double dp_nratio = 0.0;  // [-]
    double dp_sratio = 0.0;  // [-]
    double dp_mode = 0.0;    // 0..3

    /// What the linear law did this step, for a model built on it.
    struct Step {
        bool touching = false;  ///< u_n > 0 this step
        bool first = false;     ///< first contact step (touch within this step)
        double lead = 0.5;      ///< onsetFraction on the first step, else 0.5
    };

    /// PFC inheritance of kn, ks, fric from the ends; caches the mass-dependent values.
    void linearInherit(const PropBlock& pb) {
        kn = inheritSeries(kn, pb.kn);
        ks = inheritSeries(ks, pb.ks);
        fric = inheritMin(fric, pb.fric);
        setMass(pb.mass_eff);
    }

    void setMass(double m) {
        mass_eff_ = m;
        inv_mass_eff_ = m > 0.0 ? 1.0 / m : 0.0;
        cn_ = dashpotCoefficient(dp_nratio, m, kn);
        cs_ = dashpotCoefficient(dp_sratio, m, ks);
        knest_ = kn * dashpotStiffnessFactor(dp_nratio);
        ksest_ = ks * dashpotStiffnessFactor(dp_sratio);
        no_tension_ = dp_mode == 1.0 || dp_mode == 3.0;
        no_shear_dp_sliding_ = dp_mode >= 2.0;
        // Without dashpots the history is not followed (fdlaw); it must not be stale when a
        // dashpot is switched on later.
        if (cn_ <= 0.0 && cs_ <= 0.0) history_.reset();
    }

    /// After a property changed: recompute what is derived from the properties.
    void linearRefresh() { setMass(mass_eff_); }

    bool noTension() const { return no_tension_; }
    bool noShearDashpotWhileSliding() const { return no_shear_dp_sliding_; }

    /// The linear law's forces (n, s) and, with energy tracing on, its strain, slip and dashpot
    /// energies, without writing them to fd (it sets kFdSliding). `incremental` is PFC's
    /// lin_mode 1: the normal force is updated by kn du_n from its last value (no tension) and
    /// need not come down to zero where the overlap does: at separation it is paid the corner of
    /// a force that runs on at kn u_dot_n from its last value (incrementalClosing), and what it
    /// still holds there is released; `linear` and `rrlinear` use the absolute form kn u_n.
    struct Forces {
        double fn = 0.0, fs = 0.0;
        double strain = 0.0, slip = 0.0, dash = 0.0;
        double released = 0.0;  // incremental normal force let go at separation [J]
        Step step;
    };
    /// `parallel_n`, `parallel_s`: the forces of springs in parallel with the linear ones (a
    /// bond's, this step's, resisting sign: compression, -s_force), which the dashpots must not
    /// read as the rest of the model's load (lessParallelSprings, sdk/dashpot.hpp).
    /// (Fd: FdBlock, or LaneFd for the lane law: the same code either way.)
    template <class Fd>
    Forces linearForces(Fd& fd, bool incremental = false, double parallel_n = 0.0,
                        double parallel_s = 0.0) {
        if (fd.mass_eff != mass_eff_) setMass(fd.mass_eff);
        const double dt = fd.tdel;
        Forces out;
        // Gravity, the other contacts and the rest, as seen in the rates (sdk/dashpot.hpp);
        // followed on every call, touching or not, so that it is current at the next touch.
        DashpotLoad other{};
        if (cn_ > 0.0 || cs_ > 0.0) {
            const double inv_n = cn_ > 0.0 ? inv_mass_eff_ : 0.0;
            const double inv_s = cs_ > 0.0 ? fd.inv_mass_eff_s : 0.0;
            other = lessParallelSprings(history_.observe(fd, inv_n, inv_s), parallel_n, parallel_s,
                                        inv_n, inv_s);
        }

        if (fd.u_n <= 0.0) {
            // Separated. Pay what the last contact step owed for the part of the step the
            // contact lasted beyond (or fell short of) the step's centre (talus/sdk/dashpot.hpp):
            // the dashpots and the shear spring act until separation; the normal spring's force
            // falls to zero there (a corner), or, incremental, runs on from its last value to
            // separation (the corner of a finite force; what it holds there is released: until
            // 2026-11-28 neither was paid nor booked, and a ball bouncing on pbond with lin_mode 1
            // lost 1e-3 of its throughput unbooked). With the no-tension limit and a normal
            // dashpot the normal force had already reached zero before the overlap did: nothing
            // is owed.
            if (touching_) {
                const double frac = closingFraction(last_overlap_, fd.u_n);
                const bool normal_corner = !noTension() || cn_ <= 0.0;
                Corners k = linearClosingCorners(kn, ks, fric, lin_fs, lin_slip == 1.0, fd, frac,
                                                 normal_corner && !incremental);
                if (incremental && normal_corner) {
                    const IncrementalClosing c =
                        incrementalClosing(lin_fn, kn, fd.u_dot_n, fd.tdel, frac);
                    k.normal = c.corner;
                    if (lin_slip == 1.0) k.shear = std::copysign(fric * c.corner, lin_fs);
                    out.released = c.left;
                }
                const double dn = normal_corner
                                      ? dashpotClosingForce(cn_, fd.u_dot_n, last_overlap_, fd.u_n)
                                      : 0.0;
                const double ds = dashpotClosingForce(cs_, fd.u_dot_s, last_overlap_, fd.u_n);
                out.fn = k.normal + dn;
                out.fs = k.shear - ds;
                out.dash = dn * fd.u_dot_n * dt + ds * fd.u_dot_s * dt;  // impulse times rate
                // The shear spring lets go as the contact ends: its energy goes to friction.
                out.slip = springEnergy(lin_fs, ks);
            }
            touching_ = false;
            lin_fn = lin_fs = dp_fn = dp_fs = lin_slip = 0.0;
            last_overlap_ = fd.u_n;
            return out;
        }

        const bool first = !touching_;
        touching_ = true;
        const double overlap_increment = fd.u_n - last_overlap_;
        last_overlap_ = fd.u_n;
        return contactStep(*this, fd, other, first, incremental, overlap_increment);
    }

    /// The law while the bodies touch (u_n > 0): `first`, the first contact step (the touch
    /// inside it); `other`, the dashpots' load from the rest of the model (sdk/dashpot.hpp);
    /// `overlap_increment`, u_n now less u_n at the last step, what the incremental normal force
    /// adds up. Why not fd.du_n = u_dot_n dt: the host's rate is the half step's relative
    /// velocity on the new normal, and when the pair turns (a spinning bonded rock) that reads
    /// a chord as an opening of |d| (omega dt)^2 / 2 a step that never happened. Summed over
    /// thousands of steps it drifted a resting fragment's bonds 10 mm from its geometry and a
    /// rock spinning at 20 rad/s gained 1.5 kJ a second; the geometric increment is exact, and
    /// the leapfrog's work on the pair (whole-step velocity, the mean of the two half steps) is
    /// what it gives. On S = LinearLaw (FDlaw) or LaneState (a lane row's doubles): the same
    /// code, so the lane law and FDlaw give the same bits.
    template <class S, class Fd>
    __attribute__((always_inline)) static Forces contactStep(S& s, Fd& fd, const DashpotLoad& other,
                                                             bool first, bool incremental,
                                                             double overlap_increment) {
        const double dt = fd.tdel;
        const bool energy = (fd.flags & kFdEnergyOn) != 0;
        Forces out;
        const double lead = first ? onsetFraction(fd.u_n, fd.du_n) : 0.5;
        // On the first step only the part of the shear increment after touch loads the spring.
        const double du_s = first ? fd.du_s * onsetFraction(fd.u_n, fd.du_n) : fd.du_s;

        // Incremental: from the last force; at a touch inside this step both forms give kn u_n.
        s.lin_fn = (incremental && !first) ? std::max(0.0, s.lin_fn + s.kn * overlap_increment)
                                           : s.kn * fd.u_n;
        const ShearResult sr = updateShearSpring(s.lin_fs, s.ks, du_s, s.fric * s.lin_fn);
        s.lin_slip = sr.sliding ? 1.0 : 0.0;

        const double dn =
            dashpotForceInv(s.cn_, s.inv_mass_eff_, fd.u_dot_n, s.lin_fn, dt, lead, other.normal);
        s.dp_fn = (s.no_tension_ && s.lin_fn + dn < 0.0) ? -s.lin_fn : dn;
        double ds = 0.0;  // resisting the shear motion
        if (!(sr.sliding && s.no_shear_dp_sliding_))
            ds = dashpotForceInv(s.cs_, fd.inv_mass_eff_s, fd.u_dot_s, -s.lin_fs, dt, lead,
                                 other.shear);
        s.dp_fs = -ds;

        // On the first step the springs' impulses miss their corners at touch (sdk/dashpot.hpp);
        // a sliding shear force follows the normal spring's corner (Coulomb).
        const Corners corner =
            first ? linearOnsetCorners(s.kn, s.ks, s.fric, s.lin_fs, sr.sliding, fd, lead)
                  : Corners{};
        out.fn = s.lin_fn + s.dp_fn + corner.normal;
        out.fs = s.lin_fs + s.dp_fs + corner.shear;
        if (sr.sliding) fd.flags |= kFdSliding;
        if (energy) {
            out.strain = springEnergy(s.lin_fn, s.kn) + springEnergy(s.lin_fs, s.ks);
            out.slip = sr.slip_work;
            out.dash = dashpotEnergy(s.cn_, s.dp_fn, dn, dt, lead) +
                       dashpotEnergy(s.cs_, ds, ds, dt, lead);
        }
        out.step = Step{true, first, lead};
        return out;
    }

    /// The linear force-displacement law: writes n_force, s_force, moment = 0, the estimates
    /// (krest = 0) and, with energy tracing on, strain, slip and dashpot energies.
    template <class Fd>
    Step linearLaw(Fd& fd) {
        const Forces f = linearForces(fd);
        writeLaw(fd, f, knest_, ksest_);
        return f.step;
    }

    /// What the law hands back in `fd`: the forces, moment 0, the estimates (krest 0), and
    /// with tracing on the strain, slip and dashpot energies.
    template <class Fd>
    static void writeLaw(Fd& fd, const Forces& f, double knest, double ksest) {
        fd.n_force = f.fn;
        fd.s_force = f.fs;
        fd.moment = 0.0;
        fd.knest = knest;
        fd.ksest = ksest;
        fd.krest = 0.0;
        if (fd.flags & kFdEnergyOn) {
            fd.energy[kEnergyStrain] = f.strain;
            fd.energy[kEnergySlip] = f.slip;
            fd.energy[kEnergyDashpot] = f.dash;
        }
    }

    /// The linear law's per-contact state, in the layout of `linear`'s SaveRestore version 2;
    /// `history_version` is the version at which the dashpots' history was added (data older than
    /// that restores without it: the next call then estimates nothing, as on a first touch).
    void linearSaveRestore(ModelSaveObject& so, int32_t history_version) {
        so.Double(lin_fn);
        so.Double(lin_fs);
        so.Double(dp_fn);
        so.Double(dp_fs);
        so.Double(lin_slip);
        so.Double(mass_eff_);
        so.Double(last_overlap_);
        if (so.IsSaving() || so.DataVersion() >= history_version)
            history_.saveRestore(so);
        else
            history_.reset();
        so.Bool(touching_);
    }

    // --- lanes (sdk/lanes.hpp): a touching contact's step in the lanes runs contactStep and the
    // dashpot history on its row, the same code as FDlaw, so the same bits. The row: the
    // constants the step reads (kLinearLaneConstants), then the state it writes.
    static constexpr int kLinearLaneConstants = 10;
    static constexpr int kLaneMassEff = 3, kLaneCs = 6;  // (row[3] mass_eff, row[6] cs)
    /// The law's kernel id (ABI 1.3, talus_plugin_kernel): a model that runs linearLaneStep on
    /// these rows may name it, and a host that knows it runs the step itself. Raise the number
    /// whenever the rows or the step change.
    static constexpr const char* kKernelId = "talus.sdk.LinearLaw/1";
    static constexpr int kLinearLaneStateSize =
        kLinearLaneConstants + 6 + DashpotHistory::kLaneStateSize;
    static const char* const* linearLaneStateNames() {
        static const char* const names[kLinearLaneStateSize] = {
            "kn",        "ks",       "fric",     "mass_eff",     "inv_mass_eff", "cn",
            "cs",        "knest",    "ksest",    "modes",        "lin_fn",       "lin_fs",
            "dp_fn",     "dp_fs",    "lin_slip", "last_overlap", "dp_dt_prev",   "dp_rate_n",
            "dp_rate_s", "dp_est_n", "dp_est_s"};
        return names;
    }
    /// Row <- this contact, if it touches (a first touch and a separation stay with FDlaw: they
    /// pay the corners).
    bool linearToLane(double* r) const {
        if (!touching_) return false;
        r[0] = kn, r[1] = ks, r[2] = fric, r[3] = mass_eff_, r[4] = inv_mass_eff_;
        r[5] = cn_, r[6] = cs_, r[7] = knest_, r[8] = ksest_;
        r[9] = (no_tension_ ? 1.0 : 0.0) + (no_shear_dp_sliding_ ? 2.0 : 0.0);
        linearStateToLane(r);
        return true;
    }
    /// This contact's state <- row (its constants never change in the lanes).
    void linearFromLane(const double* r) {
        lin_fn = r[10], lin_fs = r[11], dp_fn = r[12], dp_fs = r[13], lin_slip = r[14];
        last_overlap_ = r[15];
        history_.fromLane(r, 16);
        touching_ = true;
    }
    /// A lane row's values under the names contactStep reads and writes, copied in and out (in
    /// registers, not through the row: the law's stores cannot alias its loads).
    struct LaneState {
        double kn, ks, fric, cn_, cs_, inv_mass_eff_;
        bool no_tension_, no_shear_dp_sliding_;
        double lin_fn, lin_fs, dp_fn, dp_fs, lin_slip;
    };
    /// One contact's step in the lanes: what linearLaw does, on the row (declined at separation,
    /// which pays the closing corners, and when the effective mass changed: setMass).
    template <class Fd>
    __attribute__((always_inline)) static bool linearLaneStep(double* r, Fd& fd) {
        if (!(fd.u_n > 0.0) || fd.mass_eff != r[3]) return false;
        const double modes = r[9];
        LaneState s{r[0],         r[1],  r[2],  r[5],  r[6],  r[4], modes == 1.0 || modes == 3.0,
                    modes >= 2.0, r[10], r[11], r[12], r[13], r[14]};
        DashpotLoad other{};
        if (s.cn_ > 0.0 || s.cs_ > 0.0) {
            DashpotHistory history;
            history.fromLane(r, 16);
            other = history.observe(fd, s.cn_ > 0.0 ? s.inv_mass_eff_ : 0.0,
                                    s.cs_ > 0.0 ? fd.inv_mass_eff_s : 0.0);
            history.toLane(r, 16);
        }
        writeLaw(fd, contactStep(s, fd, other, false, false, fd.u_n - r[15]), r[7], r[8]);
        r[10] = s.lin_fn, r[11] = s.lin_fs, r[12] = s.dp_fn, r[13] = s.dp_fs, r[14] = s.lin_slip;
        r[15] = fd.u_n;
        return true;
    }
    void linearStateToLane(double* r) const {
        r[10] = lin_fn, r[11] = lin_fs, r[12] = dp_fn, r[13] = dp_fs, r[14] = lin_slip;
        r[15] = last_overlap_;
        history_.toLane(r, 16);
    }

    double linearKnEstimate() const { return kn * dashpotStiffnessFactor(dp_nratio); }
    double linearKsEstimate() const { return ks * dashpotStiffnessFactor(dp_sratio); }
    /// Half period of the faster undamped spring; damping only lengthens the contact. The
    /// sticking shear spring of a disk sees the inverse mass 1/m* + r^2/I = 3/m* (both ends
    /// disks, or a disk on a wall), so it is the faster one when 3 ks > kn; resolving only the
    /// normal impact then left it a few steps per half cycle, and leapfrog created a few percent
    /// of the shear energy at each separation (stress seeds 228 and 684;
    /// docs/models/linear.md). A sphere's inertia (3.5/m*) would be 8% faster than this.
    /// Without kn there is no force at all (the shear force is limited by fric kn u_n).
    double linearContactDuration(double mass_eff) const {
        return kn > 0.0 ? M_PI * std::sqrt(mass_eff / std::max(kn, 3.0 * ks)) : HUGE_VAL;
    }
};

/// The linear law's settable properties, for the property table of a model D deriving from
/// LinearLaw: kn, ks, fric, dp_nratio, dp_sratio, dp_mode (PFC order).
template <class D>
PropTable<D> linearSettableProps() {
    // clang-format off
    return {
        {{"kn", "N/m", kPropInheritable, 0.0, "normal stiffness", nullptr}, &D::kn, 0.0, kStiffnessMax},
        {{"ks", "N/m", kPropInheritable, 0.0, "shear stiffness", nullptr}, &D::ks, 0.0, kStiffnessMax},
        {{"fric", "-", kPropInheritable, 0.0, "friction coefficient", nullptr}, &D::fric, 0.0},
        {{"dp_nratio", "-", 0, 0.0, "normal critical damping ratio", nullptr},
         &D::dp_nratio, 0.0, 1.0, false, "(1 = critical)"},
        {{"dp_sratio", "-", 0, 0.0, "shear critical damping ratio", nullptr},
         &D::dp_sratio, 0.0, 1.0, false, "(1 = critical)"},
        {{"dp_mode", "-", kPropInteger, 0.0, "dashpot mode", linearDpModeNames()}, &D::dp_mode,
         0.0, 3.0},
    };
    // clang-format on
}

/// The linear law's read-only state: lin_fn, lin_fs, dp_fn, dp_fs, lin_slip.
template <class D>
PropTable<D> linearStateProps() {
    // clang-format off
    return {
        {{"lin_fn", "N", kPropReadOnly | kPropState, 0.0, "linear normal force", nullptr},
         &D::lin_fn},
        {{"lin_fs", "N", kPropReadOnly | kPropState, 0.0, "linear shear force", nullptr},
         &D::lin_fs},
        {{"dp_fn", "N", kPropReadOnly | kPropState, 0.0, "normal dashpot force", nullptr},
         &D::dp_fn},
        {{"dp_fs", "N", kPropReadOnly | kPropState, 0.0, "shear dashpot force", nullptr},
         &D::dp_fs},
        {{"lin_slip", "-", kPropReadOnly | kPropState, 0.0, "1 while sliding", nullptr},
         &D::lin_slip},
    };
    // clang-format on
}

}  // namespace talus::sdk
