// SPDX-License-Identifier: MIT
//
// `null`: the plugin template. A contact model that exerts no force at all, written out in full
// so that a plugin author can copy this folder, rename the model and fill in a law.
// docs/plugin-guide.md walks through that; docs/plugin-abi.md is the contract in detail.
//
// What a null model is for. Contacts with `null` exist (the engine detects them, they count, they
// carry the model's properties and per-contact state) but the bodies pass through each other, as
// with PFC's null model. It is also the smallest complete example of the ABI: every
// ContactModel method appears below with what the host expects of it.
//
// The frame, once (docs/plugin-abi.md, "FdBlock"): n is the unit normal from end 1 to end 2 and
// t = (-n_y, n_x). u_n is the overlap (+) or gap (-), u_dot_n its rate (+ while approaching), and
// the forces the model returns act on end 2 (end 1 gets the opposite): F = n_force n + s_force t,
// n_force > 0 in compression. A wall is always end 2. All quantities are SI.
//
// How the file is organised. talus::sdk::ModelBase<Null> writes the boilerplate (property access
// from the table, range checks, placement Clone/Destroy, SaveRestore of the properties, the
// exception barrier around FDlaw). The model itself provides the table, fdlaw(), inherit() and
// saveRestoreState(), and the estimates. The methods ModelBase implements are nevertheless
// overridden below, each forwarding to ModelBase, so that the whole interface can be read in one
// place; a real model can delete every forwarding override it does not change.
#include <cmath>

#include "talus/contact_model.hpp"
#include "talus/sdk/model_base.hpp"
// The SDK's helpers most laws need (the null law uses none of them): springEnergy and the
// shear spring with its Coulomb limit (shear_spring.hpp), the viscous dashpot (dashpot.hpp),
// PFC's linear law to build on (linear_law.hpp). Remove what your model does not use.
#include "talus/sdk/dashpot.hpp"
#include "talus/sdk/shear_spring.hpp"

namespace {

using namespace talus;
using namespace talus::sdk;

class Null final : public ModelBase<Null> {
    using Base = ModelBase<Null>;

public:
    /// The model's name: what scripts write in contact_model("null", {...}) and what the registry
    /// looks up (case-insensitively). When looked up by name and not yet loaded, the library is
    /// searched for as libtalus_<lower-case name>.so, which talus_add_plugin(<name>) produces.
    /// It must be unique among all loaded libraries.
    static constexpr const char* kName = "null";

    // ------------------------------------------------------------------ properties and state
    // Every value a script can read or set is a `double` member listed in Table(). ModelBase
    // copies the whole object into each contact (Clone), so the prototype's values are the
    // defaults of new contacts. Per-contact state lives here too, never in a `static` or a global:
    // a static would be shared by every contact of the model (the defect of the power-function
    // UDM of An 2006) and would race when contacts are cycled in parallel.

    /// A value the law ignores; it shows a settable property, and the host's routes for it
    /// (rule properties, contact:prop / contact:set). [-]
    double user = 0.0;
    /// Number of FDlaw calls this contact received since it became active. Read-only per-contact
    /// state, saved by SaveRestore. [-]
    double calls = 0.0;

    /// The property table, in index order (the index is what ReturnProp/AcceptProp receive).
    /// Names are lower case; use PFC's names where PFC has one (kn, ks, fric, dp_nratio, ...).
    /// Strings must outlive the library's use (string literals do). Flags:
    ///   kPropReadOnly     AcceptProp refuses it (computed values and state)
    ///   kPropState        changes while cycling (the host does not cache it)
    ///   kPropInheritable  may come from the ends' kn/ks/fric (see inherit())
    ///   kPropInteger      integer-valued mode; give enum_names for the error text
    /// The trailing fields are the valid range [lo, hi] that AcceptProp and PreCycle enforce.
    static const PropTable<Null>& Table() {
        static const PropTable<Null> t = {
            {{"user", "-", 0, 0.0, "free value carried by the contact, ignored by the law",
              nullptr},
             &Null::user},
            {{"calls", "-", kPropReadOnly | kPropState, 0.0,
              "FDlaw calls since the contact became active", nullptr},
             &Null::calls},
        };
        return t;
    }

    // ------------------------------------------------------------------ hooks ModelBase calls

    /// Called by Clone on the new per-contact copy, with the properties of the two ends
    /// (PropBlock: kn/ks/fric defined on each end, NaN where not set; radii, masses, the
    /// effective mass and the type of end 2). Set per-contact values here: inherited stiffness
    /// (sdk::inheritSeries), friction (sdk::inheritMin), dashpot coefficients from pb.mass_eff.
    /// Return false after fail("why") to refuse the contact; the host then stops with an error
    /// naming the model and the contact. The null model inherits nothing.
    bool inherit(const PropBlock& /*pb*/) { return true; }

    /// The force-displacement law, called once per step for every active contact, after the host
    /// filled `fd` (docs/plugin-abi.md "FdBlock" lists every field). Contract:
    ///  * inputs: u_n, u_dot_n, u_dot_s, t_dot_rel, du_n, du_s, dtheta, tdel, mass_eff, time;
    ///    kFdFirstCall in flags on the first call of this contact; kFdEnergyOn when tracing.
    ///  * in/out: n_force, s_force, moment hold the previous step's values on entry (incremental
    ///    laws update them); on return they are this step's forces on end 2.
    ///  * out: knest, ksest, krest, the current *tangent* stiffnesses (raised for dashpots) that
    ///    the automatic time step uses; written at every call. Zero means "no stiffness".
    ///  * out: energy[] only when kFdEnergyOn is set: stored partitions (strain, bond strain) as
    ///    the current value, accumulated ones (slip, dashpot, plastic) as this step's increment.
    ///  * out: flags kFdSliding, kFdBonded, kFdBroken (+ break_mode), kFdKeep.
    ///  * errors: set status != 0 and error (text the model owns) -- or throw: ModelBase turns an
    ///    exception into status/error before it reaches the host.
    /// The null model writes its outputs as zeros and touches no other field.
    void fdlaw(FdBlock& fd) {
        calls += 1.0;
        fd.n_force = 0.0;
        fd.s_force = 0.0;
        fd.moment = 0.0;
        fd.knest = 0.0;
        fd.ksest = 0.0;
        fd.krest = 0.0;
        if (fd.flags & kFdEnergyOn) fd.energy[kEnergyStrain] = 0.0;  // stored: current value
        // Accumulated partitions (slip, dashpot, plastic) are increments; the host zeroes them
        // before the call, so a model that dissipates nothing leaves them alone.
    }

    /// Per-contact state for SaveRestore, after ModelBase has saved/restored the settable
    /// properties. One call per value, in the same order when saving and restoring; read
    /// so.DataVersion() to restore data written by an older Version() of the model.
    void saveRestoreState(ModelSaveObject& so) { so.Double(calls); }

    /// Called after a property changed (AcceptProp) and after a restore: recompute here whatever
    /// the model caches from its properties (a dashpot coefficient, a stiffness ratio), so that
    /// a contact:set or a restored contact never runs on stale values. Optional.
    void onPropChanged() {}

    // ------------------------------------------------------------------ identity and properties
    // (ModelBase implements these from kName and Table(); shown for reference.)

    /// kName. The pointer must stay valid while the library is loaded.
    const char* Name() const override { return Base::Name(); }
    /// Comma-separated property names in index order, PFC style: "user,calls".
    const char* PropNames() const override { return Base::PropNames(); }
    /// Number of properties (entries of Table()).
    int32_t PropCount() const override { return Base::PropCount(); }
    /// Metadata of property `index` (name, units, flags, default, description); nullptr when
    /// out of range. The host reads it to find properties by name and to document them.
    const PropInfo* PropInfoAt(int32_t index) const override { return Base::PropInfoAt(index); }
    /// Current value of property `index` (NaN when out of range). Called on the prototype and on
    /// per-contact objects, between cycles and from callbacks; must not change anything.
    double ReturnProp(int32_t index) const override { return Base::ReturnProp(index); }
    /// Sets property `index`. Returns 0, or non-zero with LastError() saying why (read-only,
    /// out of range, not an integer). Called on prototypes (rule properties) and on contacts.
    int32_t AcceptProp(int32_t index, double value) override {
        return Base::AcceptProp(index, value);
    }
    /// Version of this model's SaveRestore data layout. Raise it whenever saveRestoreState or
    /// the table of settable properties changes; SaveRestore then sees the old number in
    /// so.DataVersion() when it restores an older save.
    int32_t Version() const override { return 1; }
    /// Text of the last failure of AcceptProp, Clone or PreCycle (per thread, owned by the
    /// library; valid until the next failure on the same thread).
    const char* LastError() const override { return Base::LastError(); }

    // ------------------------------------------------------------------ lifecycle
    // The library creates one prototype per rule (create_prototype, with `new`); the host sets
    // its properties and calls PreCycle. For every pair of bodies that may touch, the host asks
    // the prototype for a per-contact copy *in storage it owns* (a pool): Clone(pb, storage).
    // When the contact separates (and OKToDelete()), the object is destroyed in place and a
    // fresh clone replaces it, so the next touch starts from a fresh state. Destroy never frees.

    /// Bytes the host reserves for a per-contact object: sizeof the most derived class.
    std::size_t ObjectSize() const override { return Base::ObjectSize(); }
    /// Placement-constructs a copy of this prototype in `storage` (ObjectSize() bytes, aligned
    /// to alignof(std::max_align_t)) and calls inherit(pb). nullptr on failure, with the reason
    /// in LastError() of the prototype.
    ContactModel* Clone(const PropBlock& pb, void* storage) const override {
        return Base::Clone(pb, storage);
    }
    /// Runs the destructor in place; the host releases the storage afterwards.
    void Destroy() override { Base::Destroy(); }

    // ------------------------------------------------------------------ cycling

    /// Validates the prototype before every run (cycle/solve) and when a rule is set: returns
    /// nullptr when fine, else an error text the library owns. ModelBase checks every settable
    /// property against its range; add cross-property checks here (e.g. ks <= kn).
    const char* PreCycle(const PropBlock& pb) override { return Base::PreCycle(pb); }
    /// The exception barrier: calls fdlaw() and turns anything it throws into fd.status = 1 with
    /// the exception's text in fd.error. A model written without ModelBase must do the same.
    void FDlaw(FdBlock& fd) override { Base::FDlaw(fd); }

    /// Stiffness at first touch [N/m] (for a contact object before its first FDlaw, and for the
    /// approach rule of the time step). Tangent value, raised for dashpots like knest; 0 = none.
    double KnEstimate() const override { return 0.0; }
    /// Shear counterpart of KnEstimate [N/m].
    double KsEstimate() const override { return 0.0; }
    /// Expected duration of an impact with this effective mass [kg] and approach speed [m/s],
    /// in seconds; the resolution rule of the automatic time step divides it by the steps per
    /// impact (30 by default) before the contact exists. A linear spring: pi sqrt(m / kn); a
    /// Hertzian law depends on the speed. No force, no impact: infinity (no limit).
    double ContactDuration(double /*mass_eff*/, double /*approach_speed*/) const override {
        return HUGE_VAL;
    }
    /// Gap [m] within which a pair is an active contact and FDlaw is called (> 0 for laws with
    /// attraction or a bond formed before touch). 0: from the moment the bodies touch.
    double ActivityDistance() const override { return Base::ActivityDistance(); }
    /// Whether a separated contact may be deleted (replaced by a fresh clone). Return false while
    /// the contact must persist, e.g. while a bond holds; FdBlock's kFdKeep does the same for
    /// one step.
    bool OKToDelete() const override { return Base::OKToDelete(); }
    /// Saves (so.IsSaving()) or restores the object, value by value, in the same order both ways
    /// (ModelBase: the settable properties, then saveRestoreState()). A save taken mid-run and
    /// restored into a fresh clone must continue bit for bit like the run that was not saved.
    void SaveRestore(ModelSaveObject& so) override { Base::SaveRestore(so); }
    /// Bit 0 set: FDlaw may run concurrently on different contacts of this model. True when all
    /// mutable state is per contact (as here). Clear it if the model writes anything shared
    /// (a file, a cache, a counter); the host then cycles its contacts serially.
    uint32_t Traits() const override { return Base::Traits(); }
};

// ---------------------------------------------------------------------- the library's entry
// One library may offer several models: create_prototype(index) for 0 <= index < model_count.
// The host destroys prototypes through destroy_prototype, so `new` and `delete` both happen in
// this library (never across the boundary).

ContactModel* createPrototype(int32_t index) { return index == 0 ? new Null() : nullptr; }
void destroyPrototype(ContactModel* prototype) { delete static_cast<Null*>(prototype); }

// TALUS_PLUGIN_INFO_INIT fills the ABI version, the struct sizes, the dimension and the build
// key from the headers this file was compiled with; the host refuses the library when any of
// them differs from its own. "1.0.0" is this plugin's own version (free text, shown in errors).
const PluginInfo kInfo = TALUS_PLUGIN_INFO_INIT("1.0.0", 1, createPrototype, destroyPrototype);

}  // namespace

/// The one symbol the library must export. The host calls it once, right after dlopen.
TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info() { return &kInfo; }

/// Optional (ABI 1.1, docs/plugin-abi.md "Batched FDlaw"): the batched law of model `index`, or
/// nullptr. The host may then call it over many contacts at once instead of FDlaw per contact;
/// it must give the same bits, which ModelBase's BatchFDlaw does by running the model's own
/// fdlaw on each contact without a virtual call. Delete this function and the host calls FDlaw.
TALUS_PLUGIN_EXPORT talus::BatchFdLawFn talus_plugin_batch(int32_t index) {
    return index == 0 ? &Null::BatchFDlaw : nullptr;
}
