// SPDX-License-Identifier: MIT
// talus.model{...} and the model's methods that drive it: creation, damping, broadphase and
// gravity settings, running, callbacks and profile; the shared helpers (model userdata, refs).
// The other methods are one file per thing (wrap_bodies.cpp: ball, wall, iterators, counts;
// wrap_history.cpp, wrap_vtk.cpp, ...), each in its file's Binding (binding.hpp); openModel
// registers the methods of every Binding.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <new>

#include "lua_bindings.hpp"
#include "solve_watch.hpp"
#include "talus/errors.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/suggest.hpp"

namespace talus::lua {

namespace {

// Registry key of the weak table LuaModel* -> model userdata (see pushModel).
const char kModelsKey = 0;

const Option kModelOptionRows[] = {
    {"gravity", "talus.Vec", "gravitational acceleration [m/s^2] (default {0, 0})"},
    {"mass", "\"disk\"|\"sphere\"",
     "disk: unit-thickness disks (PFC2D, the default); sphere: m = 4/3 rho pi R^3"},
};
const OptionTable kModelOptions = {"talus.ModelDef", "talus.model{...}: a new, empty model",
                                   kModelOptionRows};

const Option kDampingOptionRows[] = {
    {"damp", "number", "PFC's local damping coefficient in [0, 1)"},
    {"local", "number", "the old name of damp"},
    {"viscous", "number", "viscous damping rate [1/s], >= 0"},
};
const OptionTable kDampingOptions = {"talus.DampingOptions", "m:damping{...}", kDampingOptionRows};

const Option kBroadphaseOptionRows[] = {
    {"margin", "number", "how far [m] a body moves before the broadphase looks at it again"},
};
const OptionTable kBroadphaseOptions = {"talus.BroadphaseOptions", "m:broadphase{...}",
                                        kBroadphaseOptionRows};

const Option kProfileOptionRows[] = {
    {"reset", "boolean", "reset the counters after the report"},
    {"enabled", "boolean", "false stops timing"},
};
const OptionTable kProfileOptions = {"talus.ProfileOptions", "m:profile{...}", kProfileOptionRows};

void pushUserValueTable(lua_State* L, const LuaModel& lm) {
    pushModel(L, lm);
    lua_getiuservalue(L, -1, 1);
    lua_remove(L, -2);
}

// ------------------------------------------------------------------ callbacks from the engine

/// Calls the function on the stack below its `nargs` arguments; a Lua error becomes a
/// CallbackError, thrown after the stack is restored to `base`.
void callProtected(lua_State* L, int nargs, int nresults, int base) {
    if (lua_pcall(L, nargs, nresults, 0) != LUA_OK) {
        std::string msg = errorText(L, -1);
        lua_settop(L, base);
        throw CallbackError(msg);
    }
}

void runCycleCallback(LuaModel& lm, int ref) {
    lua_State* L = lm.L;
    const int base = lua_gettop(L);
    pushRef(L, lm, ref);
    pushModel(L, lm);
    lua_pushinteger(L, static_cast<lua_Integer>(lm.model->step()));
    callProtected(L, 2, 0, base);
    lua_settop(L, base);
}

const char* breakModeName(int32_t mode) {
    switch (mode) {
        case kBreakTension:
            return "tension";
        case kBreakShear:
            return "shear";
        default:
            return "none";
    }
}

/// Calls handler `ref` with the event table of `ev` (and of its crack, for a bond break).
void callEventHandler(LuaModel& lm, int ref, const Event& ev, const Crack* crack) {
    lua_State* L = lm.L;
    const int base = lua_gettop(L);
    pushRef(L, lm, ref);
    pushModel(L, lm);
    const int model_index = lua_gettop(L);
    lua_createtable(L, 0, 8);
    setString(L, "kind", ev.kind == EventKind::BondBreak ? "bond_break" : "contact_created");
    setNumber(L, "time", ev.time);
    pushVec(L, ev.pos);
    lua_setfield(L, -2, "pos");
    setString(L, "model", ev.model);
    setString(L, "mode", breakModeName(ev.mode));
    // Stresses at failure, when the bond model reports them (pbond; nil otherwise).
    if (!std::isnan(ev.sigma)) {
        setNumber(L, "sigma", ev.sigma);
        setNumber(L, "tau", ev.tau);
    }
    pushContact(L, model_index, ev.contact);
    lua_setfield(L, -2, "contact");
    if (crack) {
        // The bond as a crack: its ends, its half width and normal, the step (crack.hpp).
        setInteger(L, "step", static_cast<lua_Integer>(crack->step));
        if (lm.model->isAlive(crack->ball1)) {
            pushBall(L, model_index, crack->ball1);
            lua_setfield(L, -2, "ball1");
        }
        if (lm.model->isAlive(crack->ball2)) {
            pushBall(L, model_index, crack->ball2);
            lua_setfield(L, -2, "ball2");
        }
        setNumber(L, "radius", crack->radius);
        pushVec(L, crack->normal);
        lua_setfield(L, -2, "normal");
    }
    lua_remove(L, model_index);
    callProtected(L, 1, 0, base);
    lua_settop(L, base);
}

/// Runs every handler of the event's kind in the order they were registered, each with a table
/// of its own. A handler may add or remove handlers: the ones registered when the event came
/// run, except those removed before their turn.
void deliverEvent(LuaModel& lm, const Event& ev) {
    // A local copy for the handlers: a handler's own cycle may add cracks and move the log.
    Crack crack;
    const bool is_break = ev.kind == EventKind::BondBreak;
    if (is_break) {
        crack = crackOf(*lm.model, ev);
        lm.cracks.push_back(crack);
    }
    std::vector<int> handles;
    for (const auto& h : lm.event_handlers)
        if (h.kind == ev.kind) handles.push_back(h.handle);
    for (int handle : handles) {
        const auto it =
            std::find_if(lm.event_handlers.begin(), lm.event_handlers.end(),
                         [&](const LuaModel::EventHandler& h) { return h.handle == handle; });
        if (it != lm.event_handlers.end())
            callEventHandler(lm, it->ref, ev, is_break ? &crack : nullptr);
    }
}

void deliverWarning(LuaModel& lm, const std::string& text) {
    clearProgressLine();
    if (lm.warning_ref == LUA_NOREF || !lm.L) {
        // Keep the order a user sees on a terminal: what the script printed, then the warning.
        std::fflush(stdout);
        std::cerr << "warning: " << text << std::endl;
        return;
    }
    lua_State* L = lm.L;
    const int base = lua_gettop(L);
    pushRef(L, lm, lm.warning_ref);
    lua_pushstring(L, text.c_str());
    // A failing warning handler must not hide the finding (or an error being reported), so its
    // own error is printed, not raised.
    if (lua_pcall(L, 1, 0, 0) != LUA_OK) {
        std::fflush(stdout);
        std::cerr << "warning: " << text << "\nerror in on_warning handler: " << errorText(L, -1)
                  << std::endl;
    }
    lua_settop(L, base);
}

// ------------------------------------------------------------------ constructor, metamethods

int w_newModel(lua_State* L) {
    return catchexcept(L, [&] {
        const Options o(L, 1, "model", kModelOptions, true);
        ModelDef def;
        def.gravity = o.vec("gravity", Vec2(0.0, 0.0));
        def.mass_mode =
            o.choice("mass", 0, {"disk", "sphere"}) == 0 ? MassMode::Disk : MassMode::Sphere;
        pushNewModel(L, std::make_unique<Model>(def));
        return 1;
    });
}

}  // namespace

void pushNewModel(lua_State* L, std::unique_ptr<Model> model) {
    void* mem = lua_newuserdatauv(L, sizeof(LuaModel), 1);
    LuaModel* lm = new (mem) LuaModel();
    lm->model = std::move(model);
    // Callbacks outside a run call use the main thread, which lives as long as the state
    // (a coroutine that created the model may be collected before the model).
    lua_rawgeti(L, LUA_REGISTRYINDEX, LUA_RIDX_MAINTHREAD);
    lm->L = lua_tothread(L, -1);
    lua_pop(L, 1);
    luaL_setmetatable(L, kModelType);
    lua_newtable(L);
    lua_setiuservalue(L, -2, 1);
    // Register in the weak table so callbacks can find the userdata from the LuaModel.
    lua_rawgetp(L, LUA_REGISTRYINDEX, &kModelsKey);
    lua_pushvalue(L, -2);
    lua_rawsetp(L, -2, lm);
    lua_pop(L, 1);

    lm->model->setWarningHandler([lm](const std::string& text) { deliverWarning(*lm, text); });
    lm->model->setEventHandler([lm](const Event& ev) { deliverEvent(*lm, ev); });
}

namespace {

int w_gc(lua_State* L) {
    auto* lm = static_cast<LuaModel*>(testUserdata(L, 1, kModelType));
    if (lm) lm->close();
    return 0;
}

int w_tostring(lua_State* L) {
    return catchexcept(L, [&] {
        auto* lm = static_cast<LuaModel*>(testUserdata(L, 1, kModelType));
        if (!lm || !lm->model) {
            lua_pushliteral(L, "talus.Model (closed)");
            return 1;
        }
        const Model& m = *lm->model;
        lua_pushfstring(L, "talus.Model (%d balls, %d walls, %d contacts, step %d, t = %f s)",
                        static_cast<int>(m.ballCount()), static_cast<int>(m.wallCount()),
                        static_cast<int>(m.contactCount()), static_cast<int>(m.step()), m.time());
        return 1;
    });
}

// ------------------------------------------------------------------ settings

int w_damping(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "damping");
        // `damp` is PFC's name for local damping; `local` (a Lua keyword, so only ['local'] =)
        // is still accepted for old scripts.
        const Options o(L, 2, "damping", kDampingOptions, true);
        DampingSettings d = lm.model->damping();
        if (o.has("damp") && o.has("local"))
            throw ScriptError("damping: give 'damp' or its old name 'local', not both");
        const char* local_key = o.has("local") ? "local" : "damp";
        d.local = o.number(local_key, d.local);
        d.viscous = o.number("viscous", d.viscous);
        if (!(d.local >= 0.0 && d.local < 1.0))
            throw ScriptError(std::string("damping: '") + local_key + "' must be in [0, 1) (got " +
                              numberText(d.local) + ")");
        if (!(d.viscous >= 0.0) || !std::isfinite(d.viscous))
            throw ScriptError("damping: 'viscous' must be >= 0 [1/s] (got " +
                              numberText(d.viscous) + ")");
        lm.model->damping() = d;
        lua_createtable(L, 0, 3);
        setNumber(L, "damp", d.local);
        setNumber(L, "local", d.local);
        setNumber(L, "viscous", d.viscous);
        return 1;
    });
}

int w_broadphase(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "broadphase");
        const Options o(L, 2, "broadphase", kBroadphaseOptions, true);
        if (o.has("margin")) lm.model->setBroadphaseMargin(o.number("margin", 0.0));
        lua_createtable(L, 0, 1);
        setNumber(L, "margin", lm.model->broadphaseMargin());
        return 1;
    });
}

int w_gravity(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "gravity");
        if (!lua_isnoneornil(L, 2)) {
            const Vec2 g = toVec(L, 2, "gravity");
            if (!std::isfinite(g.x()) || !std::isfinite(g.y()))
                throw ScriptError("gravity: must be finite");
            lm.model->gravity() = g;
        }
        pushVec(L, lm.model->gravity());
        return 1;
    });
}

// ------------------------------------------------------------------ running

// The hook main.cpp sets for `talus run --save-on-interrupt` (setInterruptHook).
InterruptHook& interruptHook() {
    static InterruptHook hook;
    return hook;
}

}  // namespace

void setInterruptHook(InterruptHook hook) { interruptHook() = std::move(hook); }

void runModel(lua_State* L, LuaModel& lm, const std::function<void(Model&)>& step,
              const ProgressTarget& target) {
    ActiveThread active(lm, L);
    ++lm.running;
    // The progress line and the watch on a solve's ratio follow the outermost run call only (a
    // cycle inside an on_cycle callback is part of the step that called it).
    std::unique_ptr<ProgressLine> progress;
    std::unique_ptr<SolveWatch> watch;
    if (lm.running == 1) {
        try {
            if (progressStyle() != ProgressStyle::Off)
                progress = std::make_unique<ProgressLine>(*lm.model, target);
            if (target.ratio > 0) {
                LuaModel* lmp = &lm;
                watch = std::make_unique<SolveWatch>(target.ratio, [lmp](const std::string& text) {
                    if (lmp->model) lmp->model->warn(text);
                });
            }
        } catch (...) {
            --lm.running;
            throw;
        }
    }
    if (progress || watch) {
        ProgressLine* p = progress.get();
        SolveWatch* w = watch.get();
        lm.model->setStepObserver([p, w](const Model& m) {
            if (p) p->update(m);
            if (w) w->update(m);
        });
    }
    const auto finish = [&] {
        if (progress || watch) {
            lm.model->setStepObserver(nullptr);
            progress.reset();
            watch.reset();
        }
        --lm.running;
        lm.finishRun();
    };
    try {
        step(*lm.model);
    } catch (const Interrupted& e) {
        // Ctrl-C: the step is complete. Histories first (they must hold every row up to this
        // step), then the hook (--save-on-interrupt), then the error goes on to the script.
        finish();
        lm.flushHistories();
        if (interruptHook()) interruptHook()(L, lm, e);
        throw;
    } catch (...) {
        finish();
        try {
            lm.flushHistories();
        } catch (const std::exception&) {  // the run's own error comes first
        }
        throw;
    }
    finish();
    lm.flushHistories();
}

namespace {

int w_cycle(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "cycle");
        if (lua_isnoneornil(L, 2)) throw ScriptError("cycle: give the number of steps, m:cycle(n)");
        const long long n = toInteger(L, 2, "cycle: number of steps");
        if (n < 0)
            throw ScriptError("cycle: number of steps must be >= 0 (got " + std::to_string(n) +
                              ")");
        ProgressTarget target;
        target.steps = n;
        runModel(
            L, lm, [&](Model& m) { m.cycle(static_cast<int64_t>(n)); }, target);
        return 0;
    });
}

int w_solve(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "solve");
        const SolveRequest req = readSolveOptions(L, lm, 2);  // wrap_timestep.cpp
        ProgressTarget target;  // the progress line's "time left" (-1: not known)
        if (!std::isnan(req.spec.time)) target.time = req.spec.time;
        if (req.spec.steps >= 0) target.steps = req.spec.steps;
        if (!std::isnan(req.spec.ratio)) target.ratio = req.spec.ratio;
        SolveStop stop = SolveStop::Time;
        try {
            runModel(
                L, lm,
                [&](Model& m) {
                    if (req.time_only)
                        m.solveTime(req.spec.time);
                    else
                        stop = m.solve(req.spec);
                },
                target);
        } catch (const Interrupted& e) {
            // Ctrl-C during the run: the reason is returned. A stop that was pending before
            // the call took a step raises, so `repeat ... until m:solve{...}` cannot spin.
            if (e.beforeStart()) throw;
            stop = SolveStop::Interrupted;
        }
        lua_pushstring(L, solveStopName(stop));
        return 1;
    });
}

int w_time(lua_State* L) {
    return catchexcept(L, [&] {
        lua_pushnumber(L, checkModel(L, 1, "time").model->time());
        return 1;
    });
}

int w_step(lua_State* L) {
    return catchexcept(L, [&] {
        lua_pushinteger(L, static_cast<lua_Integer>(checkModel(L, 1, "step").model->step()));
        return 1;
    });
}

int w_dt(lua_State* L) {
    return catchexcept(L, [&] {
        const Model& m = *checkModel(L, 1, "dt").model;
        lua_pushnumber(L, m.lastTimestep());
        lua_pushstring(L, stepRuleName(m.lastStepRule()));
        return 2;
    });
}

// ------------------------------------------------------------------ callbacks

int w_on_cycle(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "on_cycle");
        if (lua_type(L, 2) != LUA_TFUNCTION)
            throw ScriptError("on_cycle: argument 1 must be a function (got " + typeName(L, 2) +
                              ")");
        long long every = 1;
        if (!lua_isnoneornil(L, 3)) every = toInteger(L, 3, "on_cycle: 'every'");
        if (every < 1)
            throw ScriptError("on_cycle: 'every' must be >= 1 (got " + std::to_string(every) + ")");
        const int ref = storeRef(L, lm, 2);
        LuaModel* lmp = &lm;
        auto handle_cell = std::make_shared<int>(0);  // the hook learns its handle after adding
        const int handle = lm.model->addCycleHook(every, [lmp, ref, handle_cell](Model&) {
            if (!lmp->hookRemoved(*handle_cell)) runCycleCallback(*lmp, ref);
        });
        *handle_cell = handle;
        lm.cycle_refs.emplace_back(handle, ref);
        lua_pushinteger(L, handle);
        return 1;
    });
}

int w_remove_on_cycle(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "remove_on_cycle");
        const long long handle = toInteger(L, 2, "remove_on_cycle: handle");
        for (auto it = lm.cycle_refs.begin(); it != lm.cycle_refs.end(); ++it)
            if (it->first == handle) {
                lm.removeHook(it->first);
                releaseRef(L, lm, it->second);
                lm.cycle_refs.erase(it);
                break;
            }
        return 0;
    });
}

// m:on_event(kind, fn) adds a handler and returns its handle; m:on_event(kind, nil) removes
// every handler of the kind (a library routine removes only its own, by handle).
int w_on_event(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "on_event");
        const int k = toEnum(L, 2, "on_event: event", {"bond_break", "contact_created"});
        const EventKind kind = k == 0 ? EventKind::BondBreak : EventKind::ContactCreated;
        if (!lua_isnil(L, 3) && lua_type(L, 3) != LUA_TFUNCTION)
            throw ScriptError("on_event: argument 2 must be a function or nil (got " +
                              typeName(L, 3) + ")");
        if (lua_isnil(L, 3)) {
            auto& hs = lm.event_handlers;
            for (const auto& h : hs)
                if (h.kind == kind) releaseRef(L, lm, h.ref);
            hs.erase(
                std::remove_if(hs.begin(), hs.end(),
                               [&](const LuaModel::EventHandler& h) { return h.kind == kind; }),
                hs.end());
            return 0;
        }
        const int handle = lm.next_event_handle++;
        lm.event_handlers.push_back({handle, kind, storeRef(L, lm, 3)});
        lua_pushinteger(L, handle);
        return 1;
    });
}

// m:remove_on_event(handle): removes that handler; returns whether there was one.
int w_remove_on_event(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "remove_on_event");
        const long long handle = toInteger(L, 2, "remove_on_event: handle");
        auto& hs = lm.event_handlers;
        const auto it = std::find_if(hs.begin(), hs.end(), [&](const LuaModel::EventHandler& h) {
            return h.handle == handle;
        });
        const bool found = it != hs.end();
        if (found) {
            releaseRef(L, lm, it->ref);
            hs.erase(it);
        }
        lua_pushboolean(L, found);
        return 1;
    });
}

int w_on_warning(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "on_warning");
        if (!lua_isnoneornil(L, 2) && lua_type(L, 2) != LUA_TFUNCTION)
            throw ScriptError("on_warning: argument 1 must be a function or nil (got " +
                              typeName(L, 2) + ")");
        if (lm.warning_ref != LUA_NOREF) releaseRef(L, lm, lm.warning_ref);
        lm.warning_ref = lua_isfunction(L, 2) ? storeRef(L, lm, 2) : LUA_NOREF;
        return 0;
    });
}

int w_profile(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "profile");
        const Options o(L, 2, "profile", kProfileOptions, true);
        Profile& p = lm.model->profile();
        lua_pushstring(L, p.report(lm.model->ballCount()).c_str());
        if (o.has("enabled")) p.enabled = o.boolean("enabled", true);
        if (o.boolean("reset", false)) p.reset();
        return 1;
    });
}

int w_index_unknown(lua_State* L) {
    // __index of the method table's metatable: an unknown method name is an error that lists
    // the known ones (m:cylce(10) would otherwise say "attempt to call a nil value").
    return catchexcept(L, [&]() -> int {
        const std::string key = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : typeName(L, 2);
        const std::vector<std::string> names = modelMethodNames();
        throw ScriptError("model: unknown method or field '" + key + "'" + didYouMean(key, names) +
                          " (known: " + joinNames(names) + ")");
    });
}

// ------------------------------------------------------------------ method tables

/// Methods of this file: settings that are one call (damping, broadphase, gravity), running,
/// callbacks and profile.
const Method kModelMethods[] = {
    {"damping", w_damping, "sets local and viscous damping; returns the settings",
     "options?: talus.DampingOptions", "table"},
    {"broadphase", w_broadphase, "sets the broadphase margin; returns the settings",
     "options?: talus.BroadphaseOptions", "table"},
    {"gravity", w_gravity, "sets the gravitational acceleration [m/s^2]; returns it",
     "g?: talus.Vec", "talus.Vec"},
    {"cycle", w_cycle, "runs n steps", "n: integer", ""},
    {"solve", w_solve,
     "runs until a criterion (time, steps, ratio, until) is met; returns why it stopped",
     "criteria: talus.SolveOptions", "string"},
    {"time", w_time, "the simulated time [s]", "", "number"},
    {"step", w_step, "the number of steps taken", "", "integer"},
    {"dt", w_dt, "the last time step [s] and the rule that set it", "", "number, string"},
    {"on_cycle", w_on_cycle, "calls fn(m, step) every `every` steps; returns a handle",
     "fn: fun(m: talus.Model, step: integer), every?: integer", "integer"},
    {"remove_on_cycle", w_remove_on_cycle, "removes an on_cycle callback by its handle",
     "handle: integer", ""},
    {"on_event", w_on_event,
     "calls fn(ev) at each event of the kind (\"bond_break\"); nil removes them all",
     "kind: \"bond_break\"|\"contact_created\", fn: fun(ev: table)|nil", "integer?"},
    {"remove_on_event", w_remove_on_event,
     "removes an on_event handler by its handle; returns whether there was one", "handle: integer",
     "boolean"},
    {"on_warning", w_on_warning, "engine warnings go to fn(text) instead of stderr; nil restores",
     "fn: fun(text: string)|nil", ""},
    {"profile", w_profile, "the engine's profile report (time per cycle phase)",
     "options?: talus.ProfileOptions", "string"},
};

const Method kModelFunctions[] = {
    {"model", w_newModel, "a new, empty model", "def?: talus.ModelDef", "talus.Model"},
};

const OptionTable* const kOptionTables[] = {&kModelOptions, &kDampingOptions, &kBroadphaseOptions,
                                            &kProfileOptions};

}  // namespace

extern const Binding kModelBinding = {"model", kModelMethods, kModelFunctions,
                                      {},      kOptionTables, {}};

// ------------------------------------------------------------------ shared with other files

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

LuaModel::~LuaModel() { close(); }

void LuaModel::close() {
    closeHistories();
    for (auto& o : outputs) {
        if (model && o->hook) model->removeCycleHook(o->hook);
        o->hook = 0;
        o->open = false;
    }
    std::vector<std::unique_ptr<Output>>().swap(outputs);
    // Free every container's storage: __gc calls close(), never the destructor.
    std::vector<std::unique_ptr<History>>().swap(histories);
    std::vector<std::pair<int, int>>().swap(cycle_refs);
    std::vector<EventHandler>().swap(event_handlers);
    std::vector<Crack>().swap(cracks);
    std::vector<int>().swap(removed_hooks);
    std::vector<BallId>().swap(ball_slots);
    model.reset();
}

void LuaModel::closeHistories() {
    for (auto& h : histories)
        if (h->open()) {
            if (model && h->hook) model->removeCycleHook(h->hook);
            h->hook = 0;
            h->closeQuietly(*this);  // no throwing here (__gc); a failed close goes to stderr
        }
}

void LuaModel::removeHook(int handle) {
    if (!model || handle == 0) return;
    if (running > 0)
        removed_hooks.push_back(handle);
    else
        model->removeCycleHook(handle);
}

bool LuaModel::hasEventHandler(EventKind kind) const {
    return std::any_of(event_handlers.begin(), event_handlers.end(),
                       [&](const EventHandler& h) { return h.kind == kind; });
}

bool LuaModel::hookRemoved(int handle) const {
    return std::find(removed_hooks.begin(), removed_hooks.end(), handle) != removed_hooks.end();
}

void LuaModel::finishRun() {
    if (running > 0 || !model) return;
    for (int handle : removed_hooks) model->removeCycleHook(handle);
    removed_hooks.clear();
}

void LuaModel::flushHistories() {
    for (auto& h : histories)
        if (h->open()) h->flush(*this);  // a failed write stops with the file's name
}

LuaModel& checkModel(lua_State* L, int index, const char* fn) {
    auto* lm = static_cast<LuaModel*>(testUserdata(L, index, kModelType));
    if (!lm)
        throw ScriptError(std::string(fn) + ": call it as a method, m:" + fn + "(...) (" +
                          (lua_isnone(L, index) ? std::string("no model was given")
                                                : "the first argument is a " + typeName(L, index) +
                                                      ", not a model") +
                          ")");
    if (!lm->model) throw ScriptError(std::string(fn) + ": the model was closed");
    return *lm;
}

void pushModel(lua_State* L, const LuaModel& lm) {
    lua_rawgetp(L, LUA_REGISTRYINDEX, &kModelsKey);
    lua_rawgetp(L, -1, &lm);
    lua_remove(L, -2);
}

int storeRef(lua_State* L, const LuaModel& lm, int value_index) {
    value_index = lua_absindex(L, value_index);
    pushUserValueTable(L, lm);
    lua_pushvalue(L, value_index);
    const int ref = luaL_ref(L, -2);
    lua_pop(L, 1);
    return ref;
}

void pushRef(lua_State* L, const LuaModel& lm, int ref) {
    pushUserValueTable(L, lm);
    lua_rawgeti(L, -1, ref);
    lua_remove(L, -2);
}

void releaseRef(lua_State* L, const LuaModel& lm, int ref) {
    pushUserValueTable(L, lm);
    luaL_unref(L, -1, ref);
    lua_pop(L, 1);
}

void openModel(lua_State* L) {
    // Weak-valued table LuaModel* -> userdata: callbacks find their model without keeping it alive.
    lua_newtable(L);
    lua_createtable(L, 0, 1);
    lua_pushliteral(L, "v");
    lua_setfield(L, -2, "__mode");
    lua_setmetatable(L, -2);
    lua_rawsetp(L, LUA_REGISTRYINDEX, &kModelsKey);

    luaL_newmetatable(L, kModelType);
    lua_pushcfunction(L, w_gc);
    lua_setfield(L, -2, "__gc");
    lua_pushcfunction(L, w_tostring);
    lua_setfield(L, -2, "__tostring");
    lua_newtable(L);
    for (const Binding* b : bindings())
        for (const Method& m : b->model_methods) {
            lua_pushcfunction(L, m.fn);
            lua_setfield(L, -2, m.name);
        }
    lua_createtable(L, 0, 1);
    lua_pushcfunction(L, w_index_unknown);
    lua_setfield(L, -2, "__index");
    lua_setmetatable(L, -2);
    lua_setfield(L, -2, "__index");
    lua_pop(L, 1);
}

}  // namespace talus::lua
