// SPDX-License-Identifier: MIT
//
// `cbond`: the linear contact model with a PFC contact bond (PFC2D's documentation; Potyondy
// & Cundall 2004; docs/models/cbond.md).
//
//   normal   F_n = kn (u_n - u_ref)          bonded: tension allowed
//            F_n = max(0, kn (u_n - u_ref))  unbonded (u_ref = 0 unless the bond formed at a gap)
//   shear    F_s <- F_s - ks dU_s            bonded: no slip
//            |F_s| <= fric F_n               unbonded: Coulomb slider (PFC's linear model)
//   bond     strengths are forces: cb_tenf (tensile), cb_shearf (shear)
//            -F_n >= cb_tenf       -> breaks in tension; both forces go to zero
//            |F_s| >= cb_shearf    -> breaks in shear; the forces are kept if F_n > 0 and
//                                     |F_s| <= fric F_n, else F_s is scaled to fric max(F_n, 0)
//                                     (and a tensile F_n goes to zero: no bond, no tension)
//
// Bond creation, two ways (docs/models/cbond.md, "Bonding"):
//  - m:bond{model = "cbond"} (the bond contract, docs/plugin-abi.md): the host writes
//    `bonded` = 1 and calls FDlaw with kFdFirstCall and the old contact's forces on entry (zero
//    with reset). The bond adopts them: u_ref = u_prev - F_n/kn, F_s kept, so the contact goes
//    on with the forces it had (or starts stress-free at its current overlap). Writing
//    `bonded` = 1 on a live contact does the same with the model's own forces; writing 0 removes
//    the bond without an event: the forces stay and the unbonded law takes over at the next
//    step. What that law cannot hold is released there (Energies, below).
//  - a rule with cb_bond = 1 bonds each contact it creates on the contact's first FDlaw, if the
//    ends touch or are within cb_gap; the activity distance is then cb_gap, so that the engine
//    creates contacts within the gap. A bond formed at a gap is force-free there: u_ref =
//    min(0, u_n at bonding). Not when the host sets kFdNoAutoBond: the bond of this pair broke
//    (or was removed) before, and a contact that re-forms after a break is not bonded again.
//
// Energies: strain = F_n^2/(2 kn) + F_s^2/(2 ks) (bonded or not). On a break:
//  - the strain reported on the breaking step is the value after the break (zero for a contact
//    left without force: a tension break, or a shear break under tension). The trial forces of
//    the breaking step were never applied: the bodies felt the last step's forces F_old and
//    then none, so the energy released is F_old F_trial / (2k) per spring (what closes the
//    leapfrog balance; zero for a bond made and broken in the same step), kEnergyReleased;
//  - a contact left in compression whose shear force is scaled to the Coulomb limit F_s' has
//    slipped: (F_trial - F_s') (F_old + F_s') / (2 ks) is slip work (trapezoidal, as the slider).
// On a removal (`bonded` written 0, m:unbond) the unbonded law decides at the next step: a
// contact in compression keeps its springs (a shear force beyond friction slips, booked as slip
// by the slider), so nothing is released; one whose normal spring is still at or beyond its
// rest length (tension, which only the bond held) loses both forces, and releases
// F_old F_trial / (2k) per spring, as a tension break between the steps would.
#include <algorithm>
#include <cmath>
#include <limits>

#include "talus/contact_model.hpp"
#include "talus/sdk/contact_bond_law.hpp"
#include "talus/sdk/corners.hpp"
#include "talus/sdk/dashpot.hpp"
#include "talus/sdk/model_base.hpp"
#include "talus/sdk/shear_spring.hpp"

namespace {

using namespace talus;
using namespace talus::sdk;

const char* const kBondFlag[] = {"no", "yes", nullptr};

/// a b / (2 k) [J]: with a = b the energy of a linear spring carrying that force.
double crossEnergy(double a, double b, double k) { return k > 0.0 ? 0.5 * a * b / k : 0.0; }
const char* const kStates[] = {"unbonded", "bonded", "broken_tension", "broken_shear", nullptr};
enum CbState { kUnbonded = 0, kBonded = 1, kBrokenTension = 2, kBrokenShear = 3 };

class CBond final : public ModelBase<CBond> {
public:
    static constexpr const char* kName = "cbond";

    // properties
    double kn = 0.0;         // [N/m]
    double ks = 0.0;         // [N/m]
    double fric = 0.0;       // [-]
    double cb_tenf = 0.0;    // tensile strength [N]
    double cb_shearf = 0.0;  // shear strength [N]
    double cb_bond = 0.0;    // 1: bond on the first FDlaw
    double cb_gap = 0.0;     // bonding gap [m]
    // state (read-only)
    double bonded = 0.0;    // 1 while bonded
    double cb_state = 0.0;  // CbState
    double cb_fn = 0.0;     // normal force [N]
    double cb_fs = 0.0;     // shear force [N]
    // per-contact bookkeeping
    double u_ref_ = 0.0;  // overlap at which the normal force is zero [m]
    bool started_ = false;
    bool touching_ = false;
    bool sliding_ = false;       // the slider slid at the last contact step
    bool adopt_ = false;         // `bonded` was written 1: bond at the next FDlaw
    double last_engaged_ = 0.0;  // u_n - u_ref at the last contact step [m]

    // One property per entry (clang-format would put every value on its own line).
    // clang-format off
    static const PropTable<CBond>& Table() {
        static const PropTable<CBond> t = {
            {{"kn", "N/m", kPropInheritable, 0.0, "normal stiffness", nullptr}, &CBond::kn, 0.0, kStiffnessMax},
            {{"ks", "N/m", kPropInheritable, 0.0, "shear stiffness", nullptr}, &CBond::ks, 0.0, kStiffnessMax},
            {{"fric", "-", kPropInheritable, 0.0, "friction coefficient", nullptr},
             &CBond::fric, 0.0},
            {{"cb_tenf", "N", 0, 0.0, "bond tensile strength (force; inf: unbreakable)", nullptr},
             &CBond::cb_tenf, 0.0},
            {{"cb_shearf", "N", 0, 0.0, "bond shear strength (force; inf: unbreakable)", nullptr},
             &CBond::cb_shearf, 0.0},
            {{"cb_bond", "-", kPropInteger, 0.0, "1: bond each new contact on its first FDlaw",
              kBondFlag},
             &CBond::cb_bond, 0.0, 1.0},
            {{"cb_gap", "m", 0, 0.0, "largest gap at which a contact is bonded", nullptr},
             &CBond::cb_gap, 0.0},
            {{"bonded", "-", kPropState | kPropInteger, 0.0,
              "1 while bonded; write 1 to bond at the current forces, 0 to unbond", kBondFlag},
             &CBond::bonded, 0.0, 1.0},
            {{"cb_state", "-", kPropReadOnly | kPropState | kPropInteger, 0.0, "bond state",
              kStates},
             &CBond::cb_state},
            {{"cb_fn", "N", kPropReadOnly | kPropState, 0.0, "normal force", nullptr},
             &CBond::cb_fn},
            {{"cb_fs", "N", kPropReadOnly | kPropState, 0.0, "shear force", nullptr},
             &CBond::cb_fs},
        };
        return t;
    }
    // clang-format on

    int32_t AcceptProp(int32_t index, double value) override {
        // Strengths may be infinite (an unbreakable bond); stiffnesses, friction and gap not.
        const auto& t = Table();
        if (index >= 0 && index < PropCount() && std::isinf(value)) {
            const auto member = t[static_cast<std::size_t>(index)].member;
            if (member != &CBond::cb_tenf && member != &CBond::cb_shearf)
                return fail(std::string("cbond: '") + t[static_cast<std::size_t>(index)].info.name +
                            "' must be finite");
        }
        const bool bond_flag = index >= 0 && index < PropCount() &&
                               t[static_cast<std::size_t>(index)].member == &CBond::bonded;
        if (const int32_t r = ModelBase<CBond>::AcceptProp(index, value); r != 0 || !bond_flag)
            return r;
        // The bond contract: 1 bonds at the next FDlaw (adopting the forces), 0 unbonds
        // without an event (the next FDlaw releases what the unbonded law cannot hold). Either
        // way the user decided: the cb_bond rule no longer applies.
        started_ = true;
        adopt_ = bonded == 1.0;
        cb_state = bonded == 1.0 ? kBonded : kUnbonded;
        return 0;
    }

    bool inherit(const PropBlock& pb) {
        kn = inheritSeries(kn, pb.kn);
        ks = inheritSeries(ks, pb.ks);
        fric = inheritMin(fric, pb.fric);
        return true;
    }

    void fdlaw(FdBlock& fd) {
        // A contact that touched at its last step and goes on touching, bonded or not, takes
        // the SDK's steady step (talus/sdk/contact_bond_law.hpp: also the lane law's and the
        // host's kernel); everything else is below.
        if (!adopt_ && started_ && touching_ && ContactBondLaw::steadyStep(*this, fd)) return;
        const double u = fd.u_n;
        if (adopt_) {
            // Bonded by the host (or a write of `bonded` = 1): go on with the forces of the last
            // step, the entry forces at a first call (the replaced contact's, zero after a
            // reset), else this object's own. u_ref puts F_n at the previous overlap u - du_n.
            adopt_ = false;
            const bool first = (fd.flags & kFdFirstCall) != 0;
            const double fn0 = first ? fd.n_force : cb_fn;
            cb_fs = first ? fd.s_force : cb_fs;
            u_ref_ = (u - fd.du_n) - (kn > 0.0 ? fn0 / kn : 0.0);
            cb_fn = kn > 0.0 ? fn0 : 0.0;
            touching_ = true;  // the springs are engaged: the whole shear increment loads
        }
        if (!started_) {
            started_ = true;
            if (cb_bond == 1.0 && u >= -cb_gap && !(fd.flags & kFdNoAutoBond)) {
                bonded = 1.0;
                cb_state = kBonded;
                u_ref_ = std::min(u, 0.0);  // force-free at the bonding gap
            }
        }
        const bool energy = (fd.flags & kFdEnergyOn) != 0;
        double slip_work = 0.0, released = 0.0;
        Corners corner;

        // Only the part of the first step after the spring engaged loads the shear spring: a
        // bond engages at the activity distance, an unbonded contact at u_n = u_ref.
        const double engaged = bonded == 1.0 ? u + ActivityDistance() : u - u_ref_;
        const double du_s = touching_ ? fd.du_s : fd.du_s * onsetFraction(engaged, fd.du_n);

        if (bonded == 1.0) {
            const bool touching_prev = touching_;
            touching_ = true;
            // The forces of the last step: what the springs held and the bodies felt.
            const double fn_old = cb_fn, fs_old = cb_fs;
            const bool first = !touching_prev;
            cb_fn = kn * (u - u_ref_);
            cb_fs -= ks * du_s;  // no slip while bonded
            // A bond made at touch (cb_gap = 0) engages inside the step, as an unbonded
            // contact does: the same onset corner (stress seed 2800).
            if (first && u - u_ref_ > 0.0)
                corner = linearOnsetCorners(kn, ks, fric, cb_fs, false, fd,
                                            onsetFraction(u - u_ref_, fd.du_n));
            const bool tension = cb_fn < 0.0 && -cb_fn >= cb_tenf;
            const bool shear = !tension && std::fabs(cb_fs) > 0.0 && std::fabs(cb_fs) >= cb_shearf;
            if (tension || shear) {
                bonded = 0.0;
                cb_state = tension ? kBrokenTension : kBrokenShear;
                fd.flags |= kFdBroken;
                fd.break_mode = tension ? kBreakTension : kBreakShear;
                if (cb_fn <= 0.0) {
                    // Nothing holds the ends together any more: both forces go (PFC rule for
                    // tension; a shear break under tension leaves no compression either).
                    // The trial forces were never applied, so their energy was never stored:
                    // the bodies felt F_old up to this step and nothing from it on. Released
                    // is what closes the leapfrog balance (docs/models/cbond.md, Energies):
                    // F_old^2/2k minus the work F_old/2 du the spring still took over the
                    // first half of this step, = F_old F_trial / 2k; zero for a bond made and
                    // broken in the same step (F_old = 0).
                    if (fn_old > 0.0) {
                        // The spring went from compression through zero to beyond the
                        // strength inside this step (a stiff bond, a weak one, or a coarse
                        // step). It is a separation at the zero crossing, as the unbonded
                        // branch treats it: the closing corner is owed, and what the bond
                        // held in tension, at most k du^2/2, is second order and not booked.
                        // F_old F_trial / 2k would book a negative release here, energy the
                        // bodies never received (stress seed 2800: 10% of the throughput).
                        corner =
                            linearClosingCorners(kn, ks, fric, fs_old, false, fd,
                                                 closingFraction(last_engaged_, u - u_ref_), true);
                        released = springEnergy(fs_old, ks) - (0.5 * fs_old + corner.shear) * du_s;
                    } else {
                        released = crossEnergy(fn_old, cb_fn, kn) + crossEnergy(fs_old, cb_fs, ks);
                    }
                    cb_fn = 0.0;
                    cb_fs = 0.0;
                } else if (std::fabs(cb_fs) > fric * cb_fn) {
                    // Shear break in compression beyond friction: slip to the Coulomb limit.
                    // The slider's work over the step, trapezoidal as the SDK's slider
                    // (shear_spring.hpp): mean force (F_old + F') / 2 times the slip
                    // (F_trial - F') / ks.
                    const double limited = std::copysign(fric * cb_fn, cb_fs);
                    slip_work = std::max(0.0, crossEnergy(cb_fs - limited, fs_old + limited, ks));
                    cb_fs = limited;
                }
            }
            last_engaged_ = u - u_ref_;
            if (bonded == 0.0) touching_ = cb_fn > 0.0;
        } else if (touching_ && last_engaged_ <= 0.0 && u - u_ref_ <= 0.0) {
            // The bond was removed (`bonded` written 0) while it held the ends at or beyond the
            // normal spring's rest length: only a bond keeps touching_ with last_engaged_ <= 0
            // (an unbonded contact step has u - u_ref > 0, and a break keeps touching_ only in
            // compression). The unbonded law holds no tension, so both forces go, as at a
            // tension break: the bodies felt the last step's forces for half a step after it
            // and nothing since, so the release is F_old F_trial / (2k) per spring, with no
            // corner (the scheme applied that force up to its window's end and stops it there).
            // A contact compressed again by now goes on by the unbonded branch below, its
            // normal spring continuous through zero; one that was in compression at the last
            // step is the ordinary unbonded law's (kept, or separating with its corners).
            released = crossEnergy(cb_fn, kn * (u - u_ref_), kn) +
                       crossEnergy(cb_fs, cb_fs - ks * du_s, ks);
            cb_fn = 0.0;
            cb_fs = 0.0;
            touching_ = false;
            sliding_ = false;
        } else if (u - u_ref_ > 0.0) {
            // Unbonded: the linear law without tension (PFC's linear model), with the
            // corner impulses at touch (talus/sdk/corners.hpp).
            const bool first = !touching_;
            cb_fn = kn * (u - u_ref_);
            const ShearResult sr = updateShearSpring(cb_fs, ks, du_s, fric * cb_fn);
            slip_work = sr.slip_work;
            sliding_ = sr.sliding;
            if (sr.sliding) fd.flags |= kFdSliding;
            if (first)
                corner = linearOnsetCorners(kn, ks, fric, cb_fs, sr.sliding, fd,
                                            onsetFraction(u - u_ref_, fd.du_n));
            touching_ = true;
            last_engaged_ = u - u_ref_;
        } else {
            // Separated: the corner impulses still owed for the last contact step.
            if (touching_)
                corner = linearClosingCorners(kn, ks, fric, cb_fs, sliding_, fd,
                                              closingFraction(last_engaged_, u - u_ref_), true);
            cb_fn = 0.0;
            // The slider lets go as F_n vanishes: the shear spring's energy at the last contact
            // step, less the work its force still did on the bodies after that step (F_old for
            // the half step left of its window, then the corner impulse, over this step's
            // du_s; the bodies gain F_s du_s). Booking all of F_old^2/2ks as slip counted that
            // work twice: a contact unloading in shear as it separates created energy (1% of
            // a sliding impact's energy).
            slip_work =
                std::max(0.0, springEnergy(cb_fs, ks) - (0.5 * cb_fs + corner.shear) * du_s);
            cb_fs = 0.0;
            touching_ = false;
            sliding_ = false;
        }

        fd.n_force = cb_fn + corner.normal;
        fd.s_force = cb_fs + corner.shear;
        fd.moment = 0.0;
        fd.knest = kn;
        fd.ksest = ks;
        fd.krest = 0.0;
        if (bonded == 1.0) fd.flags |= kFdBonded | kFdKeep;
        if (energy) {
            fd.energy[kEnergyStrain] = springEnergy(cb_fn, kn) + springEnergy(cb_fs, ks);
            fd.energy[kEnergySlip] = slip_work;
            fd.energy[kEnergyReleased] = released;
        }
    }

    void saveRestoreState(ModelSaveObject& so) {
        so.Double(bonded);
        so.Double(cb_state);
        so.Double(cb_fn);
        so.Double(cb_fs);
        so.Double(u_ref_);
        so.Bool(started_);
        so.Bool(touching_);
        so.Bool(sliding_);
        so.Double(last_engaged_);
        if (so.IsSaving() || so.DataVersion() >= 3) so.Bool(adopt_);
    }

    int32_t Version() const override { return 3; }
    /// Version 3 made `bonded` settable, so it is among the saved properties; a version-2
    /// stream has the properties without it (bonded comes with the state, as before).
    void SaveRestore(ModelSaveObject& so) override {
        if (so.IsSaving() || so.DataVersion() >= 3) return ModelBase<CBond>::SaveRestore(so);
        for (const auto& p : Table())
            if (!(p.info.flags & kPropReadOnly) && p.member != &CBond::bonded)
                so.Double(this->*(p.member));
        saveRestoreState(so);
    }
    // Lanes (sdk/lanes.hpp): the steady step's values in a row (ContactBondLaw's layout).
    static constexpr int kLaneStateSize = ContactBondLaw::kLaneStateSize;
    static const char* const* laneStateNames() { return ContactBondLaw::laneStateNames(); }
    bool toLane(double* row) const {
        if (adopt_ || !started_ || !touching_) return false;
        ContactBondLaw::toRow({kn, ks, fric, cb_tenf, cb_shearf, bonded, u_ref_, cb_fn, cb_fs,
                               last_engaged_, sliding_},
                              row);
        return true;
    }
    void fromLane(const double* row) {
        // (the rest never changes in the lanes: a write of a property takes the contact out)
        cb_fn = row[7], cb_fs = row[8], last_engaged_ = row[9], sliding_ = row[10] != 0.0;
    }
    static bool laneStep(double* row, LaneFd& fd) { return ContactBondLaw::laneStep(row, fd); }

