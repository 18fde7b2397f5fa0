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

struct ServoRef {
    LuaModel* lm;
    ServoId id;
};

const Option kServoSetOptionRows[] = {
    {"walls", "talus.Wall[]", "the walls the servo moves (one target for all of them)"},
    {"dirs", "talus.Vec[]", "each wall's direction into the material (default: its normal)"},
    {"stress", "number", "target stress [Pa], compression positive"},
    {"force", "number", "target force [N] over the walls, compression positive"},
    {"rate", "number", "target strain rate [1/s] over the gauge length"},
    {"velocity", "number", "target wall speed [m/s] into the material"},
    {"length", "number", "[m] the length that turns force into stress"},
    {"span", "talus.Wall[]", "{wall_a, wall_b}: the length is their distance, every step"},
    {"gauge", "number", "[m] the gauge length of the strain rate"},
    {"ramp", "integer", "steps over which the target grows from zero"},
    {"alpha", "number", "PFC's relaxation factor in (0, 2)"},
    {"vmax", "number", "speed cap [m/s] (default set by the control)"},
    {"on", "boolean", "false stops the walls along their directions"},
    {"hold", "talus.ServoHoldOptions|false",
     "rate, velocity: stand still while the mechanical ratio is above a limit; false: off"},
};

const Option kServoHoldOptionRows[] = {
    {"ratio", "number", "the walls stop when PFC's mechanical ratio rises above this"},
    {"resume", "number", "... and move again once it is at or below this (default: ratio)"},
    {"max_steps", "integer", "the longest hold [steps]; then the walls move until the ratio falls"},
};

const OptionTable kServoHoldOptions = {
    "talus.ServoHoldOptions",
    "hold = {...}: a strain-controlled test with equilibrium holds (the walls wait for the "
    "material to settle)",
    kServoHoldOptionRows};

const OptionTable kServoSetOptions = {
    "talus.ServoSetOptions",
    "m:servo{...} / sv:set{...}: a new servo needs walls and one target; set changes what it gives",
    kServoSetOptionRows};

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

/// hold = {ratio = r, max_steps = n}, or false (off).
void readHold(lua_State* L, const Options& o, ServoSettings& s, const std::string& what) {
    if (o.push("hold") == LUA_TBOOLEAN && !lua_toboolean(L, -1)) {
        lua_pop(L, 1);
        s.hold_ratio = kNotSet, s.hold_resume = kNotSet, s.hold_max_steps = 0;
        return;
    }
    const Options h(L, lua_gettop(L), what + ": hold", kServoHoldOptions);
    if (!h.has("ratio") || !h.has("max_steps"))
        throw ScriptError(what +
                          ": hold = {ratio = r, max_steps = n}: give the ratio limit and the "
                          "longest hold in steps");
    s.hold_ratio = h.number("ratio", 0.0);
    s.hold_max_steps = h.integer("max_steps", 0);
    s.hold_resume = h.has("resume") ? h.number("resume", 0.0) : kNotSet;
    lua_pop(L, 1);
}

/// Applies the options at stack 2 over `s` (a new servo starts from defaults and needs one
/// target; a later call changes only what it gives).
void readOptions(lua_State* L, const LuaModel& lm, ServoSettings& s, bool create,
                 const std::string& what) {
    const ServoControl before = s.control;
    const Options o(L, 2, what, kServoSetOptions);
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
    if (o.has("hold")) readHold(L, o, s, what);
}

void pushNumberOrNil(lua_State* L, double v) {
    if (std::isnan(v))
        lua_pushnil(L);
    else
        lua_pushnumber(L, v);
}

/// {control, target, on, walls, dirs, length, gauge, ramp, alpha, vmax, steps, force, forces,
/// stress, knest, speed, displacement, strain (rate: displacement over half the gauge); with a
/// hold: hold = {ratio, resume, max_steps}, ratio (the last step's), held (steps stood still),
/// holds, holds_capped, hold_run}
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
        {"ratio", st.ratio},
    };
    for (const auto& [name, v] : numbers) {
        pushNumberOrNil(L, v);
        lua_setfield(L, -2, name);
    }
    lua_pushinteger(L, static_cast<lua_Integer>(s.ramp));
    lua_setfield(L, -2, "ramp");
    lua_pushinteger(L, static_cast<lua_Integer>(st.steps));
    lua_setfield(L, -2, "steps");
    if (std::isnan(s.hold_ratio)) return;
    lua_createtable(L, 0, 3);
    lua_pushnumber(L, s.hold_ratio);
    lua_setfield(L, -2, "ratio");
    lua_pushnumber(L, s.hold_resume);
    lua_setfield(L, -2, "resume");
    lua_pushinteger(L, static_cast<lua_Integer>(s.hold_max_steps));
    lua_setfield(L, -2, "max_steps");
    lua_setfield(L, -2, "hold");
    const std::pair<const char*, int64_t> counts[] = {{"held", st.held},
                                                      {"holds", st.holds},
                                                      {"holds_capped", st.holds_capped},
                                                      {"hold_run", st.hold_run}};
    for (const auto& [name, v] : counts) {
        lua_pushinteger(L, static_cast<lua_Integer>(v));
        lua_setfield(L, -2, name);
    }
}

const ObjectType& servoObject();

ServoRef& checkServo(lua_State* L, int index, const char* fn) {
    return checkObject<ServoRef>(L, index, servoObject(), fn);
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

const Field kServoFields[] = {
    {"id", "integer", "the servo's number",
     [](lua_State* L, void* self) { lua_pushinteger(L, static_cast<ServoRef*>(self)->id.index); }},
};

const Method kServoObjectMethods[] = {
    {"set", s_set, "changes the options given; returns the state", "options: talus.ServoSetOptions",
     "table"},
    {"state", s_state,
     "{control, target, on, walls, dirs, forces, stress, force, speed, strain, steps, held, ...}",
     "", "table"},
    {"remove", s_remove, "removes the servo (its walls keep their last velocity)", "", ""},
};

void describe(lua_State* L, void* self) {
    lua_pushfstring(L, "servo %d", static_cast<int>(static_cast<ServoRef*>(self)->id.index));
}

const ObjectType kServoObject = {
    "talus.Servo", "servo",
    "sv",          "drives a set of walls to a stress, force, strain rate or velocity",
    kServoFields,  kServoObjectMethods,
    describe,      "change it with sv:set{...}",
};

const ObjectType& servoObject() { return kServoObject; }

int w_servo_new(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "servo");
        ServoSettings s;
        s.vmax = kNotSet;  // resolved by the control (Model::addServo)
        readOptions(L, lm, s, true, "servo");
        const ServoId id = lm.model->addServo(s);
        newObject<ServoRef>(L, 1, kServoObject)->id = id;
        return 1;
    });
}

const Method kServosModelMethods[] = {
    {"servo", w_servo_new, "a servo over a set of walls, run every step",
     "options: talus.ServoSetOptions", "talus.Servo"},
};
const ObjectType* const kServosTypes[] = {&kServoObject};
const OptionTable* const kServosOptionTables[] = {&kServoSetOptions, &kServoHoldOptions};

}  // namespace

extern const Binding kServosBinding = {"servos",     kServosModelMethods, {},
                                       kServosTypes, kServosOptionTables, {}};

}  // namespace talus::lua
