// SPDX-License-Identifier: MIT
//
// The Talus contact-model plugin ABI. This is the only header a contact-model plugin needs.
//
// Design note
// -----------
// The names mirror the PFC2D 3.x user-defined model (UDM) interface on purpose, so that a PFC UDM
// ports with small edits: FdBlock, PropBlock, ModelSaveObject and class ContactModel with Name,
// PropNames, Clone, ReturnProp, AcceptProp, KnEstimate, KsEstimate, Version, PreCycle, FDlaw and
// SaveRestore. What we added, and why:
//
//  * One extern "C" entry point per library (talus_plugin_info) returning a plain struct with the
//    ABI version, the sizes of the ABI structs, the dimension and a build key. The host refuses a
//    library whose numbers differ from its own, with a message naming the file and both values.
//  * Only PODs, `const char*` and the ContactModel / ModelSaveObject vtables cross the boundary.
//    Nothing is ever `dynamic_cast` across it; the plugin destroys what it creates.
//  * Per-contact objects are constructed by Clone *into storage the host provides* (pooled,
//    ObjectSize() bytes), and destroyed in place by Destroy().
//  * FdBlock carries increments, the effective mass (for dashpots), a rotational stiffness
//    estimate and energy outputs, so that later features need no ABI break.
//  * Sign conventions are chosen so that no quantity changes sign between input and state:
//    u_n is the overlap (+) and u_dot_n its rate (+ while approaching). See docs/plugin-abi.md.
//
// Exceptions: a model should not throw. It reports a failure by setting FdBlock::status and
// FdBlock::error. The host nevertheless catches anything that escapes and turns it into an error
// naming the model and the contact.
#pragma once

#include <cstddef>
#include <cstdint>

#define TALUS_ABI_MAJOR 1
#define TALUS_ABI_MINOR 3
#define TALUS_DIM 2

#if defined(__GNUC__) || defined(__clang__)
#define TALUS_PLUGIN_EXPORT extern "C" __attribute__((visibility("default")))
#else
#define TALUS_PLUGIN_EXPORT extern "C"
#endif

// The build key names the things that must agree for C++ vtables and layouts to be compatible:
// compiler family, the libstdc++ string/list ABI, pointer size and byte order.
#define TALUS_STR_(x) #x
#define TALUS_STR(x) TALUS_STR_(x)
#if defined(__clang__)
#define TALUS_COMPILER_FAMILY "itanium-clang"
#elif defined(__GNUC__)
#define TALUS_COMPILER_FAMILY "itanium-gcc"
#else
#define TALUS_COMPILER_FAMILY "unknown"
#endif
#if defined(_GLIBCXX_USE_CXX11_ABI)
#define TALUS_CXXABI "cxx11abi=" TALUS_STR(_GLIBCXX_USE_CXX11_ABI)
#else
#define TALUS_CXXABI "cxx11abi=na"
#endif
#define TALUS_BUILD_KEY                                                                        \
    TALUS_COMPILER_FAMILY "|" TALUS_CXXABI "|ptr" TALUS_STR(__SIZEOF_POINTER__) "|" TALUS_STR( \
        __BYTE_ORDER__) "|abi" TALUS_STR(TALUS_ABI_MAJOR)

namespace talus {

/// Energy partitions a model may report (PFC names: energy-strain, -slip, -dashpot, -pbstrain;
/// plastic work is Talus's own partition for elastic-plastic laws such as `power`).
/// Stored partitions are state (the model writes the current value); accumulated partitions are
/// increments over this step (the model writes the increment; the host accumulates).
enum EnergyPartition : int32_t {
    kEnergyStrain = 0,      ///< stored: recoverable elastic energy of the contact [J]
    kEnergySlip = 1,        ///< accumulated: frictional work, >= 0 [J]
    kEnergyDashpot = 2,     ///< accumulated: viscous work, >= 0 [J]
    kEnergyPlastic = 3,     ///< accumulated: plastic work, >= 0 [J]
    kEnergyBondStrain = 4,  ///< stored: elastic energy in a bond [J]
    kEnergyReleased = 5,    ///< accumulated: stored energy lost when a bond broke this step [J]
    kEnergyCount = 6
};

/// Type of a contact's second end. A wall is always end 2.
enum EndType : int32_t { kEndBall = 0, kEndWall = 1 };

/// FdBlock::flags bits.
enum FdFlags : uint32_t {
    kFdFirstCall = 1u << 0,  ///< in: first FDlaw of this contact (it just became active)
    kFdEnergyOn = 1u << 1,   ///< in: energy tracing is on; write FdBlock::energy
    /// in, with kFdFirstCall: the bond of this pair (the same two bodies) broke or was removed
    /// earlier; a model that bonds contacts by itself on touch (cbond's cb_bond) must not bond
    /// it again. A bond installed by the host (`bonded` = 1) is not affected.
    kFdNoAutoBond = 1u << 2,
    kFdSliding = 1u << 8,  ///< out: the contact slid this step (PFC bSliding)
    kFdBonded = 1u << 9,   ///< out: a bond is present (reported by contact queries)
    kFdBroken = 1u << 10,  ///< out: a bond broke this step (raises a bond_break event)
    kFdKeep = 1u << 11,    ///< out: do not delete this contact even when separated
    /// out, with kFdBroken: FdBlock::reserved[0] and [1] hold the bond's peak normal stress
    /// (tension +) and shear stress at failure [Pa] (the bond_break event's sigma and tau).
    kFdBreakStress = 1u << 12,
    /// out, lane laws only (LaneBatch::flags_out): this contact's step was not done and its
    /// state is untouched; the host runs FDlaw on it instead (ABI 1.2, "Lanes").
    kFdLaneDeclined = 1u << 13,
};

/// Bits of ContactModel::Traits().
enum ModelTraits : uint32_t {
    kTraitThreadSafe = 1u << 0,  ///< FDlaw may run concurrently on different contacts
    /// The model is a bond: `m:bond{}` may install it at existing contacts and near-contacts,
    /// and its contacts persist while bonded (OKToDelete false). A contact that re-forms after
    /// its bond broke and it separated gets the ordinary contact-model rules, never the bond.
    kTraitBond = 1u << 1,
};

/// Bond-break modes written to FdBlock::break_mode together with kFdBroken.
enum BreakMode : int32_t { kBreakNone = 0, kBreakTension = 1, kBreakShear = 2 };

/// Per-contact exchange block, filled by the host before every FDlaw call.
/// Frame: n is the unit normal from end 1 to end 2; t = (-n_y, n_x). Forces are those acting on
/// end 2 (end 1 receives the opposite): F = n_force * n + s_force * t. Moments act on end 2.
struct FdBlock {
    uint32_t size;     ///< sizeof(FdBlock) as the host sees it
    uint32_t version;  ///< TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR
    uint32_t flags;    ///< FdFlags
    int32_t status;    ///< out: 0 = ok; non-zero stops the run with `error`

    // --- in: kinematics at this step (positions at t, velocities at t - dt/2)
    double u_n;        ///< overlap (+) or gap (-) [m]
    double u_dot_n;    ///< rate of overlap, + while approaching [m/s]
    double u_dot_s;    ///< relative shear velocity of end 2 w.r.t. end 1 along t [m/s]
    double t_dot_rel;  ///< relative angular velocity, end 2 minus end 1 [rad/s]
    double tdel;       ///< time step [s]
    double du_n;       ///< overlap increment this step, u_dot_n * tdel [m]
    double du_s;       ///< shear displacement increment, u_dot_s * tdel [m]
    double dtheta;     ///< relative rotation increment, t_dot_rel * tdel [rad]
    double mass_eff;   ///< effective inertial mass m1 m2 / (m1 + m2), or m1 for a wall [kg]
    /// Inverse effective mass for relative motion along t at the contact point, rotation
    /// included: 1/m1 + r1^2/I1 (+ 1/m2 + r2^2/I2), r the centre-to-contact distance [1/kg].
    /// (For a rolling disk on a wall this is 3/m: the tangential motion is three times as
    /// mobile as the normal one; a shear dashpot integrated implicitly needs it.)
    double inv_mass_eff_s;
    double time;  ///< simulated time at this step [s]

    // --- in/out: contact forces (previous values on entry)
    double n_force;  ///< normal force, compression positive [N]
    double s_force;  ///< shear force along t [N]
    double moment;   ///< moment on end 2 (bonds, rolling resistance) [N m]

    // --- out: stiffness estimates for the time step (current tangent values, raised for
    // dashpots), refreshed at every FDlaw
    double knest;  ///< normal [N/m]
    double ksest;  ///< shear [N/m]
    double krest;  ///< rotational [N m/rad]

    // --- out: energies (only when kFdEnergyOn is set); see EnergyPartition
    double energy[kEnergyCount];

    // --- out: events and errors
    int32_t break_mode;  ///< BreakMode, with kFdBroken
    int32_t reserved0;
    const char* error;  ///< out: message when status != 0 (model-owned storage)
    double reserved[3];
};

/// Properties of the two ends, handed to Clone and PreCycle. A property an end does not define
/// is NaN ("not set"); models inherit as PFC does (springs in series, friction minimum).
struct PropBlock {
    uint32_t size;      ///< sizeof(PropBlock) as the host sees it
    uint32_t version;   ///< TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR
    int32_t end2_type;  ///< EndType
    int32_t reserved0;
    double kn[2];      ///< normal stiffness defined on end 1 / end 2 [N/m], NaN if not set
    double ks[2];      ///< shear stiffness [N/m], NaN if not set
    double fric[2];    ///< friction coefficient [-], NaN if not set
    double radius[2];  ///< radius of end 1 / end 2 [m]; 0 for a wall
    double mass[2];    ///< mass of end 1 / end 2 [kg]; 0 for a wall (infinite)
    double mass_eff;   ///< effective inertial mass [kg]
    double reserved[6];
};

/// Property flags for PropInfo::flags.
enum PropFlags : uint32_t {
    kPropReadOnly = 1u << 0,     ///< computed or state; AcceptProp refuses it
    kPropState = 1u << 1,        ///< per-contact state (changes while cycling)
    kPropInheritable = 1u << 2,  ///< may come from the ends (kn, ks, fric)
    kPropInteger = 1u << 3,      ///< integer-valued (modes); see enum_names
};

/// Describes one property. Strings are owned by the plugin and live as long as the library.
struct PropInfo {
    const char* name;               ///< PFC name where PFC has one (kn, ks, fric, dp_nratio, ...)
    const char* units;              ///< SI units, "-" if dimensionless
    uint32_t flags;                 ///< PropFlags
    double default_value;           ///< value of a freshly constructed prototype
    const char* description;        ///< one line
    const char* const* enum_names;  ///< for integer modes: names of 0, 1, ..., nullptr-ended
};

/// Symmetric save/restore stream (PFC ModelSaveObject). The same SaveRestore function saves when
/// IsSaving() and restores otherwise; each call reads or writes one typed value in place.
class ModelSaveObject {
public:
    virtual bool IsSaving() const = 0;
    /// Version() of the model that wrote the data (on restore), or of this model (on save).
    virtual int32_t DataVersion() const = 0;
    virtual void Double(double& value) = 0;
    virtual void Int(int32_t& value) = 0;
    virtual void Bool(bool& value) = 0;

protected:
    ~ModelSaveObject() = default;
};

/// The contact model. A library exposes prototypes; the host clones one object per contact.
class ContactModel {
public:
    // --- identity and properties (PFC names)
    virtual const char* Name() const = 0;
    /// Comma-separated property names in index order (PFC style).
    virtual const char* PropNames() const = 0;
    virtual int32_t PropCount() const = 0;
    virtual const PropInfo* PropInfoAt(int32_t index) const = 0;
    virtual double ReturnProp(int32_t index) const = 0;
    /// Sets a property. Returns 0, or non-zero with LastError() telling why (range, read-only).
    virtual int32_t AcceptProp(int32_t index, double value) = 0;
    /// Version of this model's data layout (SaveRestore); raise it when state changes.
    virtual int32_t Version() const = 0;
    /// Text of the last failure of AcceptProp, Clone or PreCycle.
    virtual const char* LastError() const = 0;

    // --- lifecycle: per-contact objects are built in host-provided storage
    virtual std::size_t ObjectSize() const = 0;
    /// Constructs a per-contact copy of this prototype in `storage` (ObjectSize() bytes, aligned
    /// to alignof(std::max_align_t)), inheriting properties from the ends in `pb`. Returns
    /// nullptr on failure (LastError() of the prototype says why).
    virtual ContactModel* Clone(const PropBlock& pb, void* storage) const = 0;
    /// Destroys an object made by Clone, in place (the host frees the storage).
    virtual void Destroy() = 0;
    /// Moves this per-contact object, state and all, into `storage` (ObjectSize() bytes) and
    /// destroys it here; returns the object at its new place. The host uses it to keep contact
    /// objects in the order it visits them (memory locality), so it must be cheap and exact.
    virtual ContactModel* MoveTo(void* storage) = 0;

