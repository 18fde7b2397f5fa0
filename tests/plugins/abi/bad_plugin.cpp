// SPDX-License-Identifier: MIT
//
// One source, many libraries: tests/plugins/abi/CMakeLists.txt compiles this file once per defect
// with -DDEFECT=<n> (the constants below) and -DMODEL_NAME="..." to get a library the host must
// refuse, or a well-formed one with a chosen model name (DEFECT_NONE). The libraries go to a
// test-only directory so that nothing ever loads them by accident.
#include <cmath>

#include "talus/contact_model.hpp"
#include "talus/sdk/model_base.hpp"

#define DEFECT_NONE 0
#define DEFECT_NO_ENTRY 1           // exports a misspelt entry point
#define DEFECT_NULL_INFO 2          // talus_plugin_info() returns nullptr
#define DEFECT_ABI_MAJOR 3          // built for the next major ABI
#define DEFECT_ABI_MINOR 4          // built for a newer minor ABI than the host
#define DEFECT_SIZEOF_FDBLOCK 5     // different FdBlock layout
#define DEFECT_SIZEOF_PROPBLOCK 6   // different PropBlock layout
#define DEFECT_SIZEOF_PLUGININFO 7  // different PluginInfo layout
#define DEFECT_DIM 8                // a 3D plugin
#define DEFECT_BUILD_KEY 9          // another compiler / C++ ABI
#define DEFECT_NO_MODELS 10         // model_count = 0
#define DEFECT_NULL_CREATE 11       // create_prototype missing
#define DEFECT_NULL_DESTROY 12      // destroy_prototype missing
#define DEFECT_NULL_PROTOTYPE 13    // create_prototype returns nullptr
#define DEFECT_EMPTY_NAME 14        // the model's Name() is ""
#define DEFECT_DUPLICATE_INSIDE 15  // two models of the same name in one library
#define DEFECT_LANES_SIZE 16        // a lane law of another sizeof(LaneLaw)
#define DEFECT_LANES_STATE 17       // a lane law with no state (state_size 0)
#define DEFECT_LANES_NULL 18        // a lane law without its law function

#ifndef DEFECT
#error "compile with -DDEFECT=<n>"
#endif
#ifndef MODEL_NAME
#define MODEL_NAME "probe"
#endif
#ifndef PLUGIN_VERSION
#define PLUGIN_VERSION "0.0.1-test"
#endif

namespace {

using namespace talus;
using namespace talus::sdk;

/// A linear spring in the normal direction only: enough of a model to be used by an engine.
class Probe final : public ModelBase<Probe> {
public:
#if DEFECT == DEFECT_EMPTY_NAME
    static constexpr const char* kName = "";
#else
    static constexpr const char* kName = MODEL_NAME;
#endif
    double kn = 0.0;

    static const PropTable<Probe>& Table() {
        static const PropTable<Probe> t = {
            {{"kn", "N/m", kPropInheritable, 0.0, "normal stiffness", nullptr}, &Probe::kn, 0.0},
        };
        return t;
    }
    bool inherit(const PropBlock& pb) {
        kn = inheritSeries(kn, pb.kn);
        return true;
    }
    void fdlaw(FdBlock& fd) {
        fd.n_force = fd.u_n > 0.0 ? kn * fd.u_n : 0.0;
        fd.s_force = 0.0;
        fd.moment = 0.0;
        fd.knest = kn;
        fd.ksest = fd.krest = 0.0;
        if (fd.flags & kFdEnergyOn) fd.energy[kEnergyStrain] = springEnergy(fd.n_force);
    }
    double springEnergy(double f) const { return kn > 0.0 ? 0.5 * f * f / kn : 0.0; }
    void saveRestoreState(ModelSaveObject&) {}
    int32_t Version() const override { return 1; }
    double KnEstimate() const override { return kn; }
    double KsEstimate() const override { return 0.0; }
    double ContactDuration(double mass_eff, double) const override {
        return kn > 0.0 ? M_PI * std::sqrt(mass_eff / kn) : HUGE_VAL;
    }
};

#if DEFECT == DEFECT_NULL_PROTOTYPE
ContactModel* createPrototype(int32_t) { return nullptr; }
#elif DEFECT == DEFECT_DUPLICATE_INSIDE
ContactModel* createPrototype(int32_t index) { return index < 2 ? new Probe() : nullptr; }
#else
ContactModel* createPrototype(int32_t index) { return index == 0 ? new Probe() : nullptr; }
#endif
void destroyPrototype(ContactModel* p) { delete static_cast<Probe*>(p); }

PluginInfo makeInfo() {
    PluginInfo info = TALUS_PLUGIN_INFO_INIT(PLUGIN_VERSION, 1, createPrototype, destroyPrototype);
#if DEFECT == DEFECT_ABI_MAJOR
    info.abi_major += 1;
#elif DEFECT == DEFECT_ABI_MINOR
    info.abi_minor += 1;
#elif DEFECT == DEFECT_SIZEOF_FDBLOCK
    info.sizeof_fdblock += 8;
#elif DEFECT == DEFECT_SIZEOF_PROPBLOCK
    info.sizeof_propblock += 8;
#elif DEFECT == DEFECT_SIZEOF_PLUGININFO
    info.sizeof_plugininfo += 8;
#elif DEFECT == DEFECT_DIM
    info.dim = 3;
#elif DEFECT == DEFECT_BUILD_KEY
    info.build_key = "itanium-othercc|cxx11abi=0|ptr8|1234|abi1";
#elif DEFECT == DEFECT_NO_MODELS
    info.model_count = 0;
#elif DEFECT == DEFECT_NULL_CREATE
    info.create_prototype = nullptr;
#elif DEFECT == DEFECT_NULL_DESTROY
    info.destroy_prototype = nullptr;
#elif DEFECT == DEFECT_DUPLICATE_INSIDE
    info.model_count = 2;
#endif
    return info;
}

const PluginInfo kInfo = makeInfo();

}  // namespace

#if DEFECT == DEFECT_NO_ENTRY
TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_information() { return &kInfo; }
#elif DEFECT == DEFECT_NULL_INFO
TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() {
    (void)kInfo;
    return nullptr;
}
#else
TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }
#endif

#if DEFECT == DEFECT_LANES_SIZE || DEFECT == DEFECT_LANES_STATE || DEFECT == DEFECT_LANES_NULL
namespace {
int32_t lanePack(const talus::ContactModel*, double*) { return 0; }
void laneUnpack(talus::ContactModel*, const double*) {}
void laneLaw(const talus::LaneBatch&) {}
const char* const kLaneNames[] = {"x"};
talus::LaneLaw makeLanes() {
    talus::LaneLaw l{sizeof(talus::LaneLaw), 1, kLaneNames, &lanePack, &laneUnpack, &laneLaw};
#if DEFECT == DEFECT_LANES_SIZE
    l.size += 8;
#elif DEFECT == DEFECT_LANES_STATE
    l.state_size = 0;
#else
    l.law = nullptr;
#endif
    return l;
}
const talus::LaneLaw kLanes = makeLanes();
}  // namespace
TALUS_PLUGIN_EXPORT const talus::LaneLaw* talus_plugin_lanes(int32_t index) {
    return index == 0 ? &kLanes : nullptr;
}
#endif
