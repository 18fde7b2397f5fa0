// SPDX-License-Identifier: MIT
// m:guard{...} and the guard option reader shared with impact.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"
#include "talus/plugin_registry.hpp"

namespace talus::lua {

namespace {

const char* guardName(GuardAction a) {
    switch (a) {
        case GuardAction::Off:
            return "off";
        case GuardAction::Warn:
            return "warn";
        case GuardAction::Error:
            return "error";
    }
    return "?";
}

int w_guard(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "guard");
        const Options o(L, 2, "guard", guardOptionNames(), true);
        GuardSettings g = lm.model->guard();
        readGuardOptions(o, g);
        lm.model->guard() = g;
        lua_createtable(L, 0, 12);
        lua_pushstring(L, guardName(g.energy));
        lua_setfield(L, -2, "energy");
        lua_pushnumber(L, g.energy_tolerance);
        lua_setfield(L, -2, "energy_tolerance");
        lua_pushstring(L, guardName(g.resolution));
        lua_setfield(L, -2, "resolution");
        lua_pushinteger(L, g.min_steps);
        lua_setfield(L, -2, "min_steps");
        lua_pushstring(L, guardName(g.stiffness));
        lua_setfield(L, -2, "stiffness");
        lua_pushstring(L, guardName(g.balance));
        lua_setfield(L, -2, "balance");
        lua_pushnumber(L, g.balance_tolerance);
        lua_setfield(L, -2, "balance_tolerance");
        lua_pushinteger(L, g.balance_every);
        lua_setfield(L, -2, "balance_every");
        lua_pushstring(L, guardName(g.severe));
        lua_setfield(L, -2, "severe");
        lua_pushnumber(L, g.severe_created);
        lua_setfield(L, -2, "severe_created");
        lua_pushinteger(L, g.severe_min_steps);
        lua_setfield(L, -2, "severe_min_steps");
        lua_pushnumber(L, g.memory_limit);
        lua_setfield(L, -2, "memory_limit");
        return 1;
    });
}

/// m:placement_warning(on): the warning about contacts that start overlapping, off while a
/// routine overlaps bodies on purpose; returns the setting before the call (m:placement_warning()
/// only reads it).
int w_placement_warning(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "placement_warning");
        const bool was = lm.model->placementWarning();
        if (!lua_isnoneornil(L, 2)) {
            if (!lua_isboolean(L, 2))
                throw ScriptError("placement_warning: expected true or false (got " +
                                  typeName(L, 2) + ")");
            lm.model->setPlacementWarning(lua_toboolean(L, 2) != 0);
        }
        lua_pushboolean(L, was);
        return 1;
    });
}

}  // namespace

extern const luaL_Reg kGuardMethods[] = {
    {"guard", w_guard},
    {"placement_warning", w_placement_warning},
    {nullptr, nullptr},
};

const std::vector<std::string>& guardOptionNames() {
    static const std::vector<std::string> names = {
        "energy",    "energy_tolerance", "resolution",        "min_steps",
        "stiffness", "balance",          "balance_tolerance", "balance_every",
        "severe",    "severe_created",   "severe_min_steps",  "memory_limit"};
    return names;
}

void readGuardOptions(const Options& o, GuardSettings& g) {
    const GuardAction actions[] = {GuardAction::Warn, GuardAction::Error, GuardAction::Off};
    if (o.has("energy")) g.energy = actions[o.choice("energy", 0, {"warn", "error", "off"})];
    if (o.has("resolution"))
        g.resolution = actions[o.choice("resolution", 0, {"warn", "error", "off"})];
    if (o.has("stiffness"))
        g.stiffness = actions[o.choice("stiffness", 0, {"warn", "error", "off"})];
    g.energy_tolerance = o.number("energy_tolerance", g.energy_tolerance);
    if (!(g.energy_tolerance >= 0.0))
        throw ScriptError("guard: 'energy_tolerance' must be >= 0 (got " +
                          numberText(g.energy_tolerance) + ")");
    if (o.has("balance")) g.balance = actions[o.choice("balance", 0, {"warn", "error", "off"})];
    g.balance_tolerance = o.number("balance_tolerance", g.balance_tolerance);
    if (!(g.balance_tolerance >= 0.0) || !std::isfinite(g.balance_tolerance))
        throw ScriptError("guard: 'balance_tolerance' must be a finite number >= 0 (got " +
                          numberText(g.balance_tolerance) + ")");
    const long long window = o.integer("balance_every", g.balance_every);
    if (window < 1)
        throw ScriptError("guard: 'balance_every' must be >= 1 step (got " +
                          std::to_string(window) + ")");
    g.balance_every = window;
    const long long steps = o.integer("min_steps", g.min_steps);
    if (steps < 0 || steps > std::numeric_limits<int>::max())
        throw ScriptError("guard: 'min_steps' must be >= 0 (got " + std::to_string(steps) + ")");
    g.min_steps = static_cast<int>(steps);
    // Severe findings (docs/physics/guard.md): "error" stops the run, "warn" reports them as the
    // check's other findings.
    if (o.has("severe"))
        g.severe =
            o.choice("severe", 0, {"error", "warn"}) == 0 ? GuardAction::Error : GuardAction::Warn;
    g.severe_created = o.number("severe_created", g.severe_created);
    if (!(g.severe_created > 0.0) || !std::isfinite(g.severe_created))
        throw ScriptError("guard: 'severe_created' must be a finite fraction > 0 (got " +
                          numberText(g.severe_created) + ")");
    const long long severe_steps = o.integer("severe_min_steps", g.severe_min_steps);
    if (severe_steps < 0 || severe_steps > std::numeric_limits<int>::max())
        throw ScriptError("guard: 'severe_min_steps' must be >= 0 (got " +
                          std::to_string(severe_steps) + ")");
    g.severe_min_steps = static_cast<int>(severe_steps);
    g.memory_limit = o.number("memory_limit", g.memory_limit);
    if (!(g.memory_limit >= 0.0) || !std::isfinite(g.memory_limit))
        throw ScriptError(
            "guard: 'memory_limit' must be a number of bytes >= 0 (0: what the "
            "machine has; got " +
            numberText(g.memory_limit) + ")");
}

}  // namespace talus::lua
