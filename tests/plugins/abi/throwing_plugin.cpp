// SPDX-License-Identifier: MIT
//
// Models whose FDlaw throws once the bodies touch, for the exception-barrier tests. Compiled
// twice: -DRAW_MODEL=0 gives `thrower_sdk` (built with ModelBase, whose barrier turns the
// exception into FdBlock::status/error), -DRAW_MODEL=1 gives `thrower_raw` (a bare ContactModel
// with no barrier of its own: the exception reaches the host).
#include <cmath>
#include <new>
#include <stdexcept>
#include <string>

#include "talus/contact_model.hpp"

#if !RAW_MODEL
#include "talus/sdk/model_base.hpp"
#endif

namespace {

using namespace talus;

#if !RAW_MODEL

const char* const kKinds[] = {"std_exception", "non_std", nullptr};

class ThrowerSdk final : public sdk::ModelBase<ThrowerSdk> {
public:
    static constexpr const char* kName = "thrower_sdk";
    double kind = 0.0;  // 0: throws std::runtime_error, 1: throws an int

    static const sdk::PropTable<ThrowerSdk>& Table() {
        static const sdk::PropTable<ThrowerSdk> t = {
            {{"kind", "-", kPropInteger, 0.0, "what FDlaw throws", kKinds},
             &ThrowerSdk::kind,
             0.0,
             1.0},
        };
        return t;
    }
    bool inherit(const PropBlock&) { return true; }
    void fdlaw(FdBlock& fd) {
        if (fd.u_n > 0.0) {
            if (kind == 1.0) throw 42;
            throw std::runtime_error("thrower_sdk: deliberate failure at overlap " +
                                     std::to_string(fd.u_n));
        }
        fd.n_force = fd.s_force = fd.moment = 0.0;
        fd.knest = fd.ksest = fd.krest = 0.0;
    }
    void saveRestoreState(ModelSaveObject&) {}
    int32_t Version() const override { return 1; }
    double KnEstimate() const override { return 0.0; }
    double KsEstimate() const override { return 0.0; }
    double ContactDuration(double, double) const override { return HUGE_VAL; }
};
using Model = ThrowerSdk;

#else

/// Everything by hand, as a PFC UDM port without the SDK might look.
class ThrowerRaw final : public ContactModel {
public:
    const char* Name() const override { return "thrower_raw"; }
    const char* PropNames() const override { return ""; }
    int32_t PropCount() const override { return 0; }
    const PropInfo* PropInfoAt(int32_t) const override { return nullptr; }
    double ReturnProp(int32_t) const override { return std::nan(""); }
    int32_t AcceptProp(int32_t, double) override { return 1; }
    int32_t Version() const override { return 1; }
    const char* LastError() const override { return "thrower_raw has no properties"; }
    std::size_t ObjectSize() const override { return sizeof(ThrowerRaw); }
    ContactModel* Clone(const PropBlock&, void* storage) const override {
        return new (storage) ThrowerRaw(*this);
    }
    void Destroy() override { this->~ThrowerRaw(); }
    ContactModel* MoveTo(void* storage) override {
        auto* moved = new (storage) ThrowerRaw(*this);
        this->~ThrowerRaw();
        return moved;
    }
    const char* PreCycle(const PropBlock&) override { return nullptr; }
    void FDlaw(FdBlock& fd) override {
        if (fd.u_n > 0.0)
            throw std::runtime_error("thrower_raw: deliberate failure at overlap " +
                                     std::to_string(fd.u_n));
        fd.n_force = fd.s_force = fd.moment = 0.0;
        fd.knest = fd.ksest = fd.krest = 0.0;
    }
    double KnEstimate() const override { return 0.0; }
    double KsEstimate() const override { return 0.0; }
    double ContactDuration(double, double) const override { return HUGE_VAL; }
    double ActivityDistance() const override { return 0.0; }
    bool OKToDelete() const override { return true; }
    void SaveRestore(ModelSaveObject&) override {}
    uint32_t Traits() const override { return 1u; }
};
using Model = ThrowerRaw;

#endif

ContactModel* createPrototype(int32_t index) { return index == 0 ? new Model() : nullptr; }
void destroyPrototype(ContactModel* p) { delete static_cast<Model*>(p); }

const PluginInfo kInfo = TALUS_PLUGIN_INFO_INIT("0.0.1-test", 1, createPrototype, destroyPrototype);

}  // namespace

TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }
