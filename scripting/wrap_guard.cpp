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
        lua_createtable(L, 0, 8);
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
        "stiffness", "balance",          "balance_tolerance", "balance_every"};
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
}

}  // namespace talus::lua
