// SPDX-License-Identifier: MIT
// m:cracks(): the bonds broken so far, as cracks (crack.hpp; docs/lua-api.md "Cracks").
#include <cmath>
#include <limits>

#include "lua_bindings.hpp"

namespace talus::lua {

namespace {

const Option kCracksOptionRows[] = {
    {"since", "number", "only the cracks at time >= since [s]"},
};
const OptionTable kCracksOptions = {"talus.CracksOptions", "m:cracks{...}", kCracksOptionRows};

const char* crackModeName(int32_t mode) {
    return mode == kBreakTension ? "tension" : mode == kBreakShear ? "shear" : "none";
}

// m:cracks{since = t}: the list of cracks in the order they happened (those at time >= since).
int w_cracks(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "cracks");
        const Options o(L, 2, "cracks", kCracksOptions, true);
        const double since = o.number("since", -std::numeric_limits<double>::infinity());
        lua_newtable(L);
        lua_Integer n = 0;
        for (const Crack& c : lm.cracks) {
            if (!(c.time >= since)) continue;
            lua_createtable(L, 0, 14);
            setNumber(L, "time", c.time);
            setInteger(L, "step", static_cast<lua_Integer>(c.step));
            setNumber(L, "x", c.pos.x());
            setNumber(L, "y", c.pos.y());
            setString(L, "mode", crackModeName(c.mode));
            if (c.ball1.valid()) {
                setInteger(L, "ball1", c.ball1.index);
            }
            if (c.ball2.valid()) {
                setInteger(L, "ball2", c.ball2.index);
            }
            setNumber(L, "radius", c.radius);
            setNumber(L, "width", 2.0 * c.radius);
            setNumber(L, "nx", c.normal.x());
            setNumber(L, "ny", c.normal.y());
            if (!std::isnan(c.sigma)) {
                setNumber(L, "sigma", c.sigma);
                setNumber(L, "tau", c.tau);
            }
            lua_rawseti(L, -2, ++n);
        }
        return 1;
    });
}

const Method kCrackMethods[] = {
    {"cracks", w_cracks, "the bonds broken so far, as cracks, in the order they happened",
     "options?: talus.CracksOptions", "table[]"},
};

const OptionTable* const kOptionTables[] = {&kCracksOptions};

}  // namespace

extern const Binding kCrackBinding = {"cracks", kCrackMethods, {}, {}, kOptionTables, {}};

}  // namespace talus::lua
