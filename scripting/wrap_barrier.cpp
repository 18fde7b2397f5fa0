// SPDX-License-Identifier: MIT
// m:barrier{...} and m:barriers(): segments with an energy capacity (docs/rockfall.md,
// "Barriers"; the engine's check is core/src/step/barriers.cpp).
#include "lua_bindings.hpp"
#include "talus/errors.hpp"

namespace talus::lua {

namespace {

const Option kBarrierRows[] = {
    {"from", "talus.Vec", "the barrier's foot [m]", true},
    {"to", "talus.Vec", "the barrier's top [m]", true},
    {"energy", "number", "its capacity [J]: the kinetic energy it takes from a body", true},
    {"name", "string", "a name for messages and records"},
};
const OptionTable kBarrierDef = {
    "talus.BarrierDef",
    "m:barrier{...}: a segment that takes up to `energy` from each body crossing it the first time",
    kBarrierRows};

/// m:barrier{from =, to =, energy =, name =}: returns the barrier's id (>= 1).
int w_barrier(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "barrier");
        const Options o(L, 2, "barrier", kBarrierDef);
        for (const char* key : {"from", "to", "energy"})
            if (!o.has(key)) throw ScriptError(o.field(key) + " is required");
        BarrierDef d;
        d.name = o.string("name", "");
        d.from = o.vec("from", d.from);
        d.to = o.vec("to", d.to);
        d.energy = o.number("energy", d.energy);
        lua_pushinteger(L, lm.model->createBarrier(d));
        return 1;
    });
}

/// m:barriers(): one table per barrier, in the order they were made.
int w_barriers(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "barriers");
        const std::size_t n = lm.model->barrierCount();
        lua_createtable(L, static_cast<int>(n), 0);
        for (std::size_t k = 1; k <= n; ++k) {
            const BarrierInfo b = lm.model->barrierInfo(static_cast<int>(k));
            lua_createtable(L, 0, 8);
            setInteger(L, "id", static_cast<lua_Integer>(k));
            setString(L, "name", b.def.name);
            pushVec(L, b.def.from);
            lua_setfield(L, -2, "from");
            pushVec(L, b.def.to);
            lua_setfield(L, -2, "to");
            setNumber(L, "energy", b.def.energy);
            setInteger(L, "passed", b.passed);
            setInteger(L, "stopped", b.stopped);
            setNumber(L, "absorbed", b.absorbed);
            lua_rawseti(L, -2, static_cast<lua_Integer>(k));
        }
        return 1;
    });
}

const Method kBarrierMethods[] = {
    {"barrier", w_barrier,
     "adds a barrier: a segment with an energy capacity, checked every step; returns its id",
     "def: talus.BarrierDef", "integer"},
    {"barriers", w_barriers,
     "the barriers: id, name, from, to, energy, passed, stopped and absorbed [J] of each", "",
     "table[]"},
};

const OptionTable* const kOptionTables[] = {&kBarrierDef};

}  // namespace

extern const Binding kBarrierBinding = {"barriers", kBarrierMethods, {}, {}, kOptionTables, {}};

}  // namespace talus::lua
