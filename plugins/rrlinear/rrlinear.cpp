// SPDX-License-Identifier: MIT
//
// `rrlinear`: the PFC 5+ rolling-resistance linear model (docs/models/rrlinear.md).
//
// The linear law of talus/sdk/linear_law.hpp (kn, ks, fric, dashpots, dp_mode), plus a
// rolling-resistance moment M_r on end 2 (end 1 gets -M_r), incremental like the shear spring:
//
//   R_bar = R1 R2 / (R1 + R2)  (ball-wall: R1)         effective contact radius
//   k_r   = ks R_bar^2                                  rolling stiffness (PFC's definition)
//   M_r  <- M_r - k_r dtheta,  |M_r| <= rr_fric R_bar F_n^l        (rolling slip when limited)
//
// with dtheta the relative rotation increment of end 2 with respect to end 1 (FdBlock::dtheta)
// and F_n^l >= 0 the linear normal force. The limited moment is the rolling friction of a rock
// on a slope: a disk rolling at speed v dissipates M_r v / R, so its kinetic energy
// (m + I/R^2) v^2 / 2 runs out after v^2 (1 + I/(m R^2)) / (2 rr_fric g) on a flat floor.
//
// Energies: the rolling spring's M_r^2 / (2 k_r) is booked with the strain energy and the
// rolling slip work with the slip (frictional) work: the ABI has no separate partitions for
// them, and both are the same kind as the linear law's (stored elastic, frictional).
// Time step: krest = k_r (0 when rr_fric = 0), so that the rotational stability rule sees the
// rolling spring (docs/physics/timestep.md: k_rot = sum of ksest r^2 + krest).
#include <cmath>

#include "talus/contact_model.hpp"
#include "talus/sdk/linear_law.hpp"
#include "talus/sdk/model_base.hpp"
#include "talus/sdk/shear_spring.hpp"

namespace {

using namespace talus;
using namespace talus::sdk;

class RRLinear final : public ModelBase<RRLinear>, public LinearLaw {
public:
    static constexpr const char* kName = "rrlinear";

    double rr_fric = 0.0;     // rolling friction coefficient [-]
    double rr_moment = 0.0;   // rolling-resistance moment on end 2 [N m] (state)
    double rr_slip = 0.0;     // 1 while the rolling moment is at its limit (state)
    double rr_kr = 0.0;       // rolling stiffness ks R_bar^2 [N m/rad] (derived, per contact)
    double rr_radius_ = 0.0;  // effective contact radius R_bar [m]

    static const PropTable<RRLinear>& Table() {
        static const PropTable<RRLinear> t = [] {
            PropTable<RRLinear> rows = linearSettableProps<RRLinear>();
            // clang-format off
            rows.push_back({{"rr_fric", "-", 0, 0.0, "rolling friction coefficient", nullptr},
                            &RRLinear::rr_fric, 0.0, HUGE_VAL, false,
                            "(the limiting moment is rr_fric R_bar F_n)"});
            rows.push_back({{"rr_kr", "N m/rad", kPropReadOnly, 0.0,
                             "rolling stiffness ks R_bar^2", nullptr}, &RRLinear::rr_kr});
            rows.push_back({{"rr_moment", "N m", kPropReadOnly | kPropState, 0.0,
                             "rolling-resistance moment on end 2", nullptr}, &RRLinear::rr_moment});
            rows.push_back({{"rr_slip", "-", kPropReadOnly | kPropState, 0.0,
                             "1 while the rolling moment is at its limit", nullptr},
                            &RRLinear::rr_slip});
            // clang-format on
            for (auto& r : linearStateProps<RRLinear>()) rows.push_back(r);
            return rows;
        }();
        return t;
    }

    bool inherit(const PropBlock& pb) {
        linearInherit(pb);
        // PFC: R_bar = 1 / (1/R1 + 1/R2), and R1 for a wall (R2 infinite).
        const double r1 = pb.radius[0], r2 = pb.end2_type == kEndWall ? 0.0 : pb.radius[1];
        rr_radius_ = r2 > 0.0 ? r1 * r2 / (r1 + r2) : r1;
        if (!(rr_radius_ >= 0.0) || !std::isfinite(rr_radius_)) {
            fail("rrlinear: the ends' radii give no effective radius (R1 = " + std::to_string(r1) +
                 " m, R2 = " + std::to_string(r2) + " m)");
            return false;
        }
        rr_kr = ks * rr_radius_ * rr_radius_;
        return true;
    }

    void onPropChanged() {
        linearRefresh();
        rr_kr = ks * rr_radius_ * rr_radius_;
    }

    void fdlaw(FdBlock& fd) {
        const bool energy = (fd.flags & kFdEnergyOn) != 0;
        const Step s = linearLaw(fd);
        // Without rolling friction the rolling spring never holds a moment: it has no stiffness
        // for the time step either (and rr_fric = 0 is then `linear` exactly, step for step).
        fd.krest = rr_fric > 0.0 ? rr_kr : 0.0;
        if (!s.touching) {
            // Separated: the rolling spring lets go, as the shear spring does; what it held
            // goes to friction (linear_law.hpp books the shear spring's the same way).
            if (energy) fd.energy[kEnergySlip] += springEnergy(rr_moment, rr_kr);
            rr_moment = rr_slip = 0.0;
            fd.moment = 0.0;
            return;
        }
        // Only the part of the first step after touch loads the spring (as the shear spring).
        const double dtheta = s.first ? fd.dtheta * onsetFraction(fd.u_n, fd.du_n) : fd.dtheta;
        // The slider of the shear spring is the same law for a moment: M <- M - k_r dtheta,
        // |M| <= limit, with the slip work -<M> dtheta_slip (shear_spring.hpp).
        const double limit = rr_fric * rr_radius_ * std::fmax(lin_fn, 0.0);
        const ShearResult r = updateShearSpring(rr_moment, rr_kr, dtheta, limit);
        rr_slip = r.sliding ? 1.0 : 0.0;
        fd.moment = rr_moment;
        if (energy) {
            fd.energy[kEnergyStrain] += springEnergy(rr_moment, rr_kr);
            fd.energy[kEnergySlip] += r.slip_work;
        }
    }

    void saveRestoreState(ModelSaveObject& so) {
        linearSaveRestore(so, 1);
        so.Double(rr_moment);
        so.Double(rr_slip);
        so.Double(rr_kr);
        so.Double(rr_radius_);
    }

    int32_t Version() const override { return 1; }
    double KnEstimate() const override { return linearKnEstimate(); }
    double KsEstimate() const override { return linearKsEstimate(); }
    double ContactDuration(double mass_eff, double) const override {
        // The rolling spring of a disk on k_r = ks R^2 has omega^2 = k_r / I = 2 ks / m, slower
        // than the sticking shear spring's 3 ks / m* the linear law already resolves.
        return linearContactDuration(mass_eff);
    }
};

ContactModel* createPrototype(int32_t index) { return index == 0 ? new RRLinear() : nullptr; }
void destroyPrototype(ContactModel* p) { delete static_cast<RRLinear*>(p); }

const PluginInfo kInfo = TALUS_PLUGIN_INFO_INIT("1.0.0", 1, createPrototype, destroyPrototype);

}  // namespace

TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }
