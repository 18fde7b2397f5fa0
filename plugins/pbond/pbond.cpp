// SPDX-License-Identifier: MIT
//
// `pbond`: the linear contact in parallel with a parallel bond, the 2D form of Potyondy &
// Cundall (2004) as PFC's `linearpbond` defines it (PFC's linearpbond, Itasca's documentation;
// docs/models/pbond.md).
//
// Linear part (the `linear` model's springs, slider and dashpots, talus/sdk/linear_law.hpp):
//   normal   F_n^l = kn u_n                    lin_mode 0 (absolute), u_n > 0, else 0
//            F_n^l <- max(0, F_n^l + kn du_n)  lin_mode 1 (incremental), while u_n > 0
//   shear    F_s^l <- F_s^l - ks dU_s,  |F_s^l| <= fric F_n^l   (slips even while bonded)
// Bond (a rectangle 2 R_b x t on the contact plane, t = 1; all incremental from bonding):
//   R_b = pb_rmul min(R_A, R_B)   (ball-wall: the ball's R)
//   A = 2 R_b t,  I = 2 R_b^3 t / 3
//   F_n^b <- F_n^b + pb_kn A du_n        (compression +, du_n the overlap increment)
//   F_s^b <- F_s^b - pb_ks A dU_s
//   M^b   <- M^b   - pb_kn I dtheta      (moment on end 2; dtheta end 2 minus end 1)
//   sigma = -F_n^b / A + pb_mcf |M^b| R_b / I         (peak normal stress, tension +)
//   tau   = |F_s^b| / A
//   tension break: sigma > 0 and sigma >= pb_ten                       -> pb_state 1
//   else shear break: tau > 0 and tau >= tau_c,
//        tau_c = pb_coh - s tan(pb_fa), s = -F_n^b / A, s capped at pb_ten   -> pb_state 2
//   (PFC's Mohr-Coulomb strength with its tensile cut-off; pb_fa = 0 is P&C 2004's constant
//   shear strength). A break removes the bond's force, moment and stiffness; the linear part
//   carries on with its friction.
// Deformability forms (set > 0 to use): kn = 2 emod min(R)/L, ks = kn/kratio; pb_kn =
// pb_emod/L, pb_ks = pb_kn/pb_kratio; L = R_A + R_B (ball-wall: the ball's R).
//
// Energies: strain = the linear springs' F^2/2k; bond_strain = F_n^2/(2 pb_kn A) +
// F_s^2/(2 pb_ks A) + M^2/(2 pb_kn I); slip and dashpot from the linear part. On a break the
// trial forces of the breaking step were never applied (the bodies felt the last step's bond
// forces, then none), so the energy released is F_old F_trial / (2k) per bond spring, as for
// cbond (docs/models/cbond.md, Energies): what closes the leapfrog balance. A spring whose force
// changed sign inside the breaking step (the crossing) gets the corner of its ramp up to the
// failure and releases F(g)^2 / (2k); a bond made at touch pays its onset corner
// (docs/models/pbond.md, Energies). A bond removed by writing `bonded` = 0 (m:unbond) goes at
// that step: the bodies still feel its last force for the half step after it, then nothing, so
// the next FDlaw releases F_old F_trial / (2k) per spring too (what it stored plus that half
// step's work), the same value a break at a step boundary releases. With lin_mode 1 the linear
// normal force is paid its corner up to separation, and what it holds there is released
// (talus/sdk/linear_law.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "talus/contact_model.hpp"
#include "talus/sdk/corners.hpp"
#include "talus/sdk/dashpot.hpp"
#include "talus/sdk/linear_law.hpp"
#include "talus/sdk/model_base.hpp"
#include "talus/sdk/parallel_bond_law.hpp"
#include "talus/sdk/shear_spring.hpp"

namespace {

using namespace talus;
using namespace talus::sdk;

constexpr double kInf = std::numeric_limits<double>::infinity();
const char* const kLinModes[] = {"absolute", "incremental", nullptr};
const char* const kBondFlag[] = {"no", "yes", nullptr};
// PFC's pb_state numbering (PFC's linearpbond, Itasca's documentation).
const char* const kStates[] = {"unbonded", "broken_tension", "broken_shear", "bonded", nullptr};
enum PbState { kUnbonded = 0, kBrokenTension = 1, kBrokenShear = 2, kBonded = 3 };

/// a b / (2 k) [J]: with a = b the energy of a linear spring carrying that force.
double crossEnergy(double a, double b, double k) { return k > 0.0 ? 0.5 * a * b / k : 0.0; }

class PBond final : public ModelBase<PBond>, public LinearLaw {
public:
    static constexpr const char* kName = "pbond";

