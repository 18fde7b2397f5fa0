// SPDX-License-Identifier: MIT
// m:cracks(): the bonds broken so far, as cracks (crack.hpp; docs/lua-api.md "Cracks").
#include <cmath>
#include <limits>

#include "lua_bindings.hpp"

namespace talus::lua {

namespace {

const char* crackModeName(int32_t mode) {
    return mode == kBreakTension ? "tension" : mode == kBreakShear ? "shear" : "none";
}

// m:cracks{since = t}: the list of cracks in the order they happened (those at time >= since).
int w_cracks(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "cracks");
        const Options o(L, 2, "cracks", {"since"}, true);
        const double since = o.number("since", -std::numeric_limits<double>::infinity());
        lua_newtable(L);
        lua_Integer n = 0;
        for (const Crack& c : lm.cracks) {
            if (!(c.time >= since)) continue;
            lua_createtable(L, 0, 14);
            lua_pushnumber(L, c.time);
            lua_setfield(L, -2, "time");
            lua_pushinteger(L, static_cast<lua_Integer>(c.step));
            lua_setfield(L, -2, "step");
            lua_pushnumber(L, c.pos.x());
            lua_setfield(L, -2, "x");
            lua_pushnumber(L, c.pos.y());
            lua_setfield(L, -2, "y");
            lua_pushstring(L, crackModeName(c.mode));
            lua_setfield(L, -2, "mode");
            if (c.ball1.valid()) {
                lua_pushinteger(L, c.ball1.index);
                lua_setfield(L, -2, "ball1");
            }
            if (c.ball2.valid()) {
                lua_pushinteger(L, c.ball2.index);
                lua_setfield(L, -2, "ball2");
            }
            lua_pushnumber(L, c.radius);
            lua_setfield(L, -2, "radius");
            lua_pushnumber(L, 2.0 * c.radius);
            lua_setfield(L, -2, "width");
            lua_pushnumber(L, c.normal.x());
            lua_setfield(L, -2, "nx");
            lua_pushnumber(L, c.normal.y());
            lua_setfield(L, -2, "ny");
            if (!std::isnan(c.sigma)) {
                lua_pushnumber(L, c.sigma);
                lua_setfield(L, -2, "sigma");
                lua_pushnumber(L, c.tau);
                lua_setfield(L, -2, "tau");
            }
            lua_rawseti(L, -2, ++n);
        }
        return 1;
    });
}

}  // namespace

extern const luaL_Reg kCrackMethods[] = {
    {"cracks", w_cracks},
    {nullptr, nullptr},
};

}  // namespace talus::lua
