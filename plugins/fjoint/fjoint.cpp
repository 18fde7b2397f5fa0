// SPDX-License-Identifier: MIT
//
// `fjoint`: the flat-joint contact model of Potyondy (2012) in 2D (docs/models/fjoint.md).
//
// The contact is a straight interface of half-length R = fj_rmul min(R_A, R_B) (ball-wall: the
// ball's R), centred at the contact point, perpendicular to the contact normal n, of thickness
// t = 1, divided into N = fj_nr equal elements of length L = 2R/N, centred at
//   x_e = -R + (e + 1/2) L   (e = 0 .. N-1, along t = (-n_y, n_x)).
//
// Kinematics (docs/models/fjoint.md, "Kinematics"): the interface accumulates its normal
// displacement d (closing +, the overlap increments du_n) and the relative rotation theta of the
// ends (dtheta, end 2 minus end 1) since it was installed. A point of the interface at x closes by
//   delta(x) = d + x theta
// (a counter-clockwise turn of end 2 closes the side x > 0). Rotation moves no point of the
// interface along t, so every element has the same shear displacement increment du_s.
//
// Normal law (a Winkler layer of stiffness fj_kn per unit area, integrated over each element):
//   bonded element:   F_e = kn L delta(x_e),   M_e = -kn (L^3/12) theta   (tension and compression)
//   unbonded element: the same integrals over the part of the element where delta > 0 only
//                     (no tension; an element can be partly open)
// F_e is compression +, M_e the element's moment about its own centre on end 2. The interface:
//   F_n = sum F_e,   M = sum (-x_e F_e + M_e)   (moment on end 2 about the contact point).
// Shear law, per element, incremental: F_s,e <- F_s,e - ks L du_s; an unbonded element slides at
// |F_s,e| <= fj_fric max(F_e, 0) (so an open element carries no shear); F_s = sum F_s,e.
//
// Breakage of a bonded element, on its centroid stresses at this step's displacement (PFC's
// element stresses; tension checked first):
//   sigma_e = -F_e / L (tension +),  tau_e = |F_s,e| / L
//   tension: sigma_e > 0 and sigma_e >= fj_ten                                  -> state 1
//   shear:   tau_e > 0 and tau_e >= fj_coh - min(sigma_e, fj_ten) tan(fj_fa)     -> state 2
// A broken element is unbonded from that step on (partial damage: the others carry on).
//
// Energies: bonded elements' strain energy -> bond, unbonded elements' -> strain (both the exact
// integral of the law: (kn/2) int delta^2 + F_s,e^2 / (2 ks L)); slip: the slider's trapezoidal
// work minus the change of its spring's energy; released: for an element that breaks (or is
// unbonded by writing `bonded` = 0) what it held at the last step plus the trapezoidal work of
// this step's forces minus what it holds now (pbond's F_old F_trial / 2k for a spring that
// breaks in tension: docs/models/pbond.md, Energies).
//
// Corners (talus/sdk/corners.hpp, as `linear`): an interface without bonded elements that closes
// or opens flat within a step (all its elements at once: a fresh touch, or a face lifting off
// square) is a linear spring kn 2R switched on or off inside the step; it pays `linear`'s onset
// and closing corner impulses, so that impacts of unbonded interfaces are as accurate as
// `linear`'s. An interface rocking on or off its edge loads and unloads smoothly: no corner.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "talus/contact_model.hpp"
#include "talus/sdk/corners.hpp"
#include "talus/sdk/dashpot.hpp"
#include "talus/sdk/model_base.hpp"

namespace {

using namespace talus;
using namespace talus::sdk;

constexpr int kMaxElements = 16;
const char* const kBondFlag[] = {"no", "yes", nullptr};
// Element states: pbond's pb_state numbering, per element.
const char* const kStates[] = {"unbonded", "broken_tension", "broken_shear", "bonded", nullptr};
enum ElemState : int32_t { kUnbonded = 0, kBrokenTension = 1, kBrokenShear = 2, kBonded = 3 };
// What writing `bonded` = 1 installs.
const char* const kMtypes[] = {"bonded", "unbonded", "slit", nullptr};
enum Mtype { kMtypeBonded = 0, kMtypeUnbonded = 1, kMtypeSlit = 2 };

/// Normal force (compression +), moment about the element's centre on end 2, and the strain
/// energy of the normal springs of one element. (No initialisers: fdlaw's arrays of them are
/// written before they are read, and zeroing kMaxElements of them per call cost more than the
/// law of two elements.)
struct Normal {
    double f, m, energy;
};

class FJoint final : public ModelBase<FJoint> {
public:
    static constexpr const char* kName = "fjoint";

    // ---- settable properties (PFC names)
    double fj_kn = 0.0;      // normal stiffness [Pa/m]
    double fj_ks = 0.0;      // shear stiffness [Pa/m]
    double fj_emod = 0.0;    // effective modulus [Pa]; > 0: fj_kn = fj_emod / (R_A + R_B)
    double fj_kratio = 0.0;  // fj_kn / fj_ks with fj_emod [-]
    double fj_nr = 2.0;      // number of elements [-]
    double fj_rmul = 1.0;    // radius multiplier [-]
    double fj_ten = 0.0;     // tensile strength [Pa]
    double fj_coh = 0.0;     // cohesion [Pa]
    double fj_fa = 0.0;      // friction angle of the bonded material [deg]
    double fj_fric = 0.0;    // friction coefficient of unbonded elements [-]
    double fj_gap0 = 0.0;    // installation gap of a slit interface [m]
    double fj_mtype = 0.0;   // what `bonded` = 1 installs: 0 bonded, 1 unbonded, 2 slit
    double bonded = 0.0;     // 1 while an element is bonded; write 1 to install, 0 to unbond
    double fj_elem = 1.0;    // the element the per-element properties read (1 .. fj_nr)
    // ---- read-only state and geometry
    double fj_nbond = 0.0;   // bonded elements
    double fj_radius = 0.0;  // R [m]
    double fj_area = 0.0;    // element area L t [m^2]
    double fj_gap = 0.0;     // surface gap at the interface's centre, -d [m]
    double fj_relbr = 0.0;   // relative rotation since installation, theta [rad]
    double fj_fn = 0.0;      // interface normal force, compression + [N]
    double fj_fs = 0.0;      // interface shear force [N]
    double fj_m = 0.0;       // interface moment on end 2 [N m]
    // per-element readouts of element fj_elem (computed in ReturnProp; members for the table)
    double fj_state = 0.0, fj_sigma = 0.0, fj_tau = 0.0, fj_shear = 0.0, fj_egap = 0.0,
           fj_slip = 0.0;

    // ---- per-contact state
    double r_min_ = 0.0, r_sum_ = 0.0;  // min(R_A, R_B), R_A + R_B (ball-wall: R, R) [m]
    double d_ = 0.0;                    // normal displacement of the centre, closing + [m]
    double theta_ = 0.0;                // relative rotation since installation [rad]
    double keep_gap_ = 0.0;             // an unbonded interface is kept while within it [m]
    int32_t state_[kMaxElements] = {};
    double fs_[kMaxElements] = {};  // element shear forces on end 2 along t [N]
    bool slip_[kMaxElements] = {};  // element slid at the last step
    int32_t unbond_mask_ = 0;       // elements unbonded by a write since the last step
    bool install_pending_ = false;  // `bonded` = 1 written: install at the next FDlaw
    bool started_ = false;          // had its first FDlaw
    bool keep_ = false;             // the last FDlaw asked to keep the contact
    // ---- derived (refresh)
    int n_ = 2;
    double len_ = 0.0, ielem_ = 0.0;  // element length L and L^3/12 (t = 1)
    double tan_fa_ = 0.0;             // tan(fj_fa): the shear strength's slope, read every step
    // A whole element's integrals of 1, s, s^2 over s in [-L/2, L/2] (normal(): a bonded
    // element's, every step)
    double w1_ = 0.0, w2_ = 0.0, w3_ = 0.0;

    // One property per entry (clang-format would put every value on its own line).
    // clang-format off
    static const PropTable<FJoint>& Table() {
        static const PropTable<FJoint> t = {
            {{"fj_kn", "Pa/m", 0, 0.0, "normal stiffness (stress/displacement)", nullptr},
             &FJoint::fj_kn, 0.0, kStiffnessMax},
            {{"fj_ks", "Pa/m", 0, 0.0, "shear stiffness (stress/displacement)", nullptr},
             &FJoint::fj_ks, 0.0, kStiffnessMax},
            {{"fj_emod", "Pa", 0, 0.0, "effective modulus (> 0: fj_kn = fj_emod/(R_A+R_B))", nullptr},
             &FJoint::fj_emod, 0.0, kStiffnessMax},
            {{"fj_kratio", "-", 0, 0.0, "fj_kn/fj_ks with fj_emod", nullptr}, &FJoint::fj_kratio, 0.0},
            {{"fj_nr", "-", kPropInteger, 2.0, "number of elements across the interface", nullptr},
             &FJoint::fj_nr, 1.0, double(kMaxElements)},
            {{"fj_rmul", "-", 0, 1.0, "radius multiplier", nullptr}, &FJoint::fj_rmul, 0.0, 1e6, true},
            {{"fj_ten", "Pa", 0, 0.0, "tensile strength (inf: unbreakable in tension)", nullptr},
             &FJoint::fj_ten, 0.0},
            {{"fj_coh", "Pa", 0, 0.0, "cohesion (inf: unbreakable in shear)", nullptr}, &FJoint::fj_coh, 0.0},
            {{"fj_fa", "deg", 0, 0.0, "friction angle of the bonded material", nullptr}, &FJoint::fj_fa, 0.0, 89.0},
            {{"fj_fric", "-", 0, 0.0, "friction coefficient of unbonded elements", nullptr}, &FJoint::fj_fric, 0.0},
            {{"fj_gap0", "m", 0, 0.0, "installation gap of a slit interface", nullptr}, &FJoint::fj_gap0, 0.0},
            {{"fj_mtype", "-", kPropInteger, 0.0, "what bonded = 1 installs", kMtypes}, &FJoint::fj_mtype, 0.0, 2.0},
            {{"bonded", "-", kPropInteger | kPropState, 0.0,
              "1 while an element is bonded (set 1 to install, 0 to unbond)", kBondFlag},
             &FJoint::bonded, 0.0, 1.0},
            {{"fj_elem", "-", kPropInteger | kPropState, 1.0, "element read by fj_state ... fj_slip", nullptr},
             &FJoint::fj_elem, 1.0, double(kMaxElements)},
            {{"fj_nbond", "-", kPropReadOnly | kPropState | kPropInteger, 0.0, "bonded elements", nullptr},
             &FJoint::fj_nbond},
            {{"fj_radius", "m", kPropReadOnly | kPropState, 0.0, "interface half-length R", nullptr},
             &FJoint::fj_radius},
            {{"fj_area", "m^2", kPropReadOnly | kPropState, 0.0, "element area", nullptr}, &FJoint::fj_area},
            {{"fj_gap", "m", kPropReadOnly | kPropState, 0.0, "surface gap at the centre (open +)", nullptr},
             &FJoint::fj_gap},
            {{"fj_relbr", "rad", kPropReadOnly | kPropState, 0.0, "relative rotation since installation", nullptr},
             &FJoint::fj_relbr},
            {{"fj_fn", "N", kPropReadOnly | kPropState, 0.0, "interface normal force (compression +)", nullptr},
             &FJoint::fj_fn},
            {{"fj_fs", "N", kPropReadOnly | kPropState, 0.0, "interface shear force", nullptr}, &FJoint::fj_fs},
            {{"fj_m", "N m", kPropReadOnly | kPropState, 0.0, "interface moment on end 2", nullptr}, &FJoint::fj_m},
            {{"fj_state", "-", kPropReadOnly | kPropState | kPropInteger, 0.0, "state of element fj_elem", kStates},
             &FJoint::fj_state},
            {{"fj_sigma", "Pa", kPropReadOnly | kPropState, 0.0, "normal stress at element centre (tension +)", nullptr},
             &FJoint::fj_sigma},
            {{"fj_tau", "Pa", kPropReadOnly | kPropState, 0.0, "shear stress of element fj_elem", nullptr},
             &FJoint::fj_tau},
            {{"fj_shear", "Pa", kPropReadOnly | kPropState, 0.0,
              "shear strength of element fj_elem (bonded: cohesive; unbonded: friction)", nullptr},
             &FJoint::fj_shear},
            {{"fj_egap", "m", kPropReadOnly | kPropState, 0.0, "gap at the centre of element fj_elem (open +)", nullptr},
             &FJoint::fj_egap},
            {{"fj_slip", "-", kPropReadOnly | kPropState | kPropInteger, 0.0, "1: element fj_elem slid", nullptr},
             &FJoint::fj_slip},
        };
        return t;
    }
    // clang-format on

    // ------------------------------------------------------------------ properties

    double ReturnProp(int32_t index) const override {
        if (index < 0 || index >= PropCount()) return kUnset;
        const auto member = Table()[static_cast<std::size_t>(index)].member;
        const bool per_element = member == &FJoint::fj_state || member == &FJoint::fj_sigma ||
                                 member == &FJoint::fj_tau || member == &FJoint::fj_shear ||
                                 member == &FJoint::fj_egap || member == &FJoint::fj_slip;
        if (!per_element) return ModelBase<FJoint>::ReturnProp(index);
        const int e = static_cast<int>(fj_elem) - 1;
        if (e < 0 || e >= n_) return kUnset;
        if (member == &FJoint::fj_state) return state_[e];
        if (member == &FJoint::fj_slip) return slip_[e] ? 1.0 : 0.0;
        if (member == &FJoint::fj_egap) return -(d_ + centre(e) * theta_);
        const double area = len_;
        const double fn = normal(e, state_[e] == kBonded, d_, theta_).f;
        if (member == &FJoint::fj_sigma) return area > 0.0 ? -fn / area : 0.0;
        if (member == &FJoint::fj_tau) return area > 0.0 ? std::fabs(fs_[e]) / area : 0.0;
        // fj_shear
        if (state_[e] == kBonded) return shearStrength(area > 0.0 ? -fn / area : 0.0);
        return area > 0.0 ? fj_fric * std::max(fn, 0.0) / area : 0.0;
    }

    int32_t AcceptProp(int32_t index, double value) override {
        if (index < 0 || index >= PropCount()) return ModelBase<FJoint>::AcceptProp(index, value);
        const auto& spec = Table()[static_cast<std::size_t>(index)];
        // Strengths may be infinite (an unbreakable interface); nothing else may.
        if (std::isinf(value) && spec.member != &FJoint::fj_ten && spec.member != &FJoint::fj_coh)
            return fail(std::string("fjoint: '") + spec.info.name + "' must be finite (got " +
                        (value > 0 ? "inf" : "-inf") + ")");
        if (spec.member == &FJoint::fj_nr && started_ && value != fj_nr)
            return fail(
                "fjoint: 'fj_nr' cannot change on an installed interface (its elements hold "
                "state); set it in the rule or in m:bond's props");
        if (spec.member == &FJoint::fj_elem && started_ && value > fj_nr && std::isfinite(value))
            return fail("fjoint: 'fj_elem' must be <= fj_nr = " + std::to_string(n_) + " (got " +
                        std::to_string(static_cast<long long>(value)) + ")");
        if (spec.member != &FJoint::bonded) return ModelBase<FJoint>::AcceptProp(index, value);
        if (const int32_t rc = ModelBase<FJoint>::AcceptProp(index, value)) return rc;
        if (value == 1.0) {
            // (Re)install at the next FDlaw, at the geometry of that call (fj_mtype says how).
            install_pending_ = true;
        } else {
            // Unbond every element (m:unbond): no event. The bodies still feel the elements'
            // last forces for half a step, so what they let go is booked at the next FDlaw
            // (released), once that step's motion is known.
            install_pending_ = false;
            for (int e = 0; e < n_; ++e)
                if (state_[e] == kBonded) {
                    state_[e] = kUnbonded;
                    unbond_mask_ |= int32_t(1) << e;
                }
            fj_nbond = 0.0;
        }
        return 0;
    }

    const char* PreCycle(const PropBlock& pb) override {
        if (const char* why = ModelBase<FJoint>::PreCycle(pb)) return why;
        if (fj_emod > 0.0 && !(fj_kratio > 0.0))
            errorText() =
                "fjoint: 'fj_kratio' must be > 0 when 'fj_emod' is set (fj_ks = fj_kn/fj_kratio)";
        else if (fj_elem > fj_nr)
            errorText() = "fjoint: 'fj_elem' (" + std::to_string(int(fj_elem)) +
                          ") must be <= 'fj_nr' (" + std::to_string(int(fj_nr)) + ")";
        else
            return nullptr;
        return errorText().c_str();
    }

    bool inherit(const PropBlock& pb) {
        const bool wall = pb.end2_type == kEndWall || !(pb.radius[1] > 0.0);
        r_min_ = wall ? pb.radius[0] : std::min(pb.radius[0], pb.radius[1]);
        r_sum_ = wall ? pb.radius[0] : pb.radius[0] + pb.radius[1];
        refresh();
        return true;
    }
    void onPropChanged() { refresh(); }

    /// Stiffnesses from the deformability form, and the interface's geometry.
    void refresh() {
        if (r_min_ > 0.0 && r_sum_ > 0.0) {
            // As pbond's pb_kn = pb_emod / L (Potyondy & Cundall 2004), L = R_A + R_B.
            if (fj_emod > 0.0 && fj_kratio > 0.0) {
                fj_kn = fj_emod / r_sum_;
                fj_ks = fj_kn / fj_kratio;
            }
            fj_radius = fj_rmul * r_min_;
        }
        n_ = std::clamp(static_cast<int>(fj_nr), 1, kMaxElements);
        len_ = 2.0 * fj_radius / n_;
        ielem_ = len_ * len_ * len_ / 12.0;
        fj_area = len_;
        tan_fa_ = std::tan(fj_fa * M_PI / 180.0);
        elementWidths(-0.5 * len_, 0.5 * len_, w1_, w2_, w3_);
    }

    // ------------------------------------------------------------------ the element law

    double centre(int e) const { return -fj_radius + (e + 0.5) * len_; }

    /// The integrals of 1, s and s^2 over [lo, hi].
    static void elementWidths(double lo, double hi, double& w1, double& w2, double& w3) {
        w1 = hi - lo;
        w2 = 0.5 * (hi * hi - lo * lo);
        w3 = (hi * hi * hi - lo * lo * lo) / 3.0;
    }

    /// Normal force, moment and strain energy of element e with the interface at (d, theta).
    /// Bonded: the whole element; unbonded: only its part where delta = d + x theta > 0.
    Normal normal(int e, bool is_bonded, double d, double theta) const {
        Normal out{};
        const double dc = d + centre(e) * theta;  // delta at the element's centre
        // delta(s) = dc + s theta over [lo, hi], s = x - x_e: the whole element when bonded
        double w1 = w1_, w2 = w2_, w3 = w3_;
        if (!is_bonded) {
            double lo = -0.5 * len_, hi = 0.5 * len_;
            if (theta == 0.0) {
                if (!(dc > 0.0)) return out;
            } else {
                const double s0 = -dc / theta;  // where delta = 0
                if (theta > 0.0)
                    lo = std::max(lo, s0);
                else
                    hi = std::min(hi, s0);
                if (!(hi > lo)) return out;
            }
            elementWidths(lo, hi, w1, w2, w3);
        }
        out.f = fj_kn * (dc * w1 + theta * w2);
        out.m = -fj_kn * (dc * w2 + theta * w3);
        out.energy = 0.5 * fj_kn * (dc * dc * w1 + 2.0 * dc * theta * w2 + theta * theta * w3);
        return out;
    }

    double shearSpringEnergy(double f) const {
        const double k = fj_ks * len_;
        return k > 0.0 ? 0.5 * f * f / k : 0.0;
    }

    /// Shear strength of a bonded element at centroid normal stress sigma (tension +):
    /// fj_coh - sigma tan(fj_fa), sigma capped at fj_ten (PFC's Mohr-Coulomb envelope with its
    /// tensile cut-off, as pbond).
    double shearStrength(double sigma) const {
        if (fj_fa == 0.0) return fj_coh;
        return fj_coh - std::min(sigma, fj_ten) * tan_fa_;
    }

    /// Coulomb slider of an unbonded element: the trial force capped at fj_fric max(F_e, 0).
    double capped(double trial, double fn) const {
        const double limit = fj_fric * std::max(fn, 0.0);
        return std::fabs(trial) > limit ? std::copysign(limit, trial) : trial;
    }

    /// Trapezoidal work the bodies did on element e over this step [J]: its forces of the last
    /// step (o, fs_o) and of this one (n, fs_n) over the step's displacements at its centre.
    double work(int e, const Normal& o, const Normal& n, double fs_o, double fs_n, double du_n,
                double du_s, double dtheta) const {
        return 0.5 * ((o.f + n.f) * (du_n + centre(e) * dtheta) - (o.m + n.m) * dtheta -
                      (fs_o + fs_n) * du_s);
    }

    /// Installs the interface at the current geometry (`bonded` = 1 written): fj_mtype 0 bonded
    /// and 1 unbonded adopt the entry forces (the old contact's, or this contact's last ones),
    /// spread evenly over the elements (unbonded: compression only, shear within friction);
    /// 2 slit: unbonded, force-free and open by fj_gap0.
    void install(double fn_entry, double fs_entry) {
        const int mt = static_cast<int>(fj_mtype);
        theta_ = 0.0;
        unbond_mask_ = 0;
        const double k_area = fj_kn * 2.0 * fj_radius;
        if (mt == kMtypeSlit) {
            d_ = -fj_gap0;
            keep_gap_ = 2.0 * fj_gap0;
            for (int e = 0; e < n_; ++e) state_[e] = kUnbonded, fs_[e] = 0.0;
        } else {
            const double fn = mt == kMtypeBonded ? fn_entry : std::max(fn_entry, 0.0);
            d_ = k_area > 0.0 ? fn / k_area : 0.0;
            keep_gap_ = 0.0;
            for (int e = 0; e < n_; ++e) {
                state_[e] = mt == kMtypeBonded ? kBonded : kUnbonded;
                fs_[e] = fs_entry / n_;
                if (mt != kMtypeBonded) fs_[e] = capped(fs_[e], k_area > 0.0 ? fn / n_ : 0.0);
            }
        }
        for (int e = 0; e < n_; ++e) slip_[e] = false;
    }

    /// Where on the straight path from the element's last-step state (sigma_o, fs_o) to its
    /// trial state (sigma_t, fs_t) the failure criterion of the break's mode is first met; its
    /// stresses there (the bond_break event's sigma and tau). Bisection to rounding (breaks are
    /// rare).
    void failureStresses(double sigma_o, double sigma_t, double fs_o, double fs_t, bool tension,
                         double& sigma, double& tau) const {
        const auto failed = [&](double g, double& s, double& t) {
            s = sigma_o + g * (sigma_t - sigma_o);
            t = len_ > 0.0 ? std::fabs(fs_o + g * (fs_t - fs_o)) / len_ : 0.0;
            return tension ? s > 0.0 && s >= fj_ten : t > 0.0 && t >= shearStrength(s);
        };
        double lo = 0.0, hi = 1.0, s = 0.0, t = 0.0;
        if (failed(0.0, s, t)) hi = 0.0;
        for (int it = 0; it < 60 && hi > 0.0; ++it) {
            const double mid = 0.5 * (lo + hi);
            (failed(mid, s, t) ? hi : lo) = mid;
        }
        failed(hi, sigma, tau);
    }

    void fdlaw(FdBlock& fd) {
        const bool energy = (fd.flags & kFdEnergyOn) != 0;
        const bool first = (fd.flags & kFdFirstCall) != 0;
        // A rule that bonds on touch (bonded = 1 in the rule) does not bond a pair whose bond
        // broke or was removed before: that contact starts unbonded.
        if (first && install_pending_ && (fd.flags & kFdNoAutoBond)) {
            install_pending_ = false;
            bonded = 0.0;
        }
        double released = 0.0, slip = 0.0;
        bool sliding = false;
        // The break reported with this step (one event per contact and step): the first element
        // to break in tension, else the first in shear.
        int mode = kBreakNone;
        double brk_sigma = 0.0, brk_tau = 0.0;
        Normal now[kMaxElements];
        // Corners of a flat touch (onset) or lift-off (closing) of an unbonded interface.
        bool onset = false, closing = false, closing_sliding = false;
        double corner_lead = 0.5, closing_fs = 0.0;

        if (install_pending_) {
            // The elements' forces of the last step and what they held, for the energy of a
            // re-installation on a live contact (a first call's is the host's to book).
            double stored_before = 0.0;
            Normal before[kMaxElements];
            double fs_before[kMaxElements] = {};
            if (!first && energy)
                for (int e = 0; e < n_; ++e) {
                    const bool was = state_[e] == kBonded || ((unbond_mask_ >> e) & 1);
                    before[e] = normal(e, was, d_, theta_);
                    fs_before[e] = fs_[e];
                    stored_before += before[e].energy + shearSpringEnergy(fs_[e]);
                }
            install(fd.n_force, fd.s_force);
            install_pending_ = false;
            started_ = true;
            // An element already weaker than the forces it adopts breaks at once.
            double stored_after = 0.0, work_in = 0.0;
            for (int e = 0; e < n_; ++e) {
                now[e] = normal(e, state_[e] == kBonded, d_, theta_);
                if (state_[e] == kBonded) {
                    const double sigma = len_ > 0.0 ? -now[e].f / len_ : 0.0;
                    const double tau = len_ > 0.0 ? std::fabs(fs_[e]) / len_ : 0.0;
                    const bool tension = sigma > 0.0 && sigma >= fj_ten;
                    const bool shear = !tension && tau > 0.0 && tau >= shearStrength(sigma);
                    if (tension || shear) {
                        const double held = now[e].energy + shearSpringEnergy(fs_[e]);
                        state_[e] = tension ? kBrokenTension : kBrokenShear;
                        now[e] = normal(e, false, d_, theta_);
                        fs_[e] = capped(fs_[e], now[e].f);
                        if (first) released += held - now[e].energy - shearSpringEnergy(fs_[e]);
                        if (mode == kBreakNone || (tension && mode == kBreakShear)) {
                            mode = tension ? kBreakTension : kBreakShear;
                            brk_sigma = sigma, brk_tau = tau;
                        }
                    }
                }
                if (!first && energy) {
                    stored_after += now[e].energy + shearSpringEnergy(fs_[e]);
                    work_in += work(e, before[e], now[e], fs_before[e], fs_[e], fd.du_n, fd.du_s,
                                    fd.dtheta);
                }
            }
            if (!first && energy) released += stored_before + work_in - stored_after;
        } else if (first) {
            // A contact made by a rule without bonds: an unbonded interface that touched within
            // this step, closed by the overlap (as `linear`'s kn u_n); only the shear motion
            // after the touch loads the elements' shear springs.
            started_ = true;
            d_ = fd.u_n;
            theta_ = 0.0;
            keep_gap_ = 0.0;
            unbond_mask_ = 0;
            corner_lead = onsetFraction(fd.u_n, fd.du_n);
            onset = true;
            const double ks_len = fj_ks * len_;
            for (int e = 0; e < n_; ++e) {
                state_[e] = kUnbonded;
                now[e] = normal(e, false, d_, theta_);
                const double entry = fd.s_force / n_, du_s = fd.du_s * corner_lead;
                const double trial = entry - ks_len * du_s;
                fs_[e] = capped(trial, now[e].f);
                slip_[e] = fs_[e] != trial;
                sliding = sliding || slip_[e];
                if (slip_[e] && ks_len > 0.0)
                    slip -= 0.5 * (entry + fs_[e]) * (du_s + (fs_[e] - entry) / ks_len);
            }
        } else {
            const double d_new = d_ + fd.du_n, th_new = theta_ + fd.dtheta;
            const double ks_len = fj_ks * len_;
            // A flat touch or lift-off of an interface without bonds (the header's corners).
            if (fj_nbond == 0.0 && unbond_mask_ == 0) {
                const double span_old = fj_radius * std::fabs(theta_);
                const double span_new = fj_radius * std::fabs(th_new);
                if (d_ + span_old <= 0.0 && d_new - span_new > 0.0) {
                    onset = true;
                    corner_lead = onsetFraction(d_new, fd.du_n);
                } else if (d_ - span_old > 0.0 && d_new + span_new <= 0.0) {
                    closing = true;
                    corner_lead = closingFraction(d_, d_new);
                    for (int e = 0; e < n_; ++e) {
                        closing_fs += fs_[e];
                        closing_sliding = closing_sliding || slip_[e];
                    }
                }
            }
            // On a touch only the shear motion after it loads the shear springs.
            const double du_s = onset ? fd.du_s * corner_lead : fd.du_s;
            for (int e = 0; e < n_; ++e) {
                const double fs_old = fs_[e];
                const double fs_trial = fs_old - ks_len * du_s;
                slip_[e] = false;
                if (state_[e] == kBonded) {
                    const Normal trial = normal(e, true, d_new, th_new);
                    const double sigma = len_ > 0.0 ? -trial.f / len_ : 0.0;
                    const double tau = len_ > 0.0 ? std::fabs(fs_trial) / len_ : 0.0;
                    const bool tension = sigma > 0.0 && sigma >= fj_ten;
                    const bool shear = !tension && tau > 0.0 && tau >= shearStrength(sigma);
                    if (!(tension || shear)) {
                        now[e] = trial;
                        fs_[e] = fs_trial;
                        continue;
                    }
                    const Normal old = normal(e, true, d_, theta_);
                    state_[e] = tension ? kBrokenTension : kBrokenShear;
                    now[e] = normal(e, false, d_new, th_new);
                    fs_[e] = capped(fs_trial, now[e].f);
                    released += old.energy + shearSpringEnergy(fs_old) +
                                work(e, old, now[e], fs_old, fs_[e], fd.du_n, fd.du_s, fd.dtheta) -
                                now[e].energy - shearSpringEnergy(fs_[e]);
                    if (mode == kBreakNone || (tension && mode == kBreakShear)) {
                        mode = tension ? kBreakTension : kBreakShear;
                        const double sigma_o = len_ > 0.0 ? -old.f / len_ : 0.0;
                        failureStresses(sigma_o, sigma, fs_old, fs_trial, tension, brk_sigma,
                                        brk_tau);
                    }
                    continue;
                }
                now[e] = normal(e, false, d_new, th_new);
                fs_[e] = capped(fs_trial, now[e].f);
                if ((unbond_mask_ >> e) & 1) {
                    // Unbonded by a write since the last step: it releases what it held then
                    // plus this step's work, less what it holds now (as a break).
                    const Normal old = normal(e, true, d_, theta_);
                    released += old.energy + shearSpringEnergy(fs_old) +
                                work(e, old, now[e], fs_old, fs_[e], fd.du_n, fd.du_s, fd.dtheta) -
                                now[e].energy - shearSpringEnergy(fs_[e]);
                } else if (closing) {
                    // A flat lift-off: the shear spring lets go as the face opens, its energy to
                    // friction, and the closing corner pays the rest of its force's impulse
                    // (`linear`'s separation step).
                    slip += shearSpringEnergy(fs_old);
                } else if (fs_[e] != fs_trial) {
                    // Sliding: the slider's work is the trapezoidal work of the shear force
                    // minus the change of the spring's energy (exactly what closes the books).
                    slip_[e] = true;
                    sliding = true;
                    if (ks_len > 0.0)
                        slip -= 0.5 * (fs_old + fs_[e]) * (du_s + (fs_[e] - fs_old) / ks_len);
                }
            }
            d_ = d_new;
            theta_ = th_new;
            unbond_mask_ = 0;
        }

        // The interface: sums over the elements.
        double fn = 0.0, fs = 0.0, m = 0.0, e_bond = 0.0, e_strain = 0.0;
        int nbond = 0;
        for (int e = 0; e < n_; ++e) {
            fn += now[e].f;
            fs += fs_[e];
            m += -centre(e) * now[e].f + now[e].m;
            const bool is_bonded = state_[e] == kBonded;
            nbond += is_bonded;
            if (!energy) continue;
            const double held = now[e].energy + shearSpringEnergy(fs_[e]);
            if (is_bonded)
                e_bond += held;
            else
                e_strain += held;
        }
        fj_fn = fn, fj_fs = fs, fj_m = m;
        fj_nbond = nbond;
        bonded = nbond > 0 ? 1.0 : 0.0;
        fj_gap = -d_;
        fj_relbr = theta_;
        // Kept while bonded, or while an unbonded interface touches (a slit one: while it has
        // not opened beyond twice its installation gap).
        keep_ = nbond > 0 || d_ + fj_radius * std::fabs(theta_) > -keep_gap_;

        // The corners are impulses of this step only, not state (as `linear`'s).
        Corners corner;
        if (onset) {
            bool any_slip = false;
            for (int e = 0; e < n_; ++e) any_slip = any_slip || slip_[e];
            corner = linearOnsetCorners(fj_kn * 2.0 * fj_radius, fj_ks * 2.0 * fj_radius, fj_fric,
                                        fs, any_slip, fd, corner_lead);
        } else if (closing) {
            corner = linearClosingCorners(fj_kn * 2.0 * fj_radius, fj_ks * 2.0 * fj_radius, fj_fric,
                                          closing_fs, closing_sliding, fd, corner_lead, true);
        }
        fd.n_force = fn + corner.normal;
        fd.s_force = fs + corner.shear;
        fd.moment = m;
        // The time step sees the whole interface's stiffness whatever its state: an open or
        // broken element can close within a step (over-estimating is safe).
        fd.knest = fj_kn * 2.0 * fj_radius;
        fd.ksest = fj_ks * 2.0 * fj_radius;
        fd.krest = fj_kn * inertia();
        if (nbond > 0) fd.flags |= kFdBonded;
        if (keep_) fd.flags |= kFdKeep;
        if (sliding) fd.flags |= kFdSliding;
        if (mode != kBreakNone) {
            fd.flags |= kFdBroken | kFdBreakStress;
            fd.break_mode = mode;
            fd.reserved[0] = brk_sigma;
            fd.reserved[1] = brk_tau;
        }
        if (energy) {
            fd.energy[kEnergyStrain] = e_strain;
            fd.energy[kEnergyBondStrain] = e_bond;
            fd.energy[kEnergySlip] = slip;
            fd.energy[kEnergyReleased] = released;
        }
    }

    /// Second moment of the interface, (2/3) R^3 t.
    double inertia() const { return 2.0 * fj_radius * fj_radius * fj_radius / 3.0; }

    // Version 1: the first layout.
    void saveRestoreState(ModelSaveObject& so) {
        so.Double(r_min_);
        so.Double(r_sum_);
        so.Double(d_);
        so.Double(theta_);
        so.Double(keep_gap_);
        so.Int(unbond_mask_);
        so.Bool(install_pending_);
        so.Bool(started_);
        so.Bool(keep_);
        so.Double(fj_nbond);
        so.Double(fj_gap);
        so.Double(fj_relbr);
        so.Double(fj_fn);
        so.Double(fj_fs);
        so.Double(fj_m);
        for (int e = 0; e < kMaxElements; ++e) {
            so.Int(state_[e]);
            so.Double(fs_[e]);
            so.Bool(slip_[e]);
        }
    }

    int32_t Version() const override { return 1; }
    double KnEstimate() const override { return fj_kn * 2.0 * fj_radius; }
    double KsEstimate() const override { return fj_ks * 2.0 * fj_radius; }
    /// Half period of the fastest undamped mode: normal fj_kn A, shear 3 fj_ks A (a disk's
    /// tangential mobility 3/m*, as `linear`), bending fj_kn I against the ends' rotational
    /// inertia, at least m* min(R)^2 / 2 for disks (pbond's rule).
    double ContactDuration(double mass_eff, double) const override {
        const double area = 2.0 * fj_radius;
        const double kn = fj_kn * area, ks = fj_ks * area;
        const double kr = r_min_ > 0.0 ? 2.0 * fj_kn * inertia() / (r_min_ * r_min_) : 0.0;
        const double k = std::max({kn, 3.0 * ks, kr});
        return kn > 0.0 ? M_PI * std::sqrt(mass_eff / k) : HUGE_VAL;
    }
    bool OKToDelete() const override { return !(install_pending_ || fj_nbond > 0.0 || keep_); }
    uint32_t Traits() const override { return kTraitThreadSafe | kTraitBond; }
};

ContactModel* createPrototype(int32_t index) { return index == 0 ? new FJoint() : nullptr; }
void destroyPrototype(ContactModel* p) { delete static_cast<FJoint*>(p); }

const PluginInfo kInfo = TALUS_PLUGIN_INFO_INIT("1.0.0", 1, createPrototype, destroyPrototype);

}  // namespace

TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }

// The batched law (docs/plugin-abi.md, "Batched FDlaw"): the same fdlaw over an array of
// contacts, without a virtual call each; same bits.
TALUS_PLUGIN_EXPORT talus::BatchFdLawFn talus_plugin_batch(int32_t index) {
    return index == 0 ? &FJoint::BatchFDlaw : nullptr;
}
