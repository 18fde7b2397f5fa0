// SPDX-License-Identifier: MIT
//
// `misfit`: a linear spring (F = kn u) that breaks one promise of the ABI on request, for the
// host's output checks (docs/plugin-abi.md, "Energies" and "The time-step contract"). The
// integer property `fault` picks the broken promise; 0 is a well-behaved model.
#include <cmath>

#include "talus/contact_model.hpp"
#include "talus/sdk/model_base.hpp"

namespace {

using namespace talus;

const char* const kFaults[] = {
    "none",          "duration_nan",     "duration_negative", "strain_nan",
    "slip_negative", "dashpot_negative", "plastic_negative",  "slip_roundoff",
    nullptr};

class Misfit final : public sdk::ModelBase<Misfit> {
public:
    static constexpr const char* kName = "misfit";
    double kn = 1e6;
    double fault = 0.0;

    static const sdk::PropTable<Misfit>& Table() {
        static const sdk::PropTable<Misfit> t = {
            {{"kn", "N/m", 0, 1e6, "normal stiffness", nullptr}, &Misfit::kn, 0.0, HUGE_VAL},
            {{"fault", "-", kPropInteger, 0.0, "which promise to break", kFaults},
             &Misfit::fault,
             0.0,
             7.0},
        };
        return t;
    }
    bool inherit(const PropBlock&) { return true; }
    void fdlaw(FdBlock& fd) {
        const double u = std::max(fd.u_n, 0.0);
        fd.n_force = kn * u;
        fd.s_force = fd.moment = 0.0;
        fd.knest = kn;
        fd.ksest = fd.krest = 0.0;
        if (!(fd.flags & kFdEnergyOn)) return;
        fd.energy[kEnergyStrain] = 0.5 * kn * u * u;
        const double bad = -1e-3 * (1.0 + fd.energy[kEnergyStrain]);
        switch (static_cast<int>(fault)) {
            case 3:
                fd.energy[kEnergyStrain] = std::nan("");
                break;
            case 4:
                fd.energy[kEnergySlip] = bad;
                break;
            case 5:
                fd.energy[kEnergyDashpot] = bad;
                break;
            case 6:
                fd.energy[kEnergyPlastic] = bad;
                break;
            // round-off of a work-minus-stored-energy difference: tolerated
            case 7:
                fd.energy[kEnergySlip] = -1e-14 * fd.energy[kEnergyStrain];
                break;
            default:
                break;
        }
    }
    void saveRestoreState(ModelSaveObject&) {}
    int32_t Version() const override { return 1; }
    double KnEstimate() const override { return kn; }
    double KsEstimate() const override { return 0.0; }
    double ContactDuration(double m, double) const override {
        if (fault == 1.0) return std::nan("");
        if (fault == 2.0) return -1.0;
        return kn > 0.0 ? M_PI * std::sqrt(m / kn) : HUGE_VAL;
    }
};

ContactModel* createPrototype(int32_t index) { return index == 0 ? new Misfit() : nullptr; }
void destroyPrototype(ContactModel* p) { delete static_cast<Misfit*>(p); }

const PluginInfo kInfo = TALUS_PLUGIN_INFO_INIT("0.0.1-test", 1, createPrototype, destroyPrototype);

}  // namespace

TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }
