// SPDX-License-Identifier: MIT
//
// What the wrap_<thing>.cpp files share: the Lua-side state of a model and the functions that
// push and check each userdata type.
//
// Ownership: a model userdata ("talus.Model") owns the C++ Model. Ball, wall, contact and
// history userdata store an id and a pointer to the LuaModel, and keep the model userdata alive
// through their user value, so a ball kept in a variable never outlives its model. Lua functions
// the model calls back are kept in the model userdata's user-value table (not in the registry),
// so a callback that refers to its model does not keep the model alive forever.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <lua.hpp>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "binding.hpp"
#include "crack.hpp"
#include "lua_runtime.hpp"
#include "progress.hpp"
#include "talus/errors.hpp"
#include "talus/model.hpp"

namespace talus::lua {

inline constexpr const char* kModelType = "talus.Model";
inline constexpr const char* kBallType = "talus.Ball";
inline constexpr const char* kWallType = "talus.Wall";
inline constexpr const char* kContactType = "talus.Contact";
inline constexpr const char* kClumpType = "talus.Clump";
inline constexpr const char* kHistoryType = "talus.History";
inline constexpr const char* kTrackerType = "talus.Tracker";

struct LuaModel;

/// One CSV history (m:history{...}): a cycle hook writing one row every `every` steps.
struct History {
    struct Column {
        enum Kind { Time, Step, Dt, Energy, BalanceError, Function };
        std::string name;
        Kind kind = Time;
        double EnergyTotals::*energy = nullptr;  // for Kind::Energy
        std::string group;                       // Energy/BalanceError of one group ("" = all)
        int ref = LUA_NOREF;                     // for Kind::Function (model user-value table)
    };
    std::string path;
    std::FILE* file = nullptr;
    int64_t every = 1;
    std::vector<Column> columns;
    int hook = 0;  // Model cycle-hook handle, 0 once closed
    int64_t rows = 0;
    /// Data rows the file already held when this history opened it (append = true): a save
    /// records base_rows + rows, the rows of the file up to the saved step.
    int64_t base_rows = 0;
    bool writing = false;        // a row is being written (a column function is running)
    bool close_pending = false;  // close() was asked for while writing

    bool open() const { return file != nullptr; }
    /// Writes one row at the model's current state. Throws on a failing column function.
    void writeRow(LuaModel& lm);
    /// Removes the hook and closes the file (deferred to the end of the row when writing).
    /// Throws ScriptError naming the file when the last buffered rows cannot be written.
    void close(LuaModel& lm);
    /// Hands the buffered rows to the system; throws ScriptError naming the file on failure.
    void flush(LuaModel& lm);
    /// Closes without throwing (garbage collection, exit); a failure is printed to stderr.
    void closeQuietly(LuaModel& lm);
    /// After a failed write, flush or close: closes the file and throws naming it.
    [[noreturn]] void fail(LuaModel& lm, const char* what, int err);
};

/// A file output that a cycle hook drives (m:vtk, m:picture; output.hpp): closed with the
/// model. Its userdata ("talus.Output") keeps the model alive and points here.
struct Output {
    virtual ~Output() = default;
    /// Writes one frame of the model now (throws ScriptError / talus::Error naming the file).
    virtual void write(LuaModel& lm) = 0;
    virtual std::string describe() const = 0;            // "vtk series 'out/talus.pvd'"
    virtual std::vector<std::string> files() const = 0;  // every file written, in order
    virtual std::string mainFile() const = 0;            // the .pvd, or the last picture
    /// Pictures: where the model point (x, y) is in the last picture [px from the top left].
    virtual bool pixel(double, double, double&, double&) const { return false; }
    int hook = 0;  // Model cycle-hook handle, 0 when none or closed
    bool open = true;
    int every = 0;  // steps between frames (0: on request only)
    /// Simulated time between frames (0: by steps or on request): a frame at the end of the step
    /// nearest each multiple k * every_time (within half a step of it), at most one per step.
    double every_time = 0.0;
    int64_t next_time_index = 0;  // k of the next multiple of every_time due
    int64_t written = 0;
    std::vector<std::pair<std::string, int>> functions;  // name, ref (model user-value table)
};

/// The Lua side of a model. Lives inside the model userdata (placement new; __gc destroys it).
struct LuaModel {
    std::unique_ptr<Model> model;
    /// The Lua thread that runs callbacks: the one that called the current cycle/solve (a
    /// coroutine may run the model), else the one that created it.
    lua_State* L = nullptr;
    std::vector<std::unique_ptr<History>> histories;
    std::vector<std::unique_ptr<Output>> outputs;  // m:vtk, m:picture (wrap_vtk/wrap_picture)
    /// on_event(kind, fn): every handler runs, in the order of registration.
    struct EventHandler {
        int handle;
        EventKind kind;
        int ref;  // the function (model user-value table)
    };
    std::vector<EventHandler> event_handlers;
    int next_event_handle = 1;
    /// Every bond break of the model as a crack, in the order they happened (crack.hpp).
    std::vector<Crack> cracks;
    int warning_ref = LUA_NOREF;                  // on_warning(fn)
    std::vector<std::pair<int, int>> cycle_refs;  // on_cycle: (hook handle, function ref)
    /// Nesting depth of cycle/solve calls. While the engine runs its hook loop, removing a hook
    /// from it would shift the loop and skip the next hook for that step, so removals are
    /// deferred: the hook is disabled at once and erased when the outermost run returns.
    int running = 0;
    std::vector<int> removed_hooks;
    /// m:ball_by_id's cache: ball id (slot index) -> the ball's handle, refreshed on a miss.
    std::vector<BallId> ball_slots;

    /// Removes a cycle hook (deferred while running, see above).
    void removeHook(int handle);
    bool hookRemoved(int handle) const;
    /// Called when a run call returns: erases the hooks removed during it.
    void finishRun();
    /// Whether a handler of `kind` is registered (m:save notes it).
    bool hasEventHandler(EventKind kind) const;

    ~LuaModel();
    /// Releases everything (histories, then the engine model) and leaves an empty, valid object:
    /// __gc calls this instead of the destructor, so a ball or callback that still reaches the
    /// userdata afterwards (a finalizer at exit) finds `model == nullptr`, not freed memory.
    void close();
    /// Closes every history file.
    void closeHistories();
    /// Flushes every open history file (after each run call, so os.exit loses nothing).
    void flushHistories();
};

/// Sets LuaModel::L for the duration of a run call and restores it afterwards.
class ActiveThread {
public:
    ActiveThread(LuaModel& lm, lua_State* L) : m_lm(lm), m_saved(lm.L) { lm.L = L; }
    ~ActiveThread() { m_lm.L = m_saved; }
    ActiveThread(const ActiveThread&) = delete;
    ActiveThread& operator=(const ActiveThread&) = delete;

private:
    LuaModel& m_lm;
    lua_State* m_saved;
};

// ------------------------------------------------------------------ model (wrap_model.cpp)

/// Pushes a new model userdata owning `model` (talus.model, talus.restore).
void pushNewModel(lua_State* L, std::unique_ptr<Model> model);

/// Runs `step` on lm's model as one run call (m:cycle, m:solve): `L` runs the callbacks, the
/// histories are flushed whatever happens, the outermost call shows the progress line
/// (progress.hpp; `target` gives "time left"), and on Ctrl-C (talus::Interrupted) the
/// interrupt hook runs after the flush, before the error goes on to the caller.
void runModel(lua_State* L, LuaModel& lm, const std::function<void(Model&)>& step,
              const ProgressTarget& target = {});
/// Called when a run call of `lm` stopped on Ctrl-C (after its histories were flushed), with
/// the Interrupted error (beforeStart(): Ctrl-C came between run calls and this one took no
/// step). For `talus run --save-on-interrupt FILE` (main.cpp). Empty = none.
using InterruptHook = std::function<void(lua_State* L, LuaModel& lm, const Interrupted& e)>;
void setInterruptHook(InterruptHook hook);

/// The LuaModel of the model userdata at `index`; throws ScriptError naming `fn` (and hinting
/// at the m:fn(...) method-call syntax) when it is not one.
LuaModel& checkModel(lua_State* L, int index, const char* fn);
/// m:ball_count() and its kin: the number the Model's Count() gives (Name: the method's name).
template <std::size_t (Model::*Count)() const, const char* Name>
int countMethod(lua_State* L) {
    return catchexcept(L, [&] {
        lua_pushinteger(L, static_cast<lua_Integer>((*checkModel(L, 1, Name).model.*Count)()));
        return 1;
    });
}
/// Pushes the model userdata that owns `lm` (it is alive whenever one of its objects is used).
void pushModel(lua_State* L, const LuaModel& lm);
/// Stores the value at `value_index` in the model's user-value table; returns its reference.
int storeRef(lua_State* L, const LuaModel& lm, int value_index);
void pushRef(lua_State* L, const LuaModel& lm, int ref);
void releaseRef(lua_State* L, const LuaModel& lm, int ref);

/// Reads a contact-model property table {kn = 1e8, dp_mode = "no_tension"} for `model_name`.
/// Enum properties accept their names; keys are applied in sorted order (deterministic).
std::vector<PropValue> readProps(lua_State* L, int index, const std::string& model_name,
                                 const std::string& what);
/// Friction coefficients above this are taken for angles in degrees typed by mistake (a
/// coefficient of 2 is a friction angle of 63 degrees; rock joints and rock on rock stay below 1).
inline constexpr double kPlausibleFrictionMax = 2.0;
/// Is property `name` (of a contact model whose metadata is `meta`, or none) a friction
/// coefficient: fric, or a dimensionless *_fric (rr_fric, pb_fric, ...)?
bool isFrictionCoefficient(const std::string& name, const ContactModel* meta);
/// One warning for the friction coefficients among `values` (name, value) that exceed
/// kPlausibleFrictionMax, naming tan(phi); through lm's warning channel (m:on_warning), or on
/// stderr when there is no model (talus.impact). Nothing when all are plausible.
void warnImplausibleFriction(LuaModel* lm, const std::string& what,
                             const std::vector<std::pair<std::string, double>>& values);
/// Throws "<what>: unknown property 'knn' for model 'linear'; did you mean 'kn'? (known: ...)"
/// when `name` (any case) is not a property of the model `meta` (nothing when meta is null).
void checkPropertyName(const ContactModel* meta, const std::string& name, const std::string& what);
/// Pushes {body=, boundary=, ..., balance_error=}.
void pushEnergies(lua_State* L, const EnergyTotals& e);

/// Names of the energy items (EnergyTotals fields) and their members, for histories.
struct EnergyItem {
    const char* name;
    double EnergyTotals::*member;
};
const std::vector<EnergyItem>& energyItems();

// ------------------------------------------------------------------ bodies and contacts

/// Pushes a ball userdata for `id`, keeping the model userdata at `model_index` alive.
void pushBall(lua_State* L, int model_index, BallId id);
void pushWall(lua_State* L, int model_index, WallId id);
void pushContact(lua_State* L, int model_index, ContactKey key);
void pushClump(lua_State* L, int model_index, ClumpId id);  // wrap_clump.cpp

/// The ball at `index` (with its model); nullptr if the value is not a ball.
struct BallRef {
    LuaModel* lm;
    BallId id;
};
BallRef* testBall(lua_State* L, int index);
/// The clump at `index` (with its model); nullptr if the value is not a clump (wrap_clump.cpp).
struct ClumpRef {
    LuaModel* lm;
    ClumpId id;
};
ClumpRef* testClump(lua_State* L, int index);
/// w:servo{...} / w:servo() for wall `id`, options at stack index 2 (wrap_servo.cpp).
int servoWall(lua_State* L, LuaModel& lm, WallId id);

// ------------------------------------------------------------------ body values (wrap_bodies.cpp)

/// Pushes a fixity as the list of its fixed components, {"x", "spin"}.
void pushFixity(lua_State* L, uint8_t fix);
/// Reads a fixity: a list such as {"x", "spin"}, one name, true (all) or false / nil (none).
uint8_t toFixity(lua_State* L, int index, const std::string& what);
/// Pushes a number, or nil for NaN (a contact property that is not set).
void pushOptional(lua_State* L, double v);
/// The `group` or `groups` option (one name or a list; not both).
std::vector<std::string> groupsOption(const Options& o);
/// A handle packed into one Lua integer (index in the high word), for the iterators' lists.
template <class Id>
lua_Integer packId(Id id) {
    return static_cast<lua_Integer>((uint64_t(id.index) << 32) | id.generation);
}
template <class Id>
Id unpackId(lua_Integer v) {
    const auto u = static_cast<uint64_t>(v);
    return Id{static_cast<uint32_t>(u >> 32), static_cast<uint32_t>(u & 0xffffffffu)};
}
/// m:balls{group =}'s group, checked against the model's groups ("" for every body).
std::string iteratorGroup(const Options& o, Model& m);
/// The handles among `ids` of the bodies in `group` (all when ""; groups_of(id) gives a body's
/// groups), packed for pushIterator.
template <class Id, class GroupsOf>
std::vector<lua_Integer> packIds(const std::vector<Id>& ids, const std::string& group,
                                 const GroupsOf& groups_of) {
    std::vector<lua_Integer> out;
    for (const Id id : ids) {
        if (!group.empty()) {
            const std::vector<std::string> g = groups_of(id);
            if (std::find(g.begin(), g.end(), group) == g.end()) continue;
        }
        out.push_back(packId(id));
    }
    return out;
}
/// The body of an iterator made by pushIterator: pushes the next item of its list for which
/// `push` pushes a value (it returns false for an item deleted during the loop).
int iterateIds(lua_State* L, bool (*push)(lua_State* L, LuaModel& lm, lua_Integer item));
/// Pushes the iterator over `items` for the model at index 1: a table callable as the iterator
/// function `next` (a closure over the model, the items and the position; its body calls
/// iterateIds), whose indexing or length is an error naming what to use instead
/// (m:balls()[3] would otherwise say "attempt to index a function value"). `name`: "balls".
void pushIterator(lua_State* L, lua_CFunction next, const std::vector<lua_Integer>& items,
                  const char* name);

// ------------------------------------------------------------------ bindings

/// What each wrap_<thing>.cpp adds to the API (binding.hpp); bindings() (lua_module.cpp) lists
/// them. Adding a thing is its Binding, declared here, and a row in that list.
extern const Binding kModuleBinding;        // lua_module.cpp: load_plugin, models, mkdir, ...
extern const Binding kModelBinding;         // wrap_model.cpp: talus.model, settings, running
extern const Binding kBodiesBinding;        // wrap_bodies.cpp: ball, wall, iterators, counts
extern const Binding kBallBinding;          // wrap_ball.cpp: the ball userdata
extern const Binding kWallBinding;          // wrap_wall.cpp: the wall userdata
extern const Binding kServoBinding;         // wrap_servo.cpp: w:servo's options
extern const Binding kServosBinding;        // wrap_servos.cpp: m:servo and the servo userdata
extern const Binding kContactBinding;       // wrap_contact.cpp: the contact userdata
extern const Binding kContactModelBinding;  // wrap_contact_model.cpp
extern const Binding kTimestepBinding;      // wrap_timestep.cpp: timestep, solve's options
extern const Binding kForceLoopBinding;     // wrap_force_loop.cpp: kernels, threads, sort_interval
extern const Binding kGuardBinding;         // wrap_guard.cpp
extern const Binding kEnergyBinding;        // wrap_energy.cpp
extern const Binding kClumpBinding;         // wrap_clump.cpp: clump methods and userdata
extern const Binding kBondBinding;          // wrap_bond.cpp: bond, unbond
extern const Binding kMeasureBinding;       // wrap_measure.cpp: measure, unbalanced
extern const Binding kHistoryBinding;       // wrap_history.cpp: history and its userdata
extern const Binding kVtkBinding;           // wrap_vtk.cpp: vtk and the output userdata
extern const Binding kPictureBinding;       // wrap_picture.cpp: picture
extern const Binding kSaveBinding;          // wrap_save.cpp: save, talus.restore
extern const Binding kCrackBinding;         // wrap_cracks.cpp: cracks
extern const Binding kTrackerBinding;       // wrap_tracker.cpp: track and the tracker userdata
/// The id of the tracker userdata at `index`, or 0 when the value is not a tracker; `what`
/// names the caller in the error raised for a tracker of another model (wrap_tracker.cpp).
int trackerIdAt(lua_State* L, int index, const LuaModel& lm, const std::string& what);
extern const Binding kBarrierBinding;  // wrap_barrier.cpp: barrier, barriers
extern const Binding kImpactBinding;   // wrap_impact.cpp: talus.impact, talus.drive
extern const Binding kMapBinding;      // wrap_map.cpp: talus.map, rank, ranks

/// Registers the model's metatable: every Binding's model methods (wrap_model.cpp).
void openModel(lua_State* L);

/// Parses the options of m:timestep{...} / impact{timestep = {...}} into `ts`.
void readTimestepOptions(const Options& o, TimestepSettings& ts);
/// The options of m:timestep{...} (wrap_timestep.cpp), also impact's `timestep`.
extern const OptionTable kTimestepOptions;
/// Parses the options of m:guard{...} / impact{guard = {...}} into `g`.
void readGuardOptions(const Options& o, GuardSettings& g);
/// The options of m:guard{...} (wrap_guard.cpp), also impact's `guard`.
extern const OptionTable kGuardOptions;

/// m:solve{...}'s options (wrap_timestep.cpp). `time_only`: only `time` was given, and the run
/// is Model::solveTime as before the other criteria existed. The `until` function stays at
/// its stack slot (the option table's) for the duration of the run.
struct SolveRequest {
    SolveSpec spec;
    bool time_only = false;
};
SolveRequest readSolveOptions(lua_State* L, LuaModel& lm, int index);
/// Lower-case copy of `s` (names compared without case).
std::string lower(std::string s);
/// What m:save does (wrap_save.cpp): flushes the histories and saves the model with the Lua
/// layer's section (histories, output series) to `path` through a temporary file and a rename.
/// Also `talus run --save-on-interrupt FILE` (main.cpp). Throws talus::Error naming the file.
void saveLuaModel(LuaModel& lm, const std::string& path);
/// Re-opens a restored history (wrap_history.cpp): cuts its file back to the header and the
/// h->rows rows written up to the saved step (the saving run may have written more), then
/// appends, a row every `every` steps. Returns a note for the restore's list ("" if none).
std::string reopenHistory(LuaModel& lm, std::unique_ptr<History> h);

}  // namespace talus::lua

/// Opens the `talus` module (registered in package.preload by the CLI).
extern "C" int luaopen_talus(lua_State* L);
