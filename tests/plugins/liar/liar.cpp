// SPDX-License-Identifier: MIT
//
// `liar`: a test-only contact model that lies to the time step (tests/plugins/test_guard_liar.cpp).
// It is a linear spring of stiffness kn without tension (F_n = kn u_n), but it reports
// knest = kn / lie and a contact duration pi sqrt(m* lie / kn) computed from that reported
// stiffness. The engine therefore picks a step about sqrt(lie) times too large for the force
// law actually used: the defect An (2006) found in its own model, made
// deliberate so that the engine's stability guard can be shown to catch it.
// Built into the build tree's plugin directory only; never installed.
#include <cmath>

#include "talus/contact_model.hpp"
#include "talus/sdk/model_base.hpp"
#include "talus/sdk/shear_spring.hpp"

namespace {

using namespace talus;
using namespace talus::sdk;

class Liar final : public ModelBase<Liar> {
public:
    static constexpr const char* kName = "liar";

    double kn = 0.0;     // true stiffness [N/m]
    double lie = 100.0;  // factor by which the reported stiffness is too low [-]
    double fn = 0.0;     // state [N]

    // clang-format off
    static const PropTable<Liar>& Table() {
        static const PropTable<Liar> t = {
            {{"kn", "N/m", kPropInheritable, 0.0, "true normal stiffness", nullptr},
             &Liar::kn, 0.0},
            {{"lie", "-", 0, 100.0, "reported stiffness = kn / lie", nullptr},
             &Liar::lie, 0.0, 1e12, true},
            {{"liar_fn", "N", kPropReadOnly | kPropState, 0.0, "normal force", nullptr}, &Liar::fn},
        };
        return t;
    }
    // clang-format on

    bool inherit(const PropBlock& pb) {
        kn = inheritSeries(kn, pb.kn);
        return true;
    }

    void fdlaw(FdBlock& fd) {
        fn = fd.u_n > 0.0 ? kn * fd.u_n : 0.0;
        fd.n_force = fn;
        fd.s_force = 0.0;
        fd.moment = 0.0;
        fd.knest = KnEstimate();  // the lie
        fd.ksest = 0.0;
        fd.krest = 0.0;
        if (fd.flags & kFdEnergyOn) fd.energy[kEnergyStrain] = springEnergy(fn, kn);
    }

    void saveRestoreState(ModelSaveObject& so) { so.Double(fn); }

    int32_t Version() const override { return 1; }
    double KnEstimate() const override { return kn / lie; }
    double KsEstimate() const override { return 0.0; }
    double ContactDuration(double mass_eff, double) const override {
        const double k = KnEstimate();
        return k > 0.0 ? M_PI * std::sqrt(mass_eff / k) : HUGE_VAL;
    }
};

ContactModel* createPrototype(int32_t index) { return index == 0 ? new Liar() : nullptr; }
void destroyPrototype(ContactModel* p) { delete static_cast<Liar*>(p); }

const PluginInfo kInfo = TALUS_PLUGIN_INFO_INIT("1.0.0-test", 1, createPrototype, destroyPrototype);

}  // namespace

TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }
