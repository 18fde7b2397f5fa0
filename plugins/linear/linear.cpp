// SPDX-License-Identifier: MIT
//
// `linear`: the PFC linear contact model (docs/models/linear.md).
//
//   normal:  F_n^l = kn u_n                       (secant, absolute; no tension)
//   shear:   F_s^l <- F_s^l - ks dU_s,  |F_s^l| <= fric F_n^l      (PFC's linear model)
//   dashpot: F^d = c (rate), c_n = 2 dp_nratio sqrt(m* kn), c_s = 2 dp_sratio sqrt(m* ks)
//   dp_mode: 0 full; 1 total normal force >= 0; 2 shear dashpot off while sliding; 3 = 1 and 2
//
// The law itself lives in talus/sdk/linear_law.hpp, shared with the models built on it
// (`rrlinear`); this file only makes it a plugin.
#include "talus/contact_model.hpp"
#include "talus/sdk/linear_law.hpp"
#include "talus/sdk/model_base.hpp"

namespace {

using namespace talus;
using namespace talus::sdk;

class Linear final : public ModelBase<Linear>, public LinearLaw {
public:
    static constexpr const char* kName = "linear";

    static const PropTable<Linear>& Table() {
        static const PropTable<Linear> t = [] {
            PropTable<Linear> rows = linearSettableProps<Linear>();
            for (auto& r : linearStateProps<Linear>()) rows.push_back(r);
            return rows;
        }();
        return t;
    }

    bool inherit(const PropBlock& pb) {
        linearInherit(pb);
        return true;
    }
    void onPropChanged() { linearRefresh(); }
    void fdlaw(FdBlock& fd) { linearLaw(fd); }
    // Version 2 added the dashpots' history.
    void saveRestoreState(ModelSaveObject& so) { linearSaveRestore(so, 2); }

    int32_t Version() const override { return 2; }
    double KnEstimate() const override { return linearKnEstimate(); }
    double KsEstimate() const override { return linearKsEstimate(); }
    double ContactDuration(double mass_eff, double) const override {
        return linearContactDuration(mass_eff);
    }

    // Lanes (sdk/lanes.hpp): the linear law's own.
    static constexpr int kLaneStateSize = kLinearLaneStateSize;
    static const char* const* laneStateNames() { return linearLaneStateNames(); }
    bool toLane(double* row) const { return linearToLane(row); }
    void fromLane(const double* row) { linearFromLane(row); }
    static bool laneStep(double* row, LaneFd& fd) { return linearLaneStep(row, fd); }
};

ContactModel* createPrototype(int32_t index) { return index == 0 ? new Linear() : nullptr; }
void destroyPrototype(ContactModel* p) { delete static_cast<Linear*>(p); }

const PluginInfo kInfo = TALUS_PLUGIN_INFO_INIT("1.0.0", 1, createPrototype, destroyPrototype);

}  // namespace

TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }

// The batched law (docs/plugin-abi.md, "Batched FDlaw"): the host calls it once per block of
// contacts instead of FDlaw per contact; same law, same bits.
TALUS_PLUGIN_EXPORT talus::BatchFdLawFn talus_plugin_batch(int32_t index) {
    return index == 0 ? &Linear::BatchFDlaw : nullptr;
}

// The lane law (docs/plugin-abi.md, "Lanes"): the state of touching contacts in rows the host
// owns, the same law over many contacts per call; same bits.
TALUS_PLUGIN_EXPORT const talus::LaneLaw* talus_plugin_lanes(int32_t index) {
    return index == 0 ? talus::sdk::laneLawOf<Linear>() : nullptr;
}

// The kernel (docs/plugin-abi.md, "Kernels"): this model is the SDK's linear law on its lane rows,
// so a host that has the same law compiled in runs it inline.
TALUS_PLUGIN_EXPORT const char* talus_plugin_kernel(int32_t index) {
    return index == 0 ? talus::sdk::LinearLaw::kKernelId : nullptr;
}
