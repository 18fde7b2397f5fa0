// SPDX-License-Identifier: MIT
// m:energy(on) / m:energies() and the energy items shared with histories and impact.
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

const Option kEnergyOptionRows[] = {
    {"on", "boolean", "switches energy tracing on or off"},
};
const OptionTable kEnergyOptions = {"talus.EnergyOptions", "m:energy{...}", kEnergyOptionRows};

// ------------------------------------------------------------------ energy

int w_energy(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "energy");
        const Options o(L, 2, "energy", kEnergyOptions, true);
        if (o.has("on")) lm.model->setEnergyTracing(o.boolean("on", false));
        lua_pushboolean(L, lm.model->energyTracing());
        return 1;
    });
}

int w_energies(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "energies");
        if (lua_isnoneornil(L, 2)) {
            pushEnergies(L, lm.model->energies());
        } else {
            // m:energies("rock"): the same items for one group (docs/physics/energy.md).
            if (lua_type(L, 2) != LUA_TSTRING)
                throw ScriptError("energies: the argument is a group name (a string), got " +
                                  typeName(L, 2));
            pushEnergies(L, lm.model->energies(lua_tostring(L, 2)));
        }
        return 1;
    });
}

const Method kEnergyMethods[] = {
    {"energy", w_energy, "switches energy tracing; returns whether it is on",
     "options?: talus.EnergyOptions", "boolean"},
    {"energies", w_energies,
     "the energy items [J] with balance_error and input; of one group when given", "group?: string",
     "table<string, number>"},
};

const OptionTable* const kOptionTables[] = {&kEnergyOptions};

}  // namespace

extern const Binding kEnergyBinding = {"energy", kEnergyMethods, {}, {}, kOptionTables, {}};

const std::vector<EnergyItem>& energyItems() {
    static const std::vector<EnergyItem> items = {
        {"body", &EnergyTotals::body},
        {"boundary", &EnergyTotals::boundary},
        {"kinetic", &EnergyTotals::kinetic},
        {"strain", &EnergyTotals::strain},
        {"bond", &EnergyTotals::bond},
        {"slip", &EnergyTotals::slip},
        {"dashpot", &EnergyTotals::dashpot},
        {"plastic", &EnergyTotals::plastic},
        {"damping", &EnergyTotals::damping},
        {"released", &EnergyTotals::released},
        {"deleted", &EnergyTotals::deleted},
        {"initial_kinetic", &EnergyTotals::initial_kinetic},
        {"initial_strain", &EnergyTotals::initial_strain},
        {"placement", &EnergyTotals::placement},
        {"exchanged", &EnergyTotals::exchanged},
        {"script", &EnergyTotals::script},
        {"barrier", &EnergyTotals::barrier},
    };
    return items;
}

void pushEnergies(lua_State* L, const EnergyTotals& e) {
    lua_createtable(L, 0, 18);
    for (const EnergyItem& item : energyItems()) {
        lua_pushnumber(L, e.*(item.member));
        lua_setfield(L, -2, item.name);
    }
    setNumber(L, "balance_error", e.balanceError());
    setNumber(L, "input", e.input());
}

}  // namespace talus::lua