    // properties (PFC names) besides the linear law's
    double lin_mode = 0.0;   // 0 absolute, 1 incremental normal force
    double emod = 0.0;       // linear part's effective modulus [Pa]; 0: kn, ks as given
    double kratio = 0.0;     // kn / ks with emod [-]
    double pb_kn = 0.0;      // bond normal stiffness [Pa/m]
    double pb_ks = 0.0;      // bond shear stiffness [Pa/m]
    double pb_ten = 0.0;     // tensile strength [Pa] (inf: unbreakable in tension)
    double pb_coh = 0.0;     // cohesion [Pa] (inf: unbreakable in shear)
    double pb_fa = 0.0;      // friction angle [deg]
    double pb_mcf = 1.0;     // moment-contribution factor [-]
    double pb_rmul = 1.0;    // radius multiplier [-]
    double pb_emod = 0.0;    // bond modulus [Pa]; 0: pb_kn, pb_ks as given
    double pb_kratio = 0.0;  // pb_kn / pb_ks with pb_emod [-]
    double bonded = 0.0;     // 1 while bonded (settable: the bond contract, wave 9)
    // state (read-only)
    double pb_state = kUnbonded;
    double pb_rad = 0.0;    // bond radius R_b [m]
    double pb_fn = 0.0;     // bond normal force, compression + [N]
    double pb_fs = 0.0;     // bond shear force along t [N]
    double pb_m = 0.0;      // bond moment on end 2 [N m]
    double pb_sigma = 0.0;  // peak normal stress, tension + [Pa] (at failure after a break)
    double pb_tau = 0.0;    // peak shear stress [Pa] (at failure after a break)
    // per-contact geometry and derived values
    double r_min_ = 0.0, r_sum_ = 0.0;  // min(R_A, R_B) and R_A + R_B (ball-wall: R, R) [m]
    double area_ = 0.0, inertia_ = 0.0;
    double kbn_ = 0.0, kbs_ = 0.0, kbr_ = 0.0;  // bond stiffnesses [N/m, N/m, N m/rad]
    // ... raised for the dashpots as the time step sees them (estimates(), every step)
    double kbn_est_ = 0.0, kbs_est_ = 0.0;
    bool bond_fresh_ = false;  // the next FDlaw starts the bond (no increment)
    // A bond removed by a write of `bonded` = 0, released at the next FDlaw: what it stored at
    // its last step [J] and its forces then [N, N, N m].
    bool let_go_ = false;
    double let_go_energy_ = 0.0, let_go_fn_ = 0.0, let_go_fs_ = 0.0, let_go_m_ = 0.0;

    // One property per entry (clang-format would put every value on its own line).
    // clang-format off
    static const PropTable<PBond>& Table() {
        static const PropTable<PBond> t = [] {
            PropTable<PBond> rows = linearSettableProps<PBond>();
            const PropTable<PBond> own = {
                {{"lin_mode", "-", kPropInteger, 0.0, "linear normal force: 0 absolute, 1 incremental", kLinModes},
                 &PBond::lin_mode, 0.0, 1.0},
                {{"emod", "Pa", 0, 0.0, "effective modulus of the linear part (> 0: kn = 2 emod min(R)/L)", nullptr},
                 &PBond::emod, 0.0, kStiffnessMax},
                {{"kratio", "-", 0, 0.0, "kn/ks with emod", nullptr}, &PBond::kratio, 0.0},
                {{"pb_kn", "Pa/m", 0, 0.0, "bond normal stiffness (stress/displacement)", nullptr},
                 &PBond::pb_kn, 0.0, kStiffnessMax},
                {{"pb_ks", "Pa/m", 0, 0.0, "bond shear stiffness (stress/displacement)", nullptr},
                 &PBond::pb_ks, 0.0, kStiffnessMax},
                {{"pb_ten", "Pa", 0, 0.0, "bond tensile strength (inf: unbreakable)", nullptr},
                 &PBond::pb_ten, 0.0},
                {{"pb_coh", "Pa", 0, 0.0, "bond cohesion (inf: unbreakable in shear)", nullptr},
                 &PBond::pb_coh, 0.0},
                {{"pb_fa", "deg", 0, 0.0, "bond friction angle", nullptr}, &PBond::pb_fa, 0.0, 89.0},
                {{"pb_mcf", "-", 0, 1.0, "moment-contribution factor", nullptr}, &PBond::pb_mcf, 0.0, 1.0},
                {{"pb_rmul", "-", 0, 1.0, "bond radius multiplier", nullptr}, &PBond::pb_rmul, 0.0, 1e6, true},
                {{"pb_emod", "Pa", 0, 0.0, "bond modulus (> 0: pb_kn = pb_emod/L)", nullptr},
                 &PBond::pb_emod, 0.0, kStiffnessMax},
                {{"pb_kratio", "-", 0, 0.0, "pb_kn/pb_ks with pb_emod", nullptr}, &PBond::pb_kratio, 0.0},
                {{"bonded", "-", kPropInteger | kPropState, 0.0, "1: bonded (set 1 to bond, 0 to unbond)", kBondFlag},
                 &PBond::bonded, 0.0, 1.0},
                {{"pb_state", "-", kPropReadOnly | kPropState | kPropInteger, 0.0, "bond state", kStates},
                 &PBond::pb_state},
                {{"pb_rad", "m", kPropReadOnly | kPropState, 0.0, "bond radius", nullptr}, &PBond::pb_rad},
                {{"pb_fn", "N", kPropReadOnly | kPropState, 0.0, "bond normal force (compression +)", nullptr},
                 &PBond::pb_fn},
                {{"pb_fs", "N", kPropReadOnly | kPropState, 0.0, "bond shear force", nullptr}, &PBond::pb_fs},
                {{"pb_m", "N m", kPropReadOnly | kPropState, 0.0, "bond moment on end 2", nullptr}, &PBond::pb_m},
                {{"pb_sigma", "Pa", kPropReadOnly | kPropState, 0.0, "peak normal stress (tension +)", nullptr},
                 &PBond::pb_sigma},
                {{"pb_tau", "Pa", kPropReadOnly | kPropState, 0.0, "peak shear stress", nullptr}, &PBond::pb_tau},
            };
            for (const auto& r : own) rows.push_back(r);
            for (const auto& r : linearStateProps<PBond>()) rows.push_back(r);
            return rows;
        }();
        return t;
    }
    // clang-format on

    int32_t AcceptProp(int32_t index, double value) override {
        const auto& t = Table();
        if (index < 0 || index >= PropCount()) return ModelBase<PBond>::AcceptProp(index, value);
        const auto& spec = t[static_cast<std::size_t>(index)];
        // Strengths may be infinite (an unbreakable bond); nothing else may.
        if (std::isinf(value) && spec.member != &PBond::pb_ten && spec.member != &PBond::pb_coh)
            return fail(std::string("pbond: '") + spec.info.name + "' must be finite (got " +
                        (value > 0 ? "inf" : "-inf") + ")");
        if (spec.member != &PBond::bonded) return ModelBase<PBond>::AcceptProp(index, value);
        const double before = bonded;
        if (const int32_t rc = ModelBase<PBond>::AcceptProp(index, value)) return rc;
        if (value == 1.0 && before != 1.0) {
            // Bond at the current geometry: force and moment start from zero, and the next
            // FDlaw's increment (from the geometry the host saw last) is not counted.
            pb_state = kBonded;
            pb_fn = pb_fs = pb_m = pb_sigma = pb_tau = 0.0;
            bond_fresh_ = true;
        } else if (value == 0.0 && before == 1.0) {
            // Unbond (m:unbond): no event. The bond's last forces are already in the forces
            // the bodies feel next (the host summed them at the last step), so its energy is
            // released at the next FDlaw, once that step's motion is known (fdlaw). A bond
            // made since the last FDlaw holds nothing (bond_fresh_: zero forces), and adds
            // nothing to a removal still pending.
            let_go_ = true;
            let_go_energy_ += bondEnergy();
            let_go_fn_ += pb_fn;
            let_go_fs_ += pb_fs;
            let_go_m_ += pb_m;
            pb_state = kUnbonded;
            pb_fn = pb_fs = pb_m = pb_sigma = pb_tau = 0.0;
            bond_fresh_ = false;
        }
        return 0;
    }

    const char* PreCycle(const PropBlock& pb) override {
        if (const char* why = ModelBase<PBond>::PreCycle(pb)) return why;
        if (emod > 0.0 && !(kratio > 0.0))
            errorText() = "pbond: 'kratio' must be > 0 when 'emod' is set (ks = kn/kratio)";
        else if (pb_emod > 0.0 && !(pb_kratio > 0.0))
            errorText() =
                "pbond: 'pb_kratio' must be > 0 when 'pb_emod' is set (pb_ks = pb_kn/pb_kratio)";
        else
            return nullptr;
        return errorText().c_str();
    }

    bool inherit(const PropBlock& pb) {
        linearInherit(pb);
        const bool wall = pb.end2_type == kEndWall || !(pb.radius[1] > 0.0);
        r_min_ = wall ? pb.radius[0] : std::min(pb.radius[0], pb.radius[1]);
        r_sum_ = wall ? pb.radius[0] : pb.radius[0] + pb.radius[1];
        refresh();
        return true;
    }
    void onPropChanged() { refresh(); }

    /// Stiffnesses from the deformability forms, the bond's geometry and the cached values.
    void refresh() {
        if (r_min_ > 0.0 && r_sum_ > 0.0) {
            // 2D deformability (PFC's linearpbond, Itasca's documentation): kn = A E / L with A = 2
            // min(R) t.
            if (emod > 0.0 && kratio > 0.0) {
                kn = 2.0 * emod * r_min_ / r_sum_;
                ks = kn / kratio;
            }
            // P&C 2004: pb_kn = E_bar / (R_A + R_B).
            if (pb_emod > 0.0 && pb_kratio > 0.0) {
                pb_kn = pb_emod / r_sum_;
                pb_ks = pb_kn / pb_kratio;
            }
            pb_rad = pb_rmul * r_min_;
        }
        area_ = 2.0 * pb_rad;                             // t = 1
        inertia_ = 2.0 * pb_rad * pb_rad * pb_rad / 3.0;  // (2/3) R_b^3 t
        kbn_ = pb_kn * area_;
        kbs_ = pb_ks * area_;
        kbr_ = pb_kn * inertia_;
        kbn_est_ = kbn_ * dashpotStiffnessFactor(dp_nratio);
        kbs_est_ = kbs_ * dashpotStiffnessFactor(dp_sratio);
        linearRefresh();
    }

    bool isBonded() const { return bonded == 1.0; }

    /// The linear part of the step: talus/sdk/linear_law.hpp's law in PFC's lin_mode, after
    /// the bond contract's first call; writes lin_* and dp_*, returns the forces and energies.
    LinearLaw::Forces linearPart(FdBlock& fd, double overlap_increment) {
        if (fd.flags & kFdFirstCall) {
            // The bond contract: on a first call the forces on entry are the old contact's
            // (m:bond; zero for a contact the engine just made). A contact that was already in
            // overlap at the last step carries on from them: its shear force always, its normal
            // force in incremental mode (absolute mode recomputes kn u_n).
            const double last = fd.u_n - fd.du_n;
            if (last > 0.0) {
                touching_ = true;
                last_overlap_ = last;
                lin_fn = std::max(0.0, fd.n_force);
                lin_fs = fd.s_force;
            }
        }
        // The bond's trial forces, which act in parallel with the linear springs: the
        // dashpots' load leaves them out (sdk/dashpot.hpp, lessParallelSprings).
        const bool steady_bond = isBonded() && !bond_fresh_;
        const double bond_n = steady_bond ? pb_fn + kbn_ * overlap_increment : 0.0;
        const double bond_s = steady_bond ? pb_fs - kbs_ * fd.du_s : 0.0;
        return linearForces(fd, lin_mode == 1.0, bond_n, -bond_s);
    }

    /// Peak stresses of the bond now (P&C 2004 eq. for the 2D rectangle; PFC pbSMax):
    /// talus/sdk/parallel_bond_law.hpp, which the steady step uses too.
    void bondStresses() {
        const ParallelBondLaw::Stresses st = ParallelBondLaw::stresses(*this, pb_fn, pb_fs, pb_m);
        pb_sigma = st.sigma;
        pb_tau = st.tau;
    }

    /// The bond's failure mode at its current stresses (tension first, then Mohr-Coulomb shear
    /// with the tensile cut-off: ParallelBondLaw::failure).
    ParallelBondLaw::Failure bondFailure() const {
        return ParallelBondLaw::failure(*this, pb_fn, ParallelBondLaw::Stresses{pb_sigma, pb_tau});
    }

    /// The time-step estimates: the bond's springs beside the linear ones (PFC adds k_n A,
    /// k_s A, k_n I); the dashpot factor is applied to the sum, which over-estimates (safe): the
    /// dashpots are sized on kn and ks alone.
    ParallelBondLaw::Estimates estimates() const {
        const bool b = isBonded();
        return {knest_ + (b ? kbn_est_ : 0.0), ksest_ + (b ? kbs_est_ : 0.0), b ? kbr_ : 0.0};
    }

    /// One bond spring over the breaking step: its force at the last step (what the bodies
    /// felt), its trial force, its stiffness.
    struct Spring {
        double old_f, trial, k;
        double at(double g) const { return old_f + g * (trial - old_f); }
        /// Energy released at a break at fraction g of the step; `corner` gets the force owed on
        /// this step when the spring's force changed sign (see fdlaw).
        double released(double g, double& corner) const {
            if (!(k > 0.0)) return 0.0;
            if (old_f * trial >= 0.0) return crossEnergy(old_f, trial, k);
            // The scheme paid old_f up to half a step after the last step and nothing since;
            // the spring's force ran linearly to at(g) and stopped there: owed is its integral
            // from dt/2 to g dt, as a force over this step (talus/sdk/corners.hpp, the sticking
            // shear spring's closing corner). Then the work the bodies received is the
            // spring's, and what it gives up is what it held, F(g)^2 / (2k): the leapfrog
            // balance closes up to its bounded term k du^2 / 8 (docs/models/pbond.md).
            corner = old_f * (g - 0.5) + 0.5 * (trial - old_f) * (g * g - 0.25);
            return springEnergy(at(g), k);
        }
    };

    void setForcesAt(const Spring& n, const Spring& s, const Spring& m, double g) {
        pb_fn = n.at(g);
        pb_fs = s.at(g);
        pb_m = m.at(g);
    }

    /// The fraction g in (0, 1] of the step at which the bond's forces, moving linearly from
    /// the last step's to the trial ones, first meet the failure criterion of the break's mode
    /// (bisection to rounding: 60 halvings of the step; breaks are rare).
    double failureFraction(const Spring& n, const Spring& s, const Spring& m, bool tension) {
        double lo = 0.0, hi = 1.0;
        for (int it = 0; it < 60; ++it) {
            const double mid = 0.5 * (lo + hi);
            setForcesAt(n, s, m, mid);
            bondStresses();
            const ParallelBondLaw::Stresses st{pb_sigma, pb_tau};
            const bool failed = tension ? ParallelBondLaw::tensionFails(*this, st)
                                        : ParallelBondLaw::shearFails(*this, pb_fn, st);
            (failed ? hi : lo) = mid;
        }
        return hi;
    }

    void fdlaw(FdBlock& fd) {
        // A contact that touched at its last step and goes on touching, with its bond intact
        // and not breaking or unbonded, takes the SDK's steady step
        // (talus/sdk/parallel_bond_law.hpp: also the lane law's);
        // everything else is below.
        if (!let_go_ && !bond_fresh_ && touching_ &&
            ParallelBondLaw::steadyStep(*this, fd, estimates()))
            return;
        const bool energy = (fd.flags & kFdEnergyOn) != 0;
        // The overlap's own increment since the last step (before linearPart moves
        // last_overlap_ on): what the bond's normal spring adds up, not u_dot_n dt, which a
        // turning pair reads as an opening (LinearLaw::contactStep).
        const double overlap_increment = fd.u_n - last_overlap_;
        const LinearLaw::Forces lin = linearPart(fd, overlap_increment);
        double released = 0.0;
        if (let_go_) {
            // A bond removed after the last step (m:unbond): the bodies felt its last forces
            // over the half step after that step and nothing since. It releases what it stored
            // plus that half step's work, F_old^2 / 2k + F_old du / 2 = F_old F_trial / (2k) per
            // spring, as a break between the steps would (cbond's rule): the balance closes
            // without touching the dynamics.
            released = let_go_energy_ +
                       0.5 * (let_go_fn_ * fd.du_n - let_go_fs_ * fd.du_s - let_go_m_ * fd.dtheta);
            let_go_ = false;
            let_go_energy_ = let_go_fn_ = let_go_fs_ = let_go_m_ = 0.0;
        }
        struct {
            double n = 0.0, s = 0.0, m = 0.0;
        } corner;  // the bond's corners [N, N, N m]: onset (bond at touch), break (crossing)
        if (isBonded()) {
            if (bond_fresh_) {
                // Bonded at the geometry the host saw last (this call's u_n): no increment.
                bond_fresh_ = false;
                pb_fn = pb_fs = pb_m = 0.0;
                // A bond made at touch (a rule with bonded = 1: this is the contact's first
                // call) has forces that ramp from zero at this step: the scheme's window of this
                // step's (zero) force misses their integral over its second half, k du / 8 as a
                // force over the step (talus/sdk/corners.hpp, springOnsetCorrection with the
                // touch at the step; cbond pays its onset corner likewise). Not for a bond set
                // on an existing contact (m:bond): the step of that call was sized without the
                // bond, and the bodies are at rest there as a rule.
                if (fd.flags & kFdFirstCall) {
                    corner.n = 0.125 * kbn_ * fd.du_n;
                    corner.s = -0.125 * kbs_ * fd.du_s;
                    corner.m = -0.125 * kbr_ * fd.dtheta;
                }
            } else {
                const double fn_old = pb_fn, fs_old = pb_fs, m_old = pb_m;
                pb_fn += kbn_ * overlap_increment;
                pb_fs -= kbs_ * fd.du_s;
                pb_m -= kbr_ * fd.dtheta;
                bondStresses();
                const ParallelBondLaw::Failure failure = bondFailure();
                const bool tension = failure == ParallelBondLaw::kTension;
                if (failure != ParallelBondLaw::kIntact) {
                    const Spring n{fn_old, pb_fn, kbn_}, s{fs_old, pb_fs, kbs_},
                        m{m_old, pb_m, kbr_};
                    // Where inside the step the bond failed, on the straight path from the last
                    // step's forces to the trial ones, and its stresses there: the stresses at
                    // failure (pb_sigma, pb_tau and the bond_break event).
                    const double g = failureFraction(n, s, m, tension);
                    setForcesAt(n, s, m, g);
                    bondStresses();
                    fd.flags |= kFdBreakStress;
                    fd.reserved[0] = pb_sigma;
                    fd.reserved[1] = pb_tau;
                    // The bond material goes with its force, moment and stiffness. Per spring
                    // (the work of the three splits exactly, docs/models/pbond.md "Energies"):
                    // one whose force kept its sign releases F_old F_trial / (2k), what closes
                    // the leapfrog balance without touching the dynamics (cbond's rule; zero for
                    // a bond made and broken in one step). One whose force changed sign inside
                    // the step (the crossing: a stiff or weak bond, or a coarse step, goes from
                    // compression through its whole tensile range) would book a negative release,
                    // energy the scheme really gave the bodies (0.7% of an impact at resolution
                    // 10, pbond_crossing.lua). It gets the corner of its force ramp up to the
                    // failure instead, and releases what it held at the failure, F(g)^2 / (2k).
                    released +=
                        n.released(g, corner.n) + s.released(g, corner.s) + m.released(g, corner.m);
                    bonded = 0.0;
                    pb_state = tension ? kBrokenTension : kBrokenShear;
                    pb_fn = pb_fs = pb_m = 0.0;
                    fd.flags |= kFdBroken;
                    fd.break_mode = tension ? kBreakTension : kBreakShear;
                }
            }
            if (isBonded()) bondStresses();
        }
        // The break corner is paid on the breaking step itself: its force window starts half a
        // step after the last one the bond's force was applied at.
        fd.n_force = lin.fn + pb_fn + corner.n;
        fd.s_force = lin.fs + pb_fs + corner.s;
        fd.moment = pb_m + corner.m;
        const bool b = isBonded();
        const ParallelBondLaw::Estimates est = estimates();
        fd.knest = est.kn;
        fd.ksest = est.ks;
        fd.krest = est.kr;
        if (b) fd.flags |= kFdBonded | kFdKeep;
        if (energy) {
            fd.energy[kEnergyStrain] = lin.strain;
            fd.energy[kEnergySlip] = lin.slip;
            fd.energy[kEnergyDashpot] = lin.dash;
            fd.energy[kEnergyBondStrain] = bondEnergy();
            fd.energy[kEnergyReleased] = released + lin.released;
        }
    }

    /// Strain energy in the bond [J]: F_n^2/(2 kn A) + F_s^2/(2 ks A) + M^2/(2 kn I).
    double bondEnergy() const { return ParallelBondLaw::bondEnergy(*this); }

    // Version 1: the first layout; 2 adds the removed bond awaiting its release.
    void saveRestoreState(ModelSaveObject& so) {
        linearSaveRestore(so, 1);
        so.Double(pb_state);
        so.Double(pb_rad);
        so.Double(pb_fn);
        so.Double(pb_fs);
        so.Double(pb_m);
        so.Double(pb_sigma);
        so.Double(pb_tau);
        so.Double(r_min_);
        so.Double(r_sum_);
        so.Bool(bond_fresh_);
        if (so.IsSaving() || so.DataVersion() >= 2) {
            so.Bool(let_go_);
            so.Double(let_go_energy_);
            so.Double(let_go_fn_);
            so.Double(let_go_fs_);
            so.Double(let_go_m_);
        }
    }

    // Lanes (sdk/lanes.hpp): the steady step's values in a row (ParallelBondLaw's layout).
    static constexpr int kLaneStateSize = ParallelBondLaw::kLaneStateSize;
    static const char* const* laneStateNames() { return ParallelBondLaw::laneStateNames(); }
    bool toLane(double* row) const {
        if (let_go_ || bond_fresh_ || !touching_) return false;
        ParallelBondLaw::toRow(*this, estimates(), row);
        return true;
    }
    void fromLane(const double* row) {
        ParallelBondLaw::fromRow(row, *this);
        touching_ = true;
    }
    static bool laneStep(double* row, LaneFd& fd) { return ParallelBondLaw::laneStep(row, fd); }

    int32_t Version() const override { return 2; }
    double KnEstimate() const override {
        return linearKnEstimate() + (isBonded() ? kbn_ * dashpotStiffnessFactor(dp_nratio) : 0.0);
    }
    double KsEstimate() const override {
        return linearKsEstimate() + (isBonded() ? kbs_ * dashpotStiffnessFactor(dp_sratio) : 0.0);
    }
    /// Half period of the fastest undamped mode the contact has: normal kn + pb_kn A, shear
    /// 3 (ks + pb_ks A) (a disk's tangential mobility 3/m*, as linearContactDuration), and
    /// bending pb_kn I against the ends' rotational inertia, at least m* min(R)^2 / 2 for disks:
    /// an equivalent stiffness 2 pb_kn I / min(R)^2 (faster than the normal mode once pb_rmul
    /// exceeds about 1.2).
    double ContactDuration(double mass_eff, double) const override {
        const bool b = isBonded();
        const double kn_t = kn + (b ? kbn_ : 0.0);
        const double ks_t = ks + (b ? kbs_ : 0.0);
        const double kr_t = (b && r_min_ > 0.0) ? 2.0 * kbr_ / (r_min_ * r_min_) : 0.0;
        const double k = std::max({kn_t, 3.0 * ks_t, kr_t});
        return kn_t > 0.0 ? M_PI * std::sqrt(mass_eff / k) : HUGE_VAL;
    }
    bool OKToDelete() const override { return !isBonded(); }
    uint32_t Traits() const override { return kTraitThreadSafe | kTraitBond; }
};

ContactModel* createPrototype(int32_t index) { return index == 0 ? new PBond() : nullptr; }
void destroyPrototype(ContactModel* p) { delete static_cast<PBond*>(p); }

const PluginInfo kInfo = TALUS_PLUGIN_INFO_INIT("1.0.0", 1, createPrototype, destroyPrototype);

}  // namespace

TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }

// The lane law (docs/plugin-abi.md, "Lanes"): the steady step of the SDK's parallel bond on rows
// the host owns; same bits as FDlaw. The kernel id names that law for a host that runs it inline
// ("Kernels"); this engine does not (measured no faster than FDlaw,
// docs/results/benchmarks-history.md "Kernels: pbond") and ignores the id.
TALUS_PLUGIN_EXPORT const talus::LaneLaw* talus_plugin_lanes(int32_t index) {
    return index == 0 ? talus::sdk::laneLawOf<PBond>() : nullptr;
}
TALUS_PLUGIN_EXPORT const char* talus_plugin_kernel(int32_t index) {
    return index == 0 ? talus::sdk::ParallelBondLaw::kKernelId : nullptr;
}
