// SPDX-License-Identifier: MIT
// Ball userdata: an id and its model. Fields read and write the engine state by id, so a
// ball deleted in the meantime gives the engine's "ball 3 was deleted (stale id)".
#include <algorithm>
#include <cmath>
#include <cstring>

#include "lua_bindings.hpp"

namespace talus::lua {

namespace {

enum class Field {
    Id,
    Pos,
    Vel,
    Spin,
    Angle,
    Radius,
    Mass,
    Inertia,
    Density,
    Force,
    Moment,
    Fapp,
    Mapp,
    Groups,
    Fix,
    Kn,
    Ks,
    Fric,
    Alive,
};

struct FieldInfo {
    const char* name;
    Field field;
    bool writable;
};

const FieldInfo kFields[] = {
    {"id", Field::Id, false},          {"pos", Field::Pos, true},
    {"vel", Field::Vel, true},         {"spin", Field::Spin, true},
    {"angle", Field::Angle, false},    {"radius", Field::Radius, true},
    {"mass", Field::Mass, false},      {"inertia", Field::Inertia, false},
    {"density", Field::Density, true}, {"force", Field::Force, false},
    {"moment", Field::Moment, false},  {"fapp", Field::Fapp, true},
    {"mapp", Field::Mapp, true},       {"groups", Field::Groups, false},
    {"fix", Field::Fix, true},         {"kn", Field::Kn, true},
    {"ks", Field::Ks, true},           {"fric", Field::Fric, true},
    {"alive", Field::Alive, false},
};

const char* const kMethods[] = {"set", "delete", "add_group"};

std::string knownFields(bool writable_only) {
    std::vector<std::string> names;
    for (const FieldInfo& f : kFields)
        if (f.writable || !writable_only) names.push_back(f.name);
    if (!writable_only)
        for (const char* m : kMethods) names.push_back(std::string(m) + "()");
    return joinNames(names);
}

const FieldInfo* findField(const char* name) {
    for (const FieldInfo& f : kFields)
        if (std::strcmp(f.name, name) == 0) return &f;
    return nullptr;
}

BallRef& checkBall(lua_State* L, int index, const char* fn) {
    BallRef* b = testBall(L, index);
    if (!b)
        throw ScriptError(std::string("ball: call it as a method, b:") + fn +
                          "(...) (the first argument is a " + typeName(L, index) + ", not a ball)");
    if (!b->lm->model) throw ScriptError("ball: its model was closed");
    return *b;
}

std::string fieldKey(lua_State* L, int index) {
    if (lua_type(L, index) != LUA_TSTRING)
        throw ScriptError("ball: field names are strings (got " + typeName(L, index) + ")");
    return lua_tostring(L, index);
}

void pushOptional(lua_State* L, double v) {
    if (std::isnan(v))
        lua_pushnil(L);
    else
        lua_pushnumber(L, v);
}

void pushFixity(lua_State* L, uint8_t fix) {
    std::vector<std::string> names;
    if (fix & kFixX) names.push_back("x");
    if (fix & kFixY) names.push_back("y");
    if (fix & kFixSpin) names.push_back("spin");
    pushStringList(L, names);
}

uint8_t toFixity(lua_State* L, int index) {
    if (lua_type(L, index) == LUA_TBOOLEAN)
        return lua_toboolean(L, index) ? uint8_t(kFixX | kFixY | kFixSpin) : uint8_t(0);
    if (lua_isnil(L, index)) return 0;
    if (lua_type(L, index) != LUA_TTABLE)
        throw ScriptError("ball: 'fix' must be a list such as {\"x\", \"spin\"}, or true/false");
    uint8_t fix = 0;
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, index));
    for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, index, i);
        int which = -1;
        try {
            which = toEnum(L, -1, "ball: 'fix' entry " + std::to_string(i), {"x", "y", "spin"});
        } catch (...) {
            lua_pop(L, 1);
            throw;
        }
        lua_pop(L, 1);
        fix |= which == 0 ? kFixX : which == 1 ? kFixY : kFixSpin;
    }
    return fix;
}

void pushField(lua_State* L, const BallRef& b, Field f) {
    Model& m = *b.lm->model;
    const BallId id = b.id;
    switch (f) {
        case Field::Id:
            // Checked: reading the id of a deleted ball is an error like any other field.
            (void)m.ballRadius(id);
            lua_pushinteger(L, id.index);
            break;
        case Field::Pos:
            pushVec(L, m.ballPos(id));
            break;
        case Field::Vel:
            pushVec(L, m.ballVel(id));
            break;
        case Field::Spin:
            lua_pushnumber(L, m.ballSpin(id));
            break;
        case Field::Angle:
            lua_pushnumber(L, m.ballAngle(id));
            break;
        case Field::Radius:
            lua_pushnumber(L, m.ballRadius(id));
            break;
        case Field::Mass:
            lua_pushnumber(L, m.ballMass(id));
            break;
        case Field::Inertia:
            lua_pushnumber(L, m.ballInertia(id));
            break;
        case Field::Density:
            lua_pushnumber(L, m.ballDensity(id));
            break;
        case Field::Force:
            pushVec(L, m.ballForce(id));
            break;
        case Field::Moment:
            lua_pushnumber(L, m.ballMoment(id));
            break;
        case Field::Fapp:
            pushVec(L, m.ballAppliedForce(id));
            break;
        case Field::Mapp:
            lua_pushnumber(L, m.ballAppliedMoment(id));
            break;
        case Field::Groups:
            pushStringList(L, m.ballGroups(id));
            break;
        case Field::Fix:
            pushFixity(L, m.ballFixity(id));
            break;
        case Field::Kn:
            pushOptional(L, m.ballContactProp(id, "kn"));
            break;
        case Field::Ks:
            pushOptional(L, m.ballContactProp(id, "ks"));
            break;
        case Field::Fric:
            pushOptional(L, m.ballContactProp(id, "fric"));
            break;
        case Field::Alive:
            lua_pushboolean(L, m.isAlive(id));
            break;
    }
}

/// Sets field `name` from the value at `index`.
void setField(lua_State* L, const BallRef& b, const std::string& name, int index) {
    const FieldInfo* info = findField(name.c_str());
    if (!info)
        throw ScriptError("ball: unknown field '" + name + "'" +
                          didYouMeanIn(name, knownFields(true)) +
                          " (writable: " + knownFields(true) + ")");
    if (!info->writable)
        throw ScriptError("ball: field '" + name +
                          "' is read-only (writable: " + knownFields(true) + ")");
    Model& m = *b.lm->model;
    const BallId id = b.id;
    const std::string what = "ball: '" + name + "'";
    switch (info->field) {
        case Field::Pos:
            m.setBallPos(id, toVec(L, index, what));
            break;
        case Field::Vel:
            m.setBallVel(id, toVec(L, index, what));
            break;
        case Field::Spin:
            m.setBallSpin(id, toNumber(L, index, what));
            break;
        case Field::Radius:
            m.setBallRadius(id, toNumber(L, index, what));
            break;
        case Field::Density:
            m.setBallDensity(id, toNumber(L, index, what));
            break;
        case Field::Fapp:
            m.setBallAppliedForce(id, toVec(L, index, what));
            break;
        case Field::Mapp:
            m.setBallAppliedMoment(id, toNumber(L, index, what));
            break;
        case Field::Fix:
            m.setBallFixity(id, toFixity(L, index));
            break;
        case Field::Kn:
        case Field::Ks:
        case Field::Fric: {
            // nil removes the ball's own value: its contacts use the model's property again.
            const double v = lua_isnil(L, index) ? kNotSet : toNumber(L, index, what);
            m.setBallContactProp(id, name, v);
            if (info->field == Field::Fric) warnImplausibleFriction(b.lm, "ball", {{name, v}});
            break;
        }
        default:
            break;
    }
}

int w_index(lua_State* L) {
    return catchexcept(L, [&] {
        BallRef& b = checkBall(L, 1, "index");
        const std::string key = fieldKey(L, 2);
        for (const char* m : kMethods)
            if (key == m) {
                // The methods live in the metatable's "methods" table (upvalue 1).
                lua_getfield(L, lua_upvalueindex(1), m);
                return 1;
            }
        const FieldInfo* info = findField(key.c_str());
        if (!info)
            throw ScriptError("ball: unknown field '" + key + "'" +
                              didYouMeanIn(key, knownFields(false)) +
                              " (known: " + knownFields(false) + ")");
        pushField(L, b, info->field);
        return 1;
    });
}

int w_newindex(lua_State* L) {
    return catchexcept(L, [&] {
        BallRef& b = checkBall(L, 1, "newindex");
        setField(L, b, fieldKey(L, 2), 3);
        return 0;
    });
}

int w_set(lua_State* L) {
    return catchexcept(L, [&] {
        BallRef& b = checkBall(L, 1, "set");
        applyFields(L, 2, "ball: set{...}", "ball: set{...} takes named fields (radius = 0.2, ...)",
                    [&](const std::string& key, int value) { setField(L, b, key, value); });
        return 0;
    });
}

int w_delete(lua_State* L) {
    return catchexcept(L, [&] {
        BallRef& b = checkBall(L, 1, "delete");
        b.lm->model->deleteBall(b.id);
        return 0;
    });
}

int w_add_group(lua_State* L) {
    return catchexcept(L, [&] {
        BallRef& b = checkBall(L, 1, "add_group");
        if (lua_type(L, 2) != LUA_TSTRING)
            throw ScriptError("ball: add_group(name) needs a group name (got " + typeName(L, 2) +
                              ")");
        b.lm->model->addBallGroup(b.id, lua_tostring(L, 2));
        return 0;
    });
}

int w_eq(lua_State* L) {
    const BallRef* a = testBall(L, 1);
    const BallRef* b = testBall(L, 2);
    lua_pushboolean(L, a && b && a->lm == b->lm && a->id == b->id);
    return 1;
}

int w_tostring(lua_State* L) {
    return catchexcept(L, [&] {
        const BallRef* b = testBall(L, 1);
        if (!b || !b->lm->model || !b->lm->model->isAlive(b->id)) {
            lua_pushfstring(L, "ball %d (deleted)", b ? static_cast<int>(b->id.index) : 0);
            return 1;
        }
        const Vec2 p = b->lm->model->ballPos(b->id);
        lua_pushfstring(L, "ball %d at (%f, %f)", static_cast<int>(b->id.index), p.x(), p.y());
        return 1;
    });
}

const luaL_Reg kBallMethods[] = {
    {"set", w_set},
    {"delete", w_delete},
    {"add_group", w_add_group},
    {nullptr, nullptr},
};

}  // namespace

BallRef* testBall(lua_State* L, int index) {
    return static_cast<BallRef*>(testUserdata(L, index, kBallType));
}

void pushBall(lua_State* L, int model_index, BallId id) {
    model_index = lua_absindex(L, model_index);
    auto* b = newRef<BallRef>(L, model_index, kBallType);
    b->lm = static_cast<LuaModel*>(lua_touserdata(L, model_index));
    b->id = id;
}

void openBall(lua_State* L) {
    registerRefType(L, kBallType, kBallMethods, w_index, w_newindex, w_eq, w_tostring);
}

}  // namespace talus::lua