    double KnEstimate() const override { return kn; }
    double KsEstimate() const override { return ks; }
    double ContactDuration(double mass_eff, double) const override {
        return kn > 0.0 ? M_PI * std::sqrt(mass_eff / kn) : HUGE_VAL;
    }
    /// Contacts within the bonding gap must exist for the first FDlaw to bond them.
    double ActivityDistance() const override { return cb_bond == 1.0 ? cb_gap : 0.0; }
    bool OKToDelete() const override { return bonded != 1.0; }
    uint32_t Traits() const override { return kTraitThreadSafe | kTraitBond; }
};

ContactModel* createPrototype(int32_t index) { return index == 0 ? new CBond() : nullptr; }
void destroyPrototype(ContactModel* p) { delete static_cast<CBond*>(p); }

const PluginInfo kInfo = TALUS_PLUGIN_INFO_INIT("1.0.0", 1, createPrototype, destroyPrototype);

}  // namespace

TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }

// The lane law and the kernel (docs/plugin-abi.md, "Lanes", "Kernels"): the steady step of the
// SDK's contact bond on rows the host owns; same bits as FDlaw.
TALUS_PLUGIN_EXPORT const talus::LaneLaw* talus_plugin_lanes(int32_t index) {
    return index == 0 ? talus::sdk::laneLawOf<CBond>() : nullptr;
}
TALUS_PLUGIN_EXPORT const char* talus_plugin_kernel(int32_t index) {
    return index == 0 ? talus::sdk::ContactBondLaw::kKernelId : nullptr;
}
