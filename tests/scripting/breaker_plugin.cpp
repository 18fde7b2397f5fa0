// SPDX-License-Identifier: MIT
//
// `test_breaker`: a test-only contact model for the Lua event tests. A linear normal spring
// (no shear, no tension) that reports one tension "bond break" (kFdBroken) on the step a
// contact first touches, so that m:on_event("bond_break", fn) has something to deliver.
// Built into the test directory, not the shipped plugin directory; loaded with
// talus.load_plugin(path).
#include "talus/contact_model.hpp"
#include "talus/sdk/model_base.hpp"

namespace {

using namespace talus;
using namespace talus::sdk;

class Breaker final : public ModelBase<Breaker> {
public:
    static constexpr const char* kName = "test_breaker";

    double kn = 0.0;      // [N/m]
    double broken = 0.0;  // 1 once this contact has reported its break

    static const PropTable<Breaker>& Table() {
        static const PropTable<Breaker> t = {
            {{"kn", "N/m", 0, 0.0, "normal stiffness", nullptr}, &Breaker::kn, 0.0},
            {{"broken", "-", kPropReadOnly | kPropState, 0.0, "1 after the break", nullptr},
             &Breaker::broken},
        };
        return t;
    }

    bool inherit(const PropBlock&) { return true; }

    void fdlaw(FdBlock& fd) {
        fd.n_force = fd.u_n > 0.0 ? kn * fd.u_n : 0.0;
        fd.s_force = 0.0;
        fd.moment = 0.0;
        fd.knest = kn;
        fd.ksest = 0.0;
        fd.krest = 0.0;
        if (fd.u_n > 0.0 && broken == 0.0) {
            broken = 1.0;
            fd.flags |= kFdBroken;
            fd.break_mode = kBreakTension;
        }
        if (fd.flags & kFdEnergyOn) fd.energy[kEnergyStrain] = springEnergy(fd.n_force);
    }

    double springEnergy(double f) const { return kn > 0.0 ? 0.5 * f * f / kn : 0.0; }

    void saveRestoreState(ModelSaveObject& so) { so.Double(broken); }

    int32_t Version() const override { return 1; }
    double KnEstimate() const override { return kn; }
    double KsEstimate() const override { return 0.0; }
    double ContactDuration(double mass_eff, double) const override {
        return kn > 0.0 ? M_PI * std::sqrt(mass_eff / kn) : HUGE_VAL;
    }
};

ContactModel* createPrototype(int32_t index) { return index == 0 ? new Breaker() : nullptr; }
void destroyPrototype(ContactModel* p) { delete static_cast<Breaker*>(p); }

const PluginInfo kInfo = TALUS_PLUGIN_INFO_INIT("1.0.0", 1, createPrototype, destroyPrototype);

}  // namespace

TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }
