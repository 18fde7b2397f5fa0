// SPDX-License-Identifier: MIT
//
// `ng`: Ng's normal and shear stiffness from the contact radius (docs/models/ng.md).
//
//   a = sqrt(R* u_n)                       contact radius of the Hertz contact
//   k_n = 2 G a / (1 - nu),  k_s = 4 G a / (2 - nu)
//   ng_form 0 (default, tangent):  dF_n/du_n = k_n, so F_n = (2/3) k_n(u_n) u_n
//   ng_form 1 (secant):            F_n = k_n(u_n) u_n
//   shear:  F_s <- F_s - k_s dU_s,  |F_s| <= fric F_n  (no unloading rule besides Coulomb)
//
// Citation status: Nejati's (2008) equations 2.37-2.39 could not be checked. The
// formulas are the Hertz-Mindlin tangent stiffnesses of two equal spheres in contact-radius
// form (Johnson 1985: 2 E* a with E* = G/(1-nu), and 8 G* a with G* = G/(2(2-nu))),
// which is the form Ng's stiffnesses take. How Nejati (2008) used k_n (as a tangent, incrementally,
// or as a secant like PFC's kn) is not known here: both are offered.
//
// How it differs from `hertz`: the formulas are used as written for every contact, so a wall
// counts as a body of the same material (hertz: a rigid wall, twice the E* and G*); form 1 is
// 3/2 of Hertz's force; there is no contact dashpot (Nejati 2008 damps with the law of motion,
// DampingSettings::viscous) and no scaling of the shear force on normal unloading.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "talus/contact_model.hpp"
#include "talus/sdk/dashpot.hpp"  // onsetFraction
#include "talus/sdk/model_base.hpp"
#include "talus/sdk/shear_spring.hpp"

namespace {

using namespace talus;
using namespace talus::sdk;

const char* const kForms[] = {"tangent", "secant", nullptr};

class Ng final : public ModelBase<Ng> {
public:
    static constexpr const char* kName = "ng";

    // properties
    double ng_shear = 0.0;  // shear modulus G [Pa]
    double ng_poiss = 0.0;  // Poisson ratio [-]
    double ng_form = 0.0;   // 0 tangent, 1 secant
    double fric = 0.0;      // [-]
    // state (read-only)
    double ng_fn = 0.0;    // normal force [N]
    double ng_fs = 0.0;    // shear force [N]
    double ng_slip = 0.0;  // 1 while sliding
    // per-contact values (not properties)
    double r_star_ = 0.0;  // effective radius [m]
    double last_overlap_ = 0.0;
    bool touching_ = false;

    static const PropTable<Ng>& Table() {
        static const PropTable<Ng> t = {
            {{"ng_shear", "Pa", 0, 0.0, "shear modulus G", nullptr},
             &Ng::ng_shear,
             0.0,
             kStiffnessMax},
            // range [0, 0.5) checked in AcceptProp and PreCycle (the table's ranges are closed)
            {{"ng_poiss", "-", 0, 0.0, "Poisson ratio", nullptr}, &Ng::ng_poiss},
            {{"ng_form", "-", kPropInteger, 0.0, "use of k_n: 0 tangent, 1 secant", kForms},
             &Ng::ng_form,
             0.0,
             1.0},
            {{"fric", "-", kPropInheritable, 0.0, "friction coefficient", nullptr}, &Ng::fric, 0.0},
            {{"ng_fn", "N", kPropReadOnly | kPropState, 0.0, "normal force", nullptr}, &Ng::ng_fn},
            {{"ng_fs", "N", kPropReadOnly | kPropState, 0.0, "shear force", nullptr}, &Ng::ng_fs},
            {{"ng_slip", "-", kPropReadOnly | kPropState, 0.0, "1 while sliding", nullptr},
             &Ng::ng_slip},
        };
        return t;
    }

    int32_t AcceptProp(int32_t index, double value) override {
        if (const PropInfo* info = PropInfoAt(index))
            if (std::string(info->name) == "ng_poiss" && !(value >= 0.0 && value < 0.5))
                return fail(poissonError(value));
        return ModelBase<Ng>::AcceptProp(index, value);
    }

    const char* PreCycle(const PropBlock& pb) override {
        if (!(ng_poiss >= 0.0 && ng_poiss < 0.5)) {
            errorText() = poissonError(ng_poiss);
            return errorText().c_str();
        }
        return ModelBase<Ng>::PreCycle(pb);
    }

    static std::string poissonError(double value) {
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "ng: 'ng_poiss' must be in [0, 0.5) (Poisson ratio; 0.5, incompressible, is "
                      "excluded) (got %g)",
                      value);
        return buf;
    }

    bool inherit(const PropBlock& pb) {
        fric = inheritMin(fric, pb.fric);
        const double r1 = pb.radius[0], r2 = pb.radius[1];
        r_star_ = pb.end2_type == kEndWall || !(r2 > 0.0) ? r1 : r1 * r2 / (r1 + r2);
        return true;
    }

    double contactRadius(double overlap) const {
        return overlap > 0.0 ? std::sqrt(r_star_ * overlap) : 0.0;
    }
    double normalStiffness(double overlap) const {
        return 2.0 * ng_shear * contactRadius(overlap) / (1.0 - ng_poiss);
    }
    double shearStiffness(double overlap) const {
        return 4.0 * ng_shear * contactRadius(overlap) / (2.0 - ng_poiss);
    }
    bool secant() const { return ng_form == 1.0; }

    void fdlaw(FdBlock& fd) {
        const bool energy = (fd.flags & kFdEnergyOn) != 0;
        const double u = fd.u_n;
        // Stored shear energy of the last step, for the slip booking.
        const double fs_old = ng_fs;
        const double strain_s_old = springEnergy(ng_fs, shearStiffness(last_overlap_));
        if (u <= 0.0) {
            if (energy) {
                fd.energy[kEnergyStrain] = 0.0;
                // The shear spring lets go of what it stored: slip.
                fd.energy[kEnergySlip] = touching_ ? -0.5 * fs_old * fd.du_s + strain_s_old : 0.0;
            }
            touching_ = false;
            ng_fn = ng_fs = ng_slip = 0.0;
            fd.n_force = fd.s_force = fd.moment = 0.0;
            fd.knest = fd.ksest = fd.krest = 0.0;
            last_overlap_ = u;
            return;
        }
        const bool first = !touching_;
        const double kn = normalStiffness(u);
        const double ks = shearStiffness(u);

        // Form 0: k_n is the tangent dF/du, so F = int_0^u k_n ds = (2/3) k_n(u) u. An
        // incremental update F += k_n du only approximates this integral (k_n ~ sqrt(u) has an
        // infinite derivative at touch, so the error of the first steps stays in the force for
        // the whole contact); the exact increments telescope to the closed form used here.
        // Form 1: k_n as a secant, F = k_n(u) u, as PFC's linear model uses kn.
        ng_fn = (secant() ? 1.0 : 2.0 / 3.0) * kn * u;
        const double strain_n = 0.4 * ng_fn * u;  // int F du = (2/5) F u for F ~ u^(3/2)

        const double frac = first ? onsetFraction(u, fd.du_n) : 1.0;
        // While the overlap shrinks, k_s falls with the contact radius. Holding the shear force
        // (a plain incremental spring) raises the stored energy F_s^2 / 2k_s with
        // no work: the law created energy in every load cycle of a sticking contact, booked as
        // negative slip (-2% of the throughput for a ball rolling on a floor, fric = 1).
        // Thornton's unloading rule scales the force with the contact radius, F_s *=
        // k_s(u) / k_s(u_old) (Thornton, Cummins & Cleary 2011, Powder Technol. 210, 189): the
        // stored energy falls by k_s/k_s_old instead, what the annulus leaving contact lets go,
        // and the slip increment (1 - rho)/2 (rho F^2/k_s - F du_s), rho = k_s/k_s_old, is >= 0
        // up to its second-order cross term. `hertz` does the same.
        if (!first && u < last_overlap_) {
            const double ks_old = shearStiffness(last_overlap_);
            if (ks_old > 0.0) ng_fs *= ks / ks_old;
        }
        const ShearResult sr = updateShearSpring(ng_fs, ks, fd.du_s * frac, fric * ng_fn);
        (void)sr.slip_work;  // booked below from the stored energy (k_s varies)
        ng_slip = sr.sliding ? 1.0 : 0.0;

        fd.n_force = ng_fn;
        fd.s_force = ng_fs;
        fd.moment = 0.0;
        if (sr.sliding) fd.flags |= kFdSliding;
        fd.knest = secant() ? 1.5 * kn : kn;  // tangent of F = k_n(u) u is (3/2) k_n
        fd.ksest = ks;
        fd.krest = 0.0;
        if (energy) {
            const double strain_s = springEnergy(ng_fs, ks);
            fd.energy[kEnergyStrain] = strain_n + strain_s;
            // Work in minus the change of stored energy (trapezoidal, as the engine's kinetic
            // energy sees it): Coulomb slip, plus what a k_s that changes with the overlap
            // removes at constant force. Equals the SDK's slip work when k_s is constant.
            fd.energy[kEnergySlip] = -0.5 * (fs_old + ng_fs) * fd.du_s - (strain_s - strain_s_old);
        }
        touching_ = true;
        last_overlap_ = u;
    }

    void saveRestoreState(ModelSaveObject& so) {
        so.Double(ng_fn);
        so.Double(ng_fs);
        so.Double(ng_slip);
        so.Double(r_star_);
        so.Double(last_overlap_);
        so.Bool(touching_);
    }

    int32_t Version() const override { return 1; }
    double KnEstimate() const override {
        if (!touching_) return 0.0;
        return (secant() ? 1.5 : 1.0) * normalStiffness(last_overlap_);
    }
    double KsEstimate() const override { return touching_ ? shearStiffness(last_overlap_) : 0.0; }
    double ContactDuration(double mass_eff, double approach_speed) const override {
        // Both forms are Hertz laws, F = (4/3) E sqrt(R*) u^(3/2) with E = G/(1-nu) (form 0)
        // or (3/2) G/(1-nu) (form 1): the Hertz impact duration
        // 2.8683 (m*^2/(R* E^2 v))^(1/5) (Johnson 1985).
        const double e = (secant() ? 1.5 : 1.0) * ng_shear / (1.0 - ng_poiss);
        if (!(approach_speed > 0.0) || !(e > 0.0) || !(r_star_ > 0.0)) return HUGE_VAL;
        static const double factor = 2.0 * std::sqrt(M_PI) * std::tgamma(1.4) / std::tgamma(0.9) *
                                     std::pow(15.0 / 16.0, 0.4);
        return factor * std::pow(mass_eff * mass_eff / (r_star_ * e * e * approach_speed), 0.2);
    }
};

ContactModel* createPrototype(int32_t index) { return index == 0 ? new Ng() : nullptr; }
void destroyPrototype(ContactModel* p) { delete static_cast<Ng*>(p); }

const PluginInfo kInfo = TALUS_PLUGIN_INFO_INIT("1.0.0", 1, createPrototype, destroyPrototype);

}  // namespace

TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }
