// SPDX-License-Identifier: MIT
// w:servo{...}: the wall servo (PFC "wall servo"; core/src/wall_servo.cpp, docs/lua-api.md
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
    setBoolean(L, "on", s.on);
    setString(L, "mode", s.stress ? "stress" : "force");
    setNumber(L, "target", s.target);
    setNumber(L, "force", st.force);
    setNumber(L, "stress", st.stress);
    setNumber(L, "vel", st.vel);
    setNumber(L, "gain", st.gain);
    setNumber(L, "knest", st.knest);
    setNumber(L, "length", s.length);
    setNumber(L, "alpha", s.alpha);
    setNumber(L, "vmax", s.vmax);
    pushVec(L, s.dir);
    lua_setfield(L, -2, "dir");
    if (std::isnan(s.gain))
        lua_pushboolean(L, false);
    else
        lua_pushnumber(L, s.gain);
    lua_setfield(L, -2, "fixed_gain");
}

const Option kServoOptionRows[] = {
    {"force", "number", "target force [N], compression positive (or stress)"},
    {"stress", "number", "target stress [Pa], compression positive (or force)"},
    {"length", "number", "[m] the stress form's length (default: the wall chain's length)"},
    {"gain", "number|false", "a fixed gain [m/s per N or per Pa]; false: PFC's formula again"},
    {"alpha", "number", "PFC's relaxation factor in (0, 2) (default 0.5)"},
    {"vmax", "number", "speed cap [m/s] (default 1)"},
    {"on", "boolean", "false switches the servo off (the wall stops along dir)"},
    {"dir", "talus.Vec", "direction in which the wall presses the material"},
};

const OptionTable kServoOptions = {"talus.ServoOptions",
                                   "w:servo{...}: a later call changes only the options it gives",
                                   kServoOptionRows};

const OptionTable* const kOptionTables[] = {&kServoOptions};

}  // namespace

extern const Binding kServoBinding = {"servo", {}, {}, {}, kOptionTables, {}};

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
    const Options o(L, 2, what, kServoOptions);
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
