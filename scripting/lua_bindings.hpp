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

#include <cstdint>
#include <cstdio>
#include <functional>
#include <lua.hpp>
#include <memory>
#include <string>
#include <utility>
#include <vector>

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

/// talus.model{...}
int newModel(lua_State* L);
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
/// Pushes the model userdata that owns `lm` (it is alive whenever one of its objects is used).
void pushModel(lua_State* L, const LuaModel& lm);
/// Stores the value at `value_index` in the model's user-value table; returns its reference.
int storeRef(lua_State* L, const LuaModel& lm, int value_index);
void pushRef(lua_State* L, const LuaModel& lm, int ref);
void releaseRef(lua_State* L, const LuaModel& lm, int ref);

/// Parses the options of m:timestep{...} / impact{timestep = {...}} into `ts`.
void readTimestepOptions(const Options& o, TimestepSettings& ts);
/// Parses the options of m:guard{...} / impact{guard = {...}} into `g`.
void readGuardOptions(const Options& o, GuardSettings& g);
/// The option names readGuardOptions understands (for Options' unknown-name check).
const std::vector<std::string>& guardOptionNames();
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

// ------------------------------------------------------------------ open functions

void openModel(lua_State* L);    // wrap_model.cpp: talus.Model metatable
void openBall(lua_State* L);     // wrap_ball.cpp
void openWall(lua_State* L);     // wrap_wall.cpp
void openContact(lua_State* L);  // wrap_contact.cpp
void openClump(lua_State* L);    // wrap_clump.cpp
void openHistory(lua_State* L);  // wrap_history.cpp
void openTracker(lua_State* L);  // wrap_tracker.cpp
void openOutputs(lua_State* L);  // wrap_vtk.cpp: series userdata

// ------------------------------------------------------------------ method tables

/// The model's methods: one table per thing, in its wrap_<thing>.cpp; kModelMethodTables
/// (wrap_model.cpp) lists the tables. Adding a method is a row in its thing's table; adding a
/// thing is its table, declared here, and a row in kModelMethodTables. openModel registers
/// every table and the unknown-method error lists every name in them (modelMethodNames).
extern const luaL_Reg kModelMethods[];         // wrap_model.cpp: settings, running, callbacks
extern const luaL_Reg kModelBodyMethods[];     // wrap_bodies.cpp: ball, wall, iterators, counts
extern const luaL_Reg kContactModelMethods[];  // wrap_contact_model.cpp
extern const luaL_Reg kTimestepMethods[];      // wrap_timestep.cpp
extern const luaL_Reg kForceLoopMethods[];     // wrap_force_loop.cpp: batched_law, threads
extern const luaL_Reg kGuardMethods[];         // wrap_guard.cpp
extern const luaL_Reg kEnergyMethods[];        // wrap_energy.cpp
extern const luaL_Reg kClumpMethods[];         // wrap_clump.cpp: clump, clump_template, clumps
extern const luaL_Reg kBondMethods[];          // wrap_bond.cpp: bond, unbond
extern const luaL_Reg kMeasureMethods[];       // wrap_measure.cpp: measure, unbalanced
extern const luaL_Reg kModelHistoryMethods[];  // wrap_history.cpp: history, close_history
extern const luaL_Reg kVtkMethods[];           // wrap_vtk.cpp: vtk
extern const luaL_Reg kPictureMethods[];       // wrap_picture.cpp: picture
extern const luaL_Reg kSaveMethods[];          // wrap_save.cpp: save
extern const luaL_Reg kCrackMethods[];         // wrap_cracks.cpp: cracks
extern const luaL_Reg kTrackerMethods[];       // wrap_tracker.cpp: track, trackers, clear_trackers
extern const luaL_Reg kServoMethods[];         // wrap_servos.cpp: servo
/// Every model method name in kModelMethodTables, sorted.
std::vector<std::string> modelMethodNames();
/// The `talus` module's functions, one table per thing likewise; kModuleFunctionTables
/// (lua_module.cpp) lists them and luaopen_talus registers every one.
extern const luaL_Reg kImpactFunctions[];  // wrap_impact.cpp: impact, drive
extern const luaL_Reg kMapFunctions[];     // wrap_map.cpp: map, rank, ranks
extern const luaL_Reg kSaveFunctions[];    // wrap_save.cpp: restore

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
