// SPDX-License-Identifier: MIT
//
// Getters and setters of a userdata type's fields (binding.hpp, Field) made from the engine's
// own accessors, so that a field is one row: {"pos", "talus.Vec", "centre [m]",
// get<BallRef, &Model::ballPos>, set<BallRef, &Model::setBallPos>}. The Ref struct of the type
// holds `LuaModel* lm` and the body's `id`; the value crosses as its C++ type says (a number, a
// vector {x, y}, a boolean, a string, a list of strings).
#pragma once

#include <string>
#include <type_traits>
#include <vector>

#include "lua_bindings.hpp"

namespace talus::lua::fields {

inline void pushValue(lua_State* L, double v) { lua_pushnumber(L, v); }
inline void pushValue(lua_State* L, const Vec2& v) { pushVec(L, v); }
inline void pushValue(lua_State* L, const std::vector<std::string>& v) { pushStringList(L, v); }
inline void pushValue(lua_State* L, bool v) { lua_pushboolean(L, v); }
inline void pushValue(lua_State* L, const std::string& v) {
    lua_pushlstring(L, v.data(), v.size());
}

inline void readValue(lua_State* L, int index, const std::string& what, double& out) {
    out = toNumber(L, index, what);
}
inline void readValue(lua_State* L, int index, const std::string& what, Vec2& out) {
    out = toVec(L, index, what);
}

template <class Ref>
Model& model(void* self) {
    return *static_cast<Ref*>(self)->lm->model;
}
template <class Ref>
auto id(void* self) {
    return static_cast<Ref*>(self)->id;
}

/// The type a setter Model::setX(id, value) takes.
template <class Id, class T>
std::decay_t<T> valueOf(void (Model::*)(Id, T));

/// Pushes (model.*Get)(id).
template <class Ref, auto Get>
void get(lua_State* L, void* self) {
    pushValue(L, (model<Ref>(self).*Get)(id<Ref>(self)));
}

/// (model.*Set)(id, the value at `value`).
template <class Ref, auto Set>
void set(lua_State* L, void* self, int value, const std::string& what) {
    decltype(valueOf(Set)) v{};
    readValue(L, value, what, v);
    (model<Ref>(self).*Set)(id<Ref>(self), v);
}

/// A body's own contact property (kn, ks, fric): nil while it is not set.
template <class Ref, auto Get, const char* Name>
void getProp(lua_State* L, void* self) {
    pushOptional(L, (model<Ref>(self).*Get)(id<Ref>(self), Name));
}

/// Writes a body's own contact property; nil removes it (its contacts use the model's again).
/// A friction coefficient that looks like an angle warns (warnImplausibleFriction).
template <class Ref, auto Set, const char* Name>
void setProp(lua_State* L, void* self, int value, const std::string& what) {
    const double v = lua_isnil(L, value) ? kNotSet : toNumber(L, value, what);
    (model<Ref>(self).*Set)(id<Ref>(self), Name, v);
    if (std::string(Name) == "fric")
        warnImplausibleFriction(static_cast<Ref*>(self)->lm, what.substr(0, what.find(':')),
                                {{Name, v}});
}

inline constexpr char kKn[] = "kn";
inline constexpr char kKs[] = "ks";
inline constexpr char kFric[] = "fric";

/// The fixed components {"x", "y", "spin"} through Model's getter and setter of a fixity.
template <class Ref, auto Get>
void getFixity(lua_State* L, void* self) {
    pushFixity(L, (model<Ref>(self).*Get)(id<Ref>(self)));
}
template <class Ref, auto Set>
void setFixity(lua_State* L, void* self, int value, const std::string& what) {
    (model<Ref>(self).*Set)(id<Ref>(self), toFixity(L, value, what));
}

/// Whether the body is alive (never an error).
template <class Ref>
void getAlive(lua_State* L, void* self) {
    lua_pushboolean(L, model<Ref>(self).isAlive(id<Ref>(self)));
}

/// The body's handle number (b.id); reading it from a deleted body is an error as for any field
/// (Check: a Model accessor of the body, which checks the id).
template <class Ref, auto Check>
void getIndex(lua_State* L, void* self) {
    (void)(model<Ref>(self).*Check)(id<Ref>(self));
    lua_pushinteger(L, id<Ref>(self).index);
}

/// A method without arguments that is the Model's Act(id): b:delete(), tr:stop(). Its upvalue 1
/// is the type's descriptor, as registerObjectType gives every method.
template <class Ref, auto Act, const char* Name>
int actMethod(lua_State* L) {
    const auto& type = *static_cast<const ObjectType*>(lua_touserdata(L, lua_upvalueindex(1)));
    return catchexcept(L, [&] {
        Ref& r = checkObject<Ref>(L, 1, type, Name);
        ((*r.lm->model).*Act)(r.id);
        return 0;
    });
}
inline constexpr char kDelete[] = "delete";

/// b:add_group(name): the Model's Add(id, name) for the body (a method; its upvalue 1 is the
/// type's descriptor, as registerObjectType gives every method).
template <class Ref, auto Add>
int addGroup(lua_State* L) {
    const auto& type = *static_cast<const ObjectType*>(lua_touserdata(L, lua_upvalueindex(1)));
    return catchexcept(L, [&] {
        Ref& r = checkObject<Ref>(L, 1, type, "add_group");
        if (lua_type(L, 2) != LUA_TSTRING)
            throw ScriptError(std::string(type.what) +
                              ": add_group(name) needs a group name (got " + typeName(L, 2) + ")");
        ((*r.lm->model).*Add)(r.id, lua_tostring(L, 2));
        return 0;
    });
}

/// tostring() of a body: "ball 3 at (x, y)", or "ball 3 (deleted)" (Pos: the Model's position).
template <class Ref, auto Pos, const char* What>
void describeBody(lua_State* L, void* self) {
    const Ref& r = *static_cast<const Ref*>(self);
    const auto index = static_cast<int>(r.id.index);
    if (!r.lm->model || !r.lm->model->isAlive(r.id)) {
        lua_pushfstring(L, "%s %d (deleted)", What, index);
        return;
    }
    const Vec2 p = ((*r.lm->model).*Pos)(r.id);
    lua_pushfstring(L, "%s %d at (%f, %f)", What, index, p.x(), p.y());
}

}  // namespace talus::lua::fields