    // --- cycling
    /// Validates the properties before cycling. Returns nullptr if fine, else an error text.
    virtual const char* PreCycle(const PropBlock& pb) = 0;
    /// The force-displacement law.
    virtual void FDlaw(FdBlock& fd) = 0;
    /// Stiffness this contact would have now (at first touch for a prototype) [N/m].
    virtual double KnEstimate() const = 0;
    virtual double KsEstimate() const = 0;
    /// Expected duration of an impact at the given approach speed [s]. Used by the time step's
    /// resolution rule before a contact exists. Linear laws: pi sqrt(m*/kn), speed-independent.
    virtual double ContactDuration(double mass_eff, double approach_speed) const = 0;
    /// Gap within which a contact becomes active [m] (0: on touch).
    virtual double ActivityDistance() const = 0;
    /// False while the contact must persist although separated (for example while bonded).
    virtual bool OKToDelete() const = 0;
    virtual void SaveRestore(ModelSaveObject& so) = 0;
    /// ModelTraits: kTraitThreadSafe (FDlaw may run concurrently on different contacts; the
    /// threaded force loop needs it), kTraitBond.
    virtual uint32_t Traits() const = 0;

protected:
    ~ContactModel() = default;
};

/// What talus_plugin_info() returns. All pointers point to storage owned by the library.
struct PluginInfo {
    uint32_t abi_major;          ///< TALUS_ABI_MAJOR the plugin was built with
    uint32_t abi_minor;          ///< TALUS_ABI_MINOR the plugin was built with
    uint32_t dim;                ///< TALUS_DIM
    uint32_t sizeof_fdblock;     ///< sizeof(FdBlock)
    uint32_t sizeof_propblock;   ///< sizeof(PropBlock)
    uint32_t sizeof_plugininfo;  ///< sizeof(PluginInfo)
    const char* build_key;       ///< TALUS_BUILD_KEY
    const char* plugin_version;  ///< free text, e.g. "1.0.0"
    int32_t model_count;
    /// Creates the prototype of model `index` (0 <= index < model_count) with `new`.
    ContactModel* (*create_prototype)(int32_t index);
    /// Destroys a prototype made by create_prototype (the library's own `delete`).
    void (*destroy_prototype)(ContactModel* prototype);
};

/// The batched force-displacement law (ABI 1.1, optional): the FDlaw of `count` contacts of one
/// model in one call, `models[k]` the contact's object (in host-owned storage, laid out by the
/// model) and `blocks[k]` its FdBlock, filled exactly as for FDlaw. It must do to each pair what
/// FDlaw(blocks[k]) does, bit for bit: the host calls whichever it likes (docs/plugin-abi.md,
/// "Batched FDlaw"). A failure is reported per contact in blocks[k].status / error; nothing may
/// escape as an exception.
using BatchFdLawFn = void (*)(ContactModel* const* models, FdBlock* blocks, int32_t count);

/// One call of a lane law (ABI 1.2, optional; docs/plugin-abi.md, "Lanes"): the steps of `count`
/// contacts of one model. Each contact's state lives in host-owned storage laid out as the model
/// declared it (LaneLaw::state_size doubles, the model's own order): contact k's at
/// state + row[k] * state_size. Its inputs and outputs are arrays over the batch (structure of
/// arrays, `count` entries each), meaning what the FdBlock fields of the same names mean; the
/// increments are theirs times tdel (du_n = u_dot_n[k] * tdel, as the host computes them for
/// FdBlock).
struct LaneBatch {
    uint32_t size;   ///< sizeof(LaneBatch) as the host sees it
    uint32_t flags;  ///< in: kFdEnergyOn, as FdBlock::flags (never kFdFirstCall)
    int32_t count;   ///< contacts in this call
    int32_t reserved0;
    double tdel;          ///< time step [s]
    double time;          ///< simulated time at this step [s]
    double* state;        ///< the rows of the model's contacts
    const uint32_t* row;  ///< row[k]: contact k's row
    // --- in
    const double* u_n;
    const double* u_dot_n;
    const double* u_dot_s;
    const double* t_dot_rel;
    const double* mass_eff;
    const double* inv_mass_eff_s;
    // --- in: the contact's forces of the last step; out: this step's
    double* n_force;
    double* s_force;
    double* moment;
    // --- out
    double* knest;
    double* ksest;
    double* krest;
    uint32_t* flags_out;           ///< kFdSliding, kFdBonded, kFdKeep, kFdLaneDeclined
    double* energy[kEnergyCount];  ///< with kFdEnergyOn: as FdBlock::energy
};

/// A model's lane law (ABI 1.2, optional): the per-contact state of its touching contacts in
/// storage the host owns, and its law over many contacts per call. A contact enters the lanes
/// when `pack` accepts it after an FDlaw; from then on its row holds its state and its object is
/// out of date until the host calls `unpack` (before anything reads or writes the object, and
/// whenever the contact leaves the lanes). The contract (docs/plugin-abi.md, "Lanes"):
///  * `law` does to contact k exactly what FDlaw would do, to the last bit, or declines it:
///    flags_out[k] = kFdLaneDeclined, its row and outputs untouched (the host then unpacks, runs
///    FDlaw, and offers the contact to `pack` again). A step a LaneBatch cannot carry (a bond
///    break with its stresses, an error) must be declined.
///  * Nothing escapes as an exception; thread safety as for FDlaw.
struct LaneLaw {
    uint32_t size;                   ///< sizeof(LaneLaw) as the plugin sees it
    int32_t state_size;              ///< doubles of state per contact, >= 1
    const char* const* state_names;  ///< `state_size` names (diagnostics), owned by the library
    /// Copies the contact's state from `object` into `row` (state_size doubles); returns 1 if
    /// the contact runs in the lanes from its next step, 0 if not now (then nothing is kept).
    int32_t (*pack)(const ContactModel* object, double* row);
    /// Copies `row` back into `object`, which is up to date afterwards.
    void (*unpack)(ContactModel* object, const double* row);
    void (*law)(const LaneBatch& batch);
};

}  // namespace talus

/// Name of the optional third entry point (ABI 1.2): a library that offers lanes for some of its
/// models exports TALUS_PLUGIN_EXPORT const talus::LaneLaw* talus_plugin_lanes(int32_t index),
/// returning the lane law of model `index` or nullptr.
#define TALUS_PLUGIN_LANES_ENTRY "talus_plugin_lanes"
using TalusPluginLanesFn = const talus::LaneLaw* (*)(int32_t);

/// Name of the optional fourth entry point (ABI 1.3): a library whose model runs one of the SDK's
/// laws on that law's lane rows (talus/sdk/*.hpp names the law with a kernel id, e.g.
/// sdk::LinearLaw::kKernelId) exports TALUS_PLUGIN_EXPORT const char* talus_plugin_kernel(int32_t
/// index), returning the id or nullptr. A host that knows the id runs that law itself inside its
/// force loop, compiled from the same SDK header, on the lane rows the model declared: the same
/// bits as FDlaw, without a call per contact (docs/plugin-abi.md, "Kernels"). A host that does not
/// know it, or a model whose lanes do not match, runs FDlaw.
#define TALUS_PLUGIN_KERNEL_ENTRY "talus_plugin_kernel"
using TalusPluginKernelFn = const char* (*)(int32_t);

/// Name of the optional second entry point: a library that offers a batched law for some of its
/// models exports TALUS_PLUGIN_EXPORT talus::BatchFdLawFn talus_plugin_batch(int32_t index),
/// returning the law of model `index` (the index of PluginInfo::create_prototype) or nullptr.
#define TALUS_PLUGIN_BATCH_ENTRY "talus_plugin_batch"
using TalusPluginBatchFn = talus::BatchFdLawFn (*)(int32_t);

/// Name of the single entry point every plugin library exports.
#define TALUS_PLUGIN_ENTRY "talus_plugin_info"
/// Signature: TALUS_PLUGIN_EXPORT const talus::PluginInfo* talus_plugin_info();
using TalusPluginInfoFn = const talus::PluginInfo* (*)();

/// Fills the fixed fields of a PluginInfo the way the host expects them.
#define TALUS_PLUGIN_INFO_INIT(version_text, count, create_fn, destroy_fn)                      \
    talus::PluginInfo {                                                                         \
        TALUS_ABI_MAJOR, TALUS_ABI_MINOR, TALUS_DIM, sizeof(talus::FdBlock),                    \
            sizeof(talus::PropBlock), sizeof(talus::PluginInfo), TALUS_BUILD_KEY, version_text, \
            count, create_fn, destroy_fn                                                        \
    }
