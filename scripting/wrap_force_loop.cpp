// SPDX-License-Identifier: MIT
// How the force loop runs (docs/lua-api.md, "Force loop"): m:batched_law and m:threads. Neither
// changes a result: they are for measurements and for tests that prove it.
#include <string>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"

namespace talus::lua {

namespace {

/// m:batched_law(on) switches the models' batched FDlaw on or off; m:batched_law() reads it.
int w_batched_law(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "batched_law");
        if (!lua_isnoneornil(L, 2)) {
            if (!lua_isboolean(L, 2))
                throw ScriptError(std::string("batched_law: expected true or false (got ") +
                                  luaL_tolstring(L, 2, nullptr) + ")");
            lm.model->setBatchedLaw(lua_toboolean(L, 2) != 0);
        }
        lua_pushboolean(L, lm.model->batchedLaw());
        return 1;
    });
}

}  // namespace

extern const luaL_Reg kForceLoopMethods[] = {
    {"batched_law", w_batched_law},
    {nullptr, nullptr},
};

}  // namespace talus::lua
