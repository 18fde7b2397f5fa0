// SPDX-License-Identifier: MIT
// m:servo{...}: a servo over a set of walls (talus/servo.hpp, core/src/step/servo.cpp;
// docs/lua-api.md "Servos"), and its userdata: sv:set{...}, sv:state(), sv:remove().
#include <cmath>
#include <string>
#include <vector>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"

namespace talus::lua {

namespace {

constexpr const char* kServoType = "talus.Servo";

struct ServoRef {
    LuaModel* lm;
    ServoId id;
};

const std::vector<std::string>& optionNames() {
    static const std::vector<std::string> names = {"walls",    "dirs",   "stress", "force", "rate",
                                                   "velocity", "length", "span",   "gauge", "ramp",
                                                   "alpha",    "vmax",   "on"};
    return names;
}

const char* const kControls[] = {"stress", "force", "rate", "velocity"};

/// The wall at stack `index`, of the model `lm`.
WallId toWall(lua_State* L, int index, const LuaModel& lm, const std::string& what) {
    index = lua_absindex(L, index);
    if (!testUserdata(L, index, kWallType))
        throw ScriptError(what + " must be a wall (got " + typeName(L, index) + ")");
    lua_getiuservalue(L, index, 1);
    pushModel(L, lm);
    const bool same = lua_rawequal(L, -1, -2);
    lua_pop(L, 2);
    if (!same) throw ScriptError(what + " is a wall of another model");
    lua_getfield(L, index, "id");
    const auto wanted = static_cast<uint32_t>(lua_tointeger(L, -1));
    lua_pop(L, 1);
    for (const WallId& id : lm.model->wallIds())
        if (id.index == wanted) return id;
    throw ScriptError(what + ": wall " + std::to_string(wanted) + " is gone");
}

std::vector<WallId> toWalls(lua_State* L, int index, const LuaModel& lm, const std::string& what) {
    requireTable(L, index, what);
    std::vector<WallId> out;
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, index));
    for (lua_Integer k = 1; k <= n; ++k) {
        lua_rawgeti(L, index, k);
        out.push_back(toWall(L, -1, lm, what + "[" + std::to_string(k) + "]"));
        lua_pop(L, 1);
    }
    return out;
}

/// Applies the options at stack 2 over `s` (a new servo starts from defaults and needs one
/// target; a later call changes only what it gives).
void readOptions(lua_State* L, const LuaModel& lm, ServoSettings& s, bool create,
                 const std::string& what) {
    const ServoControl before = s.control;
    const Options o(L, 2, what, optionNames());
    int targets = 0;
    for (int c = 0; c < 4; ++c)
        if (o.has(kControls[c])) {
            ++targets;
            s.control = static_cast<ServoControl>(c);
            s.target = o.number(kControls[c], 0.0);
        }
    if (targets > 1) throw ScriptError(what + ": give one target: stress, force, rate or velocity");
    if (create && targets == 0)
        throw ScriptError(what +
                          ": give a target: stress = s [Pa], force = F [N], rate = r [1/s] or "
                          "velocity = v [m/s] (compression positive)");
    if (o.has("walls")) {
        o.push("walls");
        s.walls = toWalls(L, -1, lm, what + ": walls");
        lua_pop(L, 1);
        s.dirs.clear();
    } else if (create) {
        throw ScriptError(what + ": give walls = {w1, w2, ...}");
    }
    if (o.has("dirs")) {
        o.push("dirs");
        const int at = lua_gettop(L);
        requireTable(L, at, what + ": dirs");
        s.dirs.clear();
        const auto n = static_cast<lua_Integer>(lua_rawlen(L, at));
        for (lua_Integer k = 1; k <= n; ++k) {
            lua_rawgeti(L, at, k);
            s.dirs.push_back(toVec(L, -1, what + ": dirs[" + std::to_string(k) + "]"));
            lua_pop(L, 1);
        }
        lua_pop(L, 1);
    }
    if (o.has("span")) {
        o.push("span");
        const std::vector<WallId> span = toWalls(L, -1, lm, what + ": span");
        lua_pop(L, 1);
        if (span.size() != 2) throw ScriptError(what + ": span = {wall_a, wall_b} (two walls)");
        s.span[0] = span[0], s.span[1] = span[1];
        s.length = kNotSet;
    }
    if (o.has("length")) s.length = o.number("length", 0.0);
    if (o.has("gauge")) s.gauge = o.number("gauge", 0.0);
    if (o.has("ramp")) s.ramp = o.integer("ramp", 0);
    if (o.has("alpha")) s.alpha = o.number("alpha", 0.0);
    // A new control gets its own default cap unless one is given.
    if (o.has("vmax"))
        s.vmax = o.number("vmax", 0.0);
    else if (s.control != before)
        s.vmax = kNotSet;
    if (o.has("on")) s.on = o.boolean("on", true);
}

void pushNumberOrNil(lua_State* L, double v) {
    if (std::isnan(v))
        lua_pushnil(L);
    else
        lua_pushnumber(L, v);
}

/// {control, target, on, walls, dirs, length, gauge, ramp, alpha, vmax, steps, force, forces,
/// stress, knest, speed, displacement, strain (rate: displacement over half the gauge)}
void pushState(lua_State* L, int model_index, const ServoState& st) {
    const ServoSettings& s = st.settings;
    lua_createtable(L, 0, 20);
    lua_pushstring(L, kControls[static_cast<int>(s.control)]);
    lua_setfield(L, -2, "control");
    lua_pushnumber(L, s.target);
    lua_setfield(L, -2, "target");
    lua_pushboolean(L, s.on);
    lua_setfield(L, -2, "on");
    lua_createtable(L, static_cast<int>(s.walls.size()), 0);
    for (std::size_t k = 0; k < s.walls.size(); ++k) {
        pushWall(L, model_index, s.walls[k]);
        lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    lua_setfield(L, -2, "walls");
    lua_createtable(L, static_cast<int>(s.dirs.size()), 0);
    for (std::size_t k = 0; k < s.dirs.size(); ++k) {
        pushVec(L, s.dirs[k]);
        lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    lua_setfield(L, -2, "dirs");
    lua_createtable(L, static_cast<int>(st.forces.size()), 0);
    for (std::size_t k = 0; k < st.forces.size(); ++k) {
        lua_pushnumber(L, st.forces[k]);
        lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    lua_setfield(L, -2, "forces");
    const std::pair<const char*, double> numbers[] = {
        {"length", s.control == ServoControl::Stress ? st.length : kNotSet},
        {"gauge", s.gauge},
        {"alpha", s.alpha},
        {"vmax", s.vmax},
        {"force", st.force},
        {"stress", st.stress},
        {"knest", st.knest},
        {"speed", st.speed},
        {"displacement", st.displacement},
        {"strain", s.control == ServoControl::Rate ? 2.0 * st.displacement / s.gauge : kNotSet},
    };
    for (const auto& [name, v] : numbers) {
        pushNumberOrNil(L, v);
        lua_setfield(L, -2, name);
    }
    lua_pushinteger(L, static_cast<lua_Integer>(s.ramp));
    lua_setfield(L, -2, "ramp");
    lua_pushinteger(L, static_cast<lua_Integer>(st.steps));
    lua_setfield(L, -2, "steps");
}

ServoRef& checkServo(lua_State* L, int index, const char* fn) {
    auto* s = static_cast<ServoRef*>(testUserdata(L, index, kServoType));
    if (!s)
        throw ScriptError(std::string("servo: call it as a method, sv:") + fn +
                          "(...) (the first argument is a " + typeName(L, index) +
                          ", not a servo)");
    if (!s->lm->model) throw ScriptError("servo: its model was closed");
    return *s;
}

/// The model userdata of a servo userdata at `index`, pushed.
void pushOwner(lua_State* L, int index) { lua_getiuservalue(L, index, 1); }

int s_set(lua_State* L) {
    return catchexcept(L, [&] {
        ServoRef& r = checkServo(L, 1, "set");
        Model& m = *r.lm->model;
        ServoSettings s = m.servo(r.id).settings;
        readOptions(L, *r.lm, s, false, "servo " + std::to_string(r.id.index) + ": set");
        m.setServo(r.id, s);
        pushOwner(L, 1);
        pushState(L, lua_gettop(L), m.servo(r.id));
        return 1;
    });
}

int s_state(lua_State* L) {
    return catchexcept(L, [&] {
        ServoRef& r = checkServo(L, 1, "state");
        pushOwner(L, 1);
        pushState(L, lua_gettop(L), r.lm->model->servo(r.id));
        return 1;
    });
}

int s_remove(lua_State* L) {
    return catchexcept(L, [&] {
        ServoRef& r = checkServo(L, 1, "remove");
        r.lm->model->removeServo(r.id);
        return 0;
    });
}

const luaL_Reg kServoObjectMethods[] = {
    {"set", s_set},
    {"state", s_state},
    {"remove", s_remove},
    {nullptr, nullptr},
};

int s_index(lua_State* L) {
    return catchexcept(L, [&] {
        const ServoRef& r = checkServo(L, 1, "index");
        if (lua_type(L, 2) == LUA_TSTRING) {
            const std::string key = lua_tostring(L, 2);
            if (key == "id") {
                lua_pushinteger(L, r.id.index);
                return 1;
            }
            lua_getfield(L, lua_upvalueindex(1), key.c_str());
            if (!lua_isnil(L, -1)) return 1;
            lua_pop(L, 1);
        }
        throw ScriptError("servo: no field '" + std::string(luaL_tolstring(L, 2, nullptr)) +
                          "' (known: id, set(), state(), remove())");
    });
}

int s_newindex(lua_State* L) {
    return catchexcept(L, [&]() -> int {
        throw ScriptError("servo: fields are read-only; change it with sv:set{...}");
    });
}

int s_eq(lua_State* L) {
    const auto* a = static_cast<ServoRef*>(testUserdata(L, 1, kServoType));
    const auto* b = static_cast<ServoRef*>(testUserdata(L, 2, kServoType));
    lua_pushboolean(L, a && b && a->lm == b->lm && a->id.index == b->id.index);
    return 1;
}

int s_tostring(lua_State* L) {
    const auto* s = static_cast<ServoRef*>(testUserdata(L, 1, kServoType));
    lua_pushfstring(L, "servo %d", s ? static_cast<int>(s->id.index) : 0);
    return 1;
}

int w_servo_new(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "servo");
        ServoSettings s;
        s.vmax = kNotSet;  // resolved by the control (Model::addServo)
        readOptions(L, lm, s, true, "servo");
        const ServoId id = lm.model->addServo(s);
        if (luaL_getmetatable(L, kServoType) == LUA_TNIL)
            registerRefType(L, kServoType, kServoObjectMethods, s_index, s_newindex, s_eq,
                            s_tostring);
        lua_pop(L, 1);
        auto* r = newRef<ServoRef>(L, 1, kServoType);
        r->lm = &lm;
        r->id = id;
        return 1;
    });
}

}  // namespace

const luaL_Reg kServoMethods[] = {
    {"servo", w_servo_new},
    {nullptr, nullptr},
};

}  // namespace talus::lua
