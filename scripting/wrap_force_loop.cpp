// SPDX-License-Identifier: MIT
// How the force loop runs (docs/lua-api.md, "Force loop"): m:batched_law, m:lanes, m:kernels and
// m:threads, none of which changes a result (they are for measurements and for tests that prove
// it), and m:sort_interval, the balls' memory order (the same physics; sums in another order).
#include <string>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"

namespace talus::lua {

namespace {

/// A switch of the force loop: m:<name>(on) sets it, m:<name>() reads it; returns the setting.
template <class Set, class Get>
int loopSwitch(lua_State* L, const char* name, Set set, Get get) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, name);
        if (!lua_isnoneornil(L, 2)) {
            if (!lua_isboolean(L, 2))
                throw ScriptError(std::string(name) + ": expected true or false (got " +
                                  luaL_tolstring(L, 2, nullptr) + ")");
            set(*lm.model, lua_toboolean(L, 2) != 0);
        }
        lua_pushboolean(L, get(*lm.model));
        return 1;
    });
}

/// m:batched_law(on): the models' batched FDlaw, or FDlaw per contact.
int w_batched_law(lua_State* L) {
    return loopSwitch(
        L, "batched_law", [](Model& m, bool on) { m.setBatchedLaw(on); },
        [](const Model& m) { return m.batchedLaw(); });
}

/// m:lanes(on): the contacts of models with a lane law through it.
int w_lanes(lua_State* L) {
    return loopSwitch(
        L, "lanes", [](Model& m, bool on) { m.setLanes(on); },
        [](const Model& m) { return m.lanes(); });
}

/// m:kernels(on): the host's kernels of the shipped models' laws, or their FDlaw.
int w_kernels(lua_State* L) {
    return loopSwitch(
        L, "kernels", [](Model& m, bool on) { m.setKernels(on); },
        [](const Model& m) { return m.kernels(); });
}

/// m:threads(n [, grain]) sets the force loop's threads, m:threads() reads them.
int w_threads(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "threads");
        if (!lua_isnoneornil(L, 2)) {
            if (!lua_isinteger(L, 2))
                throw ScriptError(std::string("threads: the thread count must be an integer "
                                              "from 1 to 1024 (got ") +
                                  luaL_tolstring(L, 2, nullptr) + ")");
            const lua_Integer n = lua_tointeger(L, 2);
            if (n < 1 || n > 1024)
                throw ScriptError("threads: the thread count must be from 1 to 1024 (got " +
                                  std::to_string(n) + ")");
            lua_Integer grain = Model::kDefaultThreadGrain;
            if (!lua_isnoneornil(L, 3)) {
                if (!lua_isinteger(L, 3) || lua_tointeger(L, 3) < 1 ||
                    lua_tointeger(L, 3) > 1000000000)
                    throw ScriptError(std::string("threads: the grain (fewest pairs per thread) "
                                                  "must be an integer >= 1 (got ") +
                                      luaL_tolstring(L, 3, nullptr) + ")");
                grain = lua_tointeger(L, 3);
            }
            lm.model->setThreads(static_cast<int>(n), static_cast<int>(grain));
        }
        lua_pushinteger(L, lm.model->threads());
        return 1;
    });
}

/// m:sort_interval(steps | "auto") sets how often the balls are re-ordered in memory, 0 never;
/// m:sort_interval() reads it (a number, or "auto").
int w_sort_interval(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "sort_interval");
        if (!lua_isnoneornil(L, 2)) {
            if (lua_type(L, 2) == LUA_TSTRING && std::string(lua_tostring(L, 2)) == "auto") {
                lm.model->setSortInterval(Model::kSortAuto);
            } else if (lua_isinteger(L, 2) && lua_tointeger(L, 2) >= 0) {
                lm.model->setSortInterval(lua_tointeger(L, 2));
            } else {
                throw ScriptError(std::string("sort_interval: expected a step count >= 0 or "
                                              "\"auto\" (got ") +
                                  luaL_tolstring(L, 2, nullptr) + ")");
            }
        }
        const int64_t every = lm.model->sortInterval();
        if (every == Model::kSortAuto)
            lua_pushliteral(L, "auto");
        else
            lua_pushinteger(L, every);
        return 1;
    });
}

const Method kForceLoopMethods[] = {
    {"batched_law", w_batched_law, "the models' batched FDlaw (true) or FDlaw per contact",
     "on?: boolean", "boolean"},
    {"lanes", w_lanes, "the contacts of models with a lane law through it", "on?: boolean",
     "boolean"},
    {"kernels", w_kernels, "the host's kernels of the shipped models' laws, or their FDlaw",
     "on?: boolean", "boolean"},
    {"threads", w_threads, "the force loop's threads (the same results for any number)",
     "n?: integer, grain?: integer", "integer"},
    {"sort_interval", w_sort_interval,
     "steps between re-orderings of the balls in memory, 0 never, or \"auto\"",
     "steps?: integer|\"auto\"", "integer|\"auto\""},
};

}  // namespace

extern const Binding kForceLoopBinding = {"force loop", kForceLoopMethods, {}, {}, {}, {}};

}  // namespace talus::lua
