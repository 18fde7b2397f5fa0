// SPDX-License-Identifier: MIT
// Wall userdata: a chain of segments moved by prescribed velocity and spin (PFC walls).
#include <algorithm>
#include <cmath>
#include <cstring>

#include "lua_bindings.hpp"

namespace talus::lua {

namespace {

struct WallRef {
    LuaModel* lm;
    WallId id;
};

enum class Field { Id, Points, Vel, Spin, Center, Force, Kn, Ks, Fric, Groups };

struct FieldInfo {
    const char* name;
    Field field;
    bool writable;
};

const FieldInfo kFields[] = {
    {"id", Field::Id, false},        {"points", Field::Points, false},
    {"vel", Field::Vel, true},       {"spin", Field::Spin, true},
    {"center", Field::Center, true}, {"force", Field::Force, false},
    {"kn", Field::Kn, true},         {"ks", Field::Ks, true},
    {"fric", Field::Fric, true},     {"groups", Field::Groups, false},
};

std::string knownFields(bool writable_only) {
    std::vector<std::string> names;
    for (const FieldInfo& f : kFields)
        if (f.writable || !writable_only) names.push_back(f.name);
    if (!writable_only)
        names.push_back("set()"), names.push_back("add_group()"), names.push_back("servo()");
    return joinNames(names);
}

const FieldInfo* findField(const std::string& name) {
    for (const FieldInfo& f : kFields)
        if (name == f.name) return &f;
    return nullptr;
}

WallRef& checkWall(lua_State* L, int index, const char* fn) {
    auto* w = static_cast<WallRef*>(testUserdata(L, index, kWallType));
    if (!w)
        throw ScriptError(std::string("wall: call it as a method, w:") + fn +
                          "(...) (the first argument is a " + typeName(L, index) + ", not a wall)");
    if (!w->lm->model) throw ScriptError("wall: its model was closed");
    return *w;
}

std::string fieldKey(lua_State* L, int index) {
    if (lua_type(L, index) != LUA_TSTRING)
        throw ScriptError("wall: field names are strings (got " + typeName(L, index) + ")");
    return lua_tostring(L, index);
}

void pushField(lua_State* L, const WallRef& w, Field f) {
    Model& m = *w.lm->model;
    auto optional = [&](const char* prop) {
        const double v = m.wallContactProp(w.id, prop);
        if (std::isnan(v))
            lua_pushnil(L);
        else
            lua_pushnumber(L, v);
    };
    switch (f) {
        case Field::Id:
            (void)m.wallVel(w.id);  // checks the id
            lua_pushinteger(L, w.id.index);
            break;
        case Field::Points: {
            const std::vector<Vec2> pts = m.wallPoints(w.id);
            lua_createtable(L, static_cast<int>(pts.size()), 0);
            for (std::size_t i = 0; i < pts.size(); ++i) {
                pushVec(L, pts[i]);
                lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
            }
            break;
        }
        case Field::Vel:
            pushVec(L, m.wallVel(w.id));
            break;
        case Field::Spin:
            lua_pushnumber(L, m.wallSpin(w.id));
            break;
        case Field::Center:
            pushVec(L, m.wallCenter(w.id));
            break;
        case Field::Force:
            pushVec(L, m.wallForce(w.id));
            break;
        case Field::Kn:
            optional("kn");
            break;
        case Field::Ks:
            optional("ks");
            break;
        case Field::Fric:
            optional("fric");
            break;
        case Field::Groups:
            pushStringList(L, m.wallGroups(w.id));
            break;
    }
}

void setField(lua_State* L, const WallRef& w, const std::string& name, int index) {
    const FieldInfo* info = findField(name);
    if (!info)
        throw ScriptError("wall: unknown field '" + name + "'" +
                          didYouMeanIn(name, knownFields(true)) +
                          " (writable: " + knownFields(true) + ")");
    if (!info->writable)
        throw ScriptError("wall: field '" + name +
                          "' is read-only (writable: " + knownFields(true) + ")");
    Model& m = *w.lm->model;
    const std::string what = "wall: '" + name + "'";
    switch (info->field) {
        case Field::Vel:
            m.setWallVel(w.id, toVec(L, index, what));
            break;
        case Field::Spin:
            m.setWallSpin(w.id, toNumber(L, index, what));
            break;
        case Field::Center: {
            const Vec2 c = toVec(L, index, what);
            if (!std::isfinite(c.x()) || !std::isfinite(c.y()))
                throw ScriptError("wall: 'center' must be finite");
            m.setWallCenter(w.id, c);
            break;
        }
        case Field::Kn:
        case Field::Ks:
        case Field::Fric: {
            const double v = lua_isnil(L, index) ? kNotSet : toNumber(L, index, what);
            m.setWallContactProp(w.id, name, v);
            if (info->field == Field::Fric) warnImplausibleFriction(w.lm, "wall", {{name, v}});
            break;
        }
        default:
            break;
    }
}

int w_index(lua_State* L) {
    return catchexcept(L, [&] {
        WallRef& w = checkWall(L, 1, "index");
        const std::string key = fieldKey(L, 2);
        if (key == "set" || key == "add_group" || key == "servo") {
            lua_pushstring(L, key.c_str());
            lua_rawget(L, lua_upvalueindex(1));
            return 1;
        }
        const FieldInfo* info = findField(key);
        if (!info)
            throw ScriptError("wall: unknown field '" + key + "'" +
                              didYouMeanIn(key, knownFields(false)) +
                              " (known: " + knownFields(false) + ")");
        pushField(L, w, info->field);
        return 1;
    });
}

int w_newindex(lua_State* L) {
    return catchexcept(L, [&] {
        WallRef& w = checkWall(L, 1, "newindex");
        setField(L, w, fieldKey(L, 2), 3);
        return 0;
    });
}

int w_set(lua_State* L) {
    return catchexcept(L, [&] {
        WallRef& w = checkWall(L, 1, "set");
        applyFields(L, 2, "wall: set{...}", "wall: set{...} takes named fields (vel = {1, 0}, ...)",
                    [&](const std::string& key, int value) { setField(L, w, key, value); });
        return 0;
    });
}

int w_eq(lua_State* L) {
    const auto* a = static_cast<WallRef*>(testUserdata(L, 1, kWallType));
    const auto* b = static_cast<WallRef*>(testUserdata(L, 2, kWallType));
    lua_pushboolean(L, a && b && a->lm == b->lm && a->id == b->id);
    return 1;
}

int w_tostring(lua_State* L) {
    const auto* w = static_cast<WallRef*>(testUserdata(L, 1, kWallType));
    lua_pushfstring(L, "wall %d", w ? static_cast<int>(w->id.index) : 0);
    return 1;
}

int w_add_group(lua_State* L) {
    return catchexcept(L, [&] {
        WallRef& w = checkWall(L, 1, "add_group");
        if (lua_type(L, 2) != LUA_TSTRING)
            throw ScriptError("wall: add_group(name) needs a group name (got " + typeName(L, 2) +
                              ")");
        w.lm->model->addWallGroup(w.id, lua_tostring(L, 2));
        return 0;
    });
}

int w_servo(lua_State* L) {
    return catchexcept(L, [&] {
        WallRef& w = checkWall(L, 1, "servo");
        return servoWall(L, *w.lm, w.id);  // wrap_servo.cpp
    });
}

const luaL_Reg kWallMethods[] = {
    {"set", w_set},
    {"add_group", w_add_group},
    {"servo", w_servo},
    {nullptr, nullptr},
};

}  // namespace

void pushWall(lua_State* L, int model_index, WallId id) {
    model_index = lua_absindex(L, model_index);
    auto* w = newRef<WallRef>(L, model_index, kWallType);
    w->lm = static_cast<LuaModel*>(lua_touserdata(L, model_index));
    w->id = id;
}

void openWall(lua_State* L) {
    registerRefType(L, kWallType, kWallMethods, w_index, w_newindex, w_eq, w_tostring);
}

}  // namespace talus::lua
