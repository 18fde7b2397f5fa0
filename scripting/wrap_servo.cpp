// SPDX-License-Identifier: MIT
// w:servo{...}: the wall servo (PFC "wall servo"; core/src/step/wall_servo.cpp, docs/lua-api.md
// "Servo walls"). The wall userdata's method table (wrap_wall.cpp) routes w:servo here.
#include <cmath>
#include <string>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"

namespace talus::lua {

namespace {

void pushServoState(lua_State* L, const WallServoState& st) {
    const WallServoSettings& s = st.settings;
    lua_createtable(L, 0, 14);
    lua_pushboolean(L, s.on);
    lua_setfield(L, -2, "on");
    lua_pushstring(L, s.stress ? "stress" : "force");
    lua_setfield(L, -2, "mode");
    lua_pushnumber(L, s.target);
    lua_setfield(L, -2, "target");
    lua_pushnumber(L, st.force);
    lua_setfield(L, -2, "force");
    lua_pushnumber(L, st.stress);
    lua_setfield(L, -2, "stress");
    lua_pushnumber(L, st.vel);
    lua_setfield(L, -2, "vel");
    lua_pushnumber(L, st.gain);
    lua_setfield(L, -2, "gain");
    lua_pushnumber(L, st.knest);
    lua_setfield(L, -2, "knest");
    lua_pushnumber(L, s.length);
    lua_setfield(L, -2, "length");
    lua_pushnumber(L, s.alpha);
    lua_setfield(L, -2, "alpha");
    lua_pushnumber(L, s.vmax);
    lua_setfield(L, -2, "vmax");
    pushVec(L, s.dir);
    lua_setfield(L, -2, "dir");
    if (std::isnan(s.gain))
        lua_pushboolean(L, false);
    else
        lua_pushnumber(L, s.gain);
    lua_setfield(L, -2, "fixed_gain");
}

}  // namespace

int servoWall(lua_State* L, LuaModel& lm, WallId id) {
    Model& m = *lm.model;
    const std::string what = "wall " + std::to_string(id.index) + ": servo";
    WallServoState st;
    const bool exists = m.wallServo(id, st);
    if (lua_isnoneornil(L, 2)) {
        if (!exists) {
            (void)m.wallVel(id);  // a stale wall is an error, not "no servo"
            lua_pushnil(L);
        } else {
            pushServoState(L, st);
        }
        return 1;
    }
    const Options o(L, 2, what,
                    {"force", "stress", "length", "gain", "alpha", "vmax", "on", "dir"});
    WallServoSettings s = exists ? st.settings : WallServoSettings{};
    if (o.has("force") && o.has("stress"))
        throw ScriptError(what + ": give force = F [N] or stress = s [Pa], not both");
    if (!exists && !o.has("force") && !o.has("stress"))
        throw ScriptError(what +
                          ": the first call needs a target, force = F [N] or stress = s "
                          "[Pa] (compression positive)");
    if (o.has("force")) s.stress = false, s.target = o.number("force", 0.0);
    if (o.has("stress")) s.stress = true, s.target = o.number("stress", 0.0);
    if (o.has("length")) s.length = o.number("length", 0.0);
    if (o.has("alpha")) s.alpha = o.number("alpha", 0.0);
    if (o.has("vmax")) s.vmax = o.number("vmax", 0.0);
    if (o.has("on")) s.on = o.boolean("on", true);
    if (o.has("dir")) s.dir = o.vec("dir", Vec2(0.0, 0.0));
    if (o.has("gain")) {
        // gain = false goes back to PFC's formula.
        const int t = o.push("gain");
        const bool is_false = t == LUA_TBOOLEAN && !lua_toboolean(L, -1);
        lua_pop(L, 1);
        s.gain = is_false ? kNotSet : o.number("gain", 0.0);
    }
    m.setWallServo(id, s);
    m.wallServo(id, st);
    pushServoState(L, st);
    return 1;
}

}  // namespace talus::lua
