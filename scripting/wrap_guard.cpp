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

/// The options of m:guard{...} and of impact's guard = {...}: adding one is a row here and its
/// reading in readGuardOptions (and its value in w_guard's result).
const Option kGuardOptionRows[] = {
    {"energy", "\"warn\"|\"error\"|\"off\"", "a contact that gave back more energy than it took"},
    {"energy_tolerance", "number", "allowed gain, a fraction of the contact's energy (0.01)"},
    {"resolution", "\"warn\"|\"error\"|\"off\"",
     "a step larger than an impact's duration / min_steps"},
    {"min_steps", "integer", "steps an impact must take at least (default 10)"},
    {"stiffness", "\"warn\"|\"error\"|\"off\"", "a model stiffer than it reports"},
    {"balance", "\"warn\"|\"error\"|\"off\"", "the energy balance, while tracing is on"},
    {"balance_tolerance", "number", "allowed balance error, a fraction of the throughput (0.01)"},
    {"balance_every", "integer", "steps between two balance checks (default 10)"},
    {"severe", "\"error\"|\"warn\"", "severe findings stop the run (\"error\") or only warn"},
    {"severe_created", "number",
     "energy created beyond this share of the throughput is severe (0.1)"},
    {"severe_min_steps", "integer", "fewer steps per contact duration is severe (default 3)"},
    {"memory_limit", "number", "most memory the model may take [bytes]; 0 = what the machine has"},
};

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
        const Options o(L, 2, "guard", kGuardOptions, true);
        GuardSettings g = lm.model->guard();
        readGuardOptions(o, g);
        lm.model->guard() = g;
        lua_createtable(L, 0, 12);
        setString(L, "energy", guardName(g.energy));
        setNumber(L, "energy_tolerance", g.energy_tolerance);
        setString(L, "resolution", guardName(g.resolution));
        setInteger(L, "min_steps", g.min_steps);
        setString(L, "stiffness", guardName(g.stiffness));
        setString(L, "balance", guardName(g.balance));
        setNumber(L, "balance_tolerance", g.balance_tolerance);
        setInteger(L, "balance_every", g.balance_every);
        setString(L, "severe", guardName(g.severe));
        setNumber(L, "severe_created", g.severe_created);
        setInteger(L, "severe_min_steps", g.severe_min_steps);
        setNumber(L, "memory_limit", g.memory_limit);
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

const Method kGuardMethods[] = {
    {"guard", w_guard, "sets what the run checks and how it reacts; returns the settings",
     "options?: talus.GuardOptions", "table"},
    {"placement_warning", w_placement_warning,
     "switches the warning about bodies placed overlapping; returns the setting before",
     "on?: boolean", "boolean"},
};

}  // namespace

extern const OptionTable kGuardOptions = {
    "talus.GuardOptions", "m:guard{...}: what the run checks, each \"warn\", \"error\" or \"off\"",
    kGuardOptionRows};

namespace {
const OptionTable* const kOptionTables[] = {&kGuardOptions};
}  // namespace

extern const Binding kGuardBinding = {"guard", kGuardMethods, {}, {}, kOptionTables, {}};

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
