// SPDX-License-Identifier: MIT
// m:timestep{...} and the time-step option reader shared with impact.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"
#include "talus/plugin_registry.hpp"

namespace talus::lua {

namespace {

const Option kTimestepOptionRows[] = {
    {"safety", "number", "stability rule: the step is at most safety sqrt(m/k) (default 0.8)"},
    {"resolution", "number", "at least this many steps per contact duration; 0 off (default 30)"},
    {"fixed", "number|false", "a fixed step [s]; false returns to the automatic step"},
    {"max", "number", "largest automatic step [s] (default math.huge)"},
    {"growth", "number", "largest ratio between consecutive automatic steps, > 1 (default 2)"},
    {"auto", "boolean", "automatic step (default true); false needs a fixed step"},
};

const Option kSolveOptionRows[] = {
    {"time", "number", "run until this much more simulated time has passed [s]"},
    {"steps", "integer", "run this many steps"},
    {"ratio", "number", "run until PFC's mechanical ratio (m:unbalanced().ratio) is below this"},
    {"until", "fun(m: talus.Model): boolean", "run until it returns true (checked every step)"},
    {"max_steps", "integer", "stop after this many steps whatever the other criteria"},
    {"max_time", "number", "stop after this much simulated time [s]"},
};
const OptionTable kSolveOptions = {
    "talus.SolveOptions", "m:solve{...}: the first criterion met stops the run", kSolveOptionRows};

int w_timestep(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "timestep");
        const Options o(L, 2, "timestep", kTimestepOptions, true);
        TimestepSettings ts = lm.model->timestep();
        readTimestepOptions(o, ts);
        lm.model->timestep() = ts;
        Model& m = *lm.model;
        lua_createtable(L, 0, 9);
        setBoolean(L, "auto", ts.automatic);
        if (ts.automatic)
            lua_pushboolean(L, false);
        else
            lua_pushnumber(L, ts.fixed);
        lua_setfield(L, -2, "fixed");
        setNumber(L, "safety", ts.safety);
        setNumber(L, "resolution", ts.resolution);
        setNumber(L, "max", ts.max);
        setNumber(L, "growth", ts.growth);
        setNumber(L, "dt", m.lastTimestep());
        setString(L, "rule", stepRuleName(m.lastStepRule()));
        setString(L, "reason", m.lastStepReason());
        return 1;
    });
}

const Method kTimestepMethods[] = {
    {"timestep", w_timestep,
     "sets the time-step rules; returns them with the last step and its rule",
     "options?: talus.TimestepOptions", "table"},
};

}  // namespace

extern const OptionTable kTimestepOptions = {
    "talus.TimestepOptions", "m:timestep{...}: the time-step rules", kTimestepOptionRows};

namespace {
const OptionTable* const kOptionTables[] = {&kTimestepOptions, &kSolveOptions};
}  // namespace

extern const Binding kTimestepBinding = {"time step", kTimestepMethods, {}, {}, kOptionTables, {}};

void readTimestepOptions(const Options& o, TimestepSettings& ts) {
    lua_State* L = o.state();
    if (o.has("fixed")) {
        const int t = o.push("fixed");
        const bool is_false = t == LUA_TBOOLEAN && !lua_toboolean(L, -1);
        lua_pop(L, 1);
        if (is_false) {
            ts.automatic = true;
        } else {
            const double dt = o.number("fixed", 0.0);
            if (!(dt > 0.0) || !std::isfinite(dt))
                throw ScriptError("timestep: 'fixed' must be > 0 [s] (got " + numberText(dt) + ")");
            ts.fixed = dt;
            ts.automatic = false;
        }
    }
    if (o.has("auto")) {
        ts.automatic = o.boolean("auto", true);
        if (!ts.automatic && !(ts.fixed > 0.0))
            throw ScriptError("timestep: auto = false needs a 'fixed' step");
    }
    ts.safety = o.number("safety", ts.safety);
    ts.resolution = o.number("resolution", ts.resolution);
    ts.max = o.number("max", ts.max);
    ts.growth = o.number("growth", ts.growth);
    if (!(ts.safety > 0.0) || !std::isfinite(ts.safety))
        throw ScriptError("timestep: 'safety' must be > 0 (got " + numberText(ts.safety) + ")");
    if (!(ts.resolution >= 0.0) || !std::isfinite(ts.resolution))
        throw ScriptError("timestep: 'resolution' must be >= 0 steps per contact (got " +
                          numberText(ts.resolution) + ")");
    if (!(ts.max > 0.0))
        throw ScriptError("timestep: 'max' must be > 0 [s] (got " + numberText(ts.max) + ")");
    if (!(ts.growth > 1.0))
        throw ScriptError("timestep: 'growth' must be > 1 (got " + numberText(ts.growth) + ")");
}

SolveRequest readSolveOptions(lua_State* L, LuaModel& lm, int index) {
    index = lua_absindex(L, index);
    const Options o(L, index, "solve", kSolveOptions);
    SolveRequest r;
    SolveSpec& s = r.spec;
    if (o.has("time")) s.time = o.number("time", 0.0);
    if (o.has("steps")) {
        const long long n = o.integer("steps", 0);
        if (n < 0) throw ScriptError("solve: 'steps' must be >= 0 (got " + std::to_string(n) + ")");
        s.steps = n;
    }
    // Ranges of ratio and max_time: Model::solve checks them.
    if (o.has("ratio")) s.ratio = o.number("ratio", 0.0);
    if (o.has("max_steps")) {
        const long long n = o.integer("max_steps", 0);
        if (n < 1)
            throw ScriptError("solve: 'max_steps' must be >= 1 (got " + std::to_string(n) + ")");
        s.max_steps = n;
    }
    if (o.has("max_time")) s.max_time = o.number("max_time", 0.0);
    if (o.has("until")) {
        if (o.push("until") != LUA_TFUNCTION) {
            const std::string got = typeName(L, -1);
            lua_pop(L, 1);
            throw ScriptError("solve: 'until' must be a function(m) returning true to stop (got " +
                              got + ")");
        }
        // The function stays on this stack (the caller's thread, which runs the callbacks)
        // until the binding returns, after the run.
        const int fn = lua_gettop(L);
        LuaModel* lmp = &lm;
        s.until = [L, fn, lmp](Model&) {
            const int base = lua_gettop(L);
            lua_pushvalue(L, fn);
            pushModel(L, *lmp);
            if (lua_pcall(L, 1, 1, 0) != LUA_OK) {
                std::string msg = errorText(L, -1);
                lua_settop(L, base);
                throw CallbackError(msg);
            }
            const bool stop = lua_toboolean(L, -1);
            lua_settop(L, base);
            return stop;
        };
    }
    if (!o.has("time") && !o.has("steps") && !o.has("ratio") && !o.has("until") &&
        !o.has("max_steps") && !o.has("max_time"))
        throw ScriptError(
            "solve: give a criterion: time = t, steps = n, ratio = r, [\"until\"] = "
            "fn (and caps max_steps = n, max_time = s)");
    r.time_only = o.has("time") && !o.has("steps") && !o.has("ratio") && !o.has("until") &&
                  !o.has("max_steps") && !o.has("max_time");
    return r;
}

}  // namespace talus::lua
