// SPDX-License-Identifier: MIT
// The metatables made from the descriptors of binding.hpp, and the one generic __index,
// __newindex, __eq and __tostring every userdata type shares.
#include "binding.hpp"

#include <algorithm>
#include <cstring>

#include "lua_bindings.hpp"
#include "talus/suggest.hpp"

namespace talus::lua {

namespace {

/// The descriptor of the running metamethod or method (its upvalue 1).
const ObjectType& descriptor(lua_State* L) {
    return *static_cast<const ObjectType*>(lua_touserdata(L, lua_upvalueindex(1)));
}

LuaModel* modelOf(void* self) { return *static_cast<LuaModel**>(self); }

const Field* findField(const ObjectType& type, const std::string& name) {
    for (const Field& f : type.fields)
        if (name == f.name) return &f;
    return nullptr;
}

bool hasWritable(const ObjectType& type) {
    return std::any_of(type.fields.begin(), type.fields.end(),
                       [](const Field& f) { return f.set != nullptr; });
}

/// Throws unless the key at `index` is a string (a field name).
void checkKey(lua_State* L, int index, const ObjectType& type) {
    if (lua_type(L, index) != LUA_TSTRING)
        throw ScriptError(std::string(type.what) + ": field names are strings (got " +
                          typeName(L, index) + ")");
}

/// "(writable: pos, vel; model properties: ...)"
std::string writableList(const ObjectType& type) {
    std::string list = "(writable: " + knownNames(type, true);
    if (type.writable_note) list += std::string("; ") + type.writable_note;
    return list + ")";
}

/// The errors of a write to field `name` that is not a writable field of `type` (f: the field,
/// when it is one).
[[noreturn]] void refuseWrite(const ObjectType& type, const Field* f, const std::string& name) {
    const std::string what = type.what;
    if (!hasWritable(type))
        throw ScriptError(what + ": its fields are read-only" +
                          (type.writable_note ? std::string(" (") + type.writable_note + ")" : ""));
    if (!f)
        throw ScriptError(what + ": unknown field '" + name + "'" +
                          didYouMeanIn(name, knownNames(type, true)) + " " + writableList(type));
    throw ScriptError(what + ": field '" + name + "' is read-only " + writableList(type));
}

/// Writes field `f` (null: not a field) of `self` from the value at `value`: the body of
/// __newindex and set{...}.
void setField(lua_State* L, const ObjectType& type, void* self, const Field* f,
              const std::string& name, int value) {
    if (!f || !f->set) refuseWrite(type, f, name);
    f->set(L, self, value, std::string(type.what) + ": '" + name + "'");
}

/// The field named by the string at stack index `key`, through the type's table name -> row
/// (upvalue `names`); null when there is none.
const Field* fieldByName(lua_State* L, const ObjectType& type, int key, int names) {
    lua_pushvalue(L, key);
    const bool found = lua_rawget(L, names) == LUA_TNUMBER;
    const lua_Integer row = lua_tointeger(L, -1);
    lua_pop(L, 1);
    return found ? &type.fields.first[row] : nullptr;
}

int objectIndex(lua_State* L) {
    const ObjectType& type = descriptor(L);
    return catchexcept(L, [&] {
        void* self = checkObject(L, 1, type, "index");
        checkKey(L, 2, type);
        lua_pushvalue(L, 2);
        if (lua_rawget(L, lua_upvalueindex(2)) != LUA_TNIL) return 1;  // a method
        lua_pop(L, 1);
        const Field* f = fieldByName(L, type, 2, lua_upvalueindex(3));
        if (!f) {
            const std::string key = lua_tostring(L, 2);
            throw ScriptError(std::string(type.what) + ": unknown field '" + key + "'" +
                              didYouMeanIn(key, knownNames(type, false)) +
                              " (known: " + knownNames(type, false) + ")");
        }
        f->get(L, self);
        return 1;
    });
}

int objectNewIndex(lua_State* L) {
    const ObjectType& type = descriptor(L);
    return catchexcept(L, [&] {
        void* self = checkObject(L, 1, type, "newindex");
        checkKey(L, 2, type);
        const std::string key = lua_tostring(L, 2);
        setField(L, type, self, fieldByName(L, type, 2, lua_upvalueindex(2)), key, 3);
        return 0;
    });
}

int objectEq(lua_State* L) {
    const ObjectType& type = descriptor(L);
    const void* a = luaL_testudata(L, 1, type.tname);
    const void* b = luaL_testudata(L, 2, type.tname);
    const std::size_t size = lua_rawlen(L, 1);
    lua_pushboolean(L, a && b && size == lua_rawlen(L, 2) && std::memcmp(a, b, size) == 0);
    return 1;
}

int objectToString(lua_State* L) {
    const ObjectType& type = descriptor(L);
    return catchexcept(L, [&] {
        void* self = luaL_testudata(L, 1, type.tname);
        if (self && type.describe)
            type.describe(L, self);
        else
            lua_pushstring(L, type.tname);
        return 1;
    });
}

void setClosure(lua_State* L, const ObjectType& type, lua_CFunction fn, const char* name) {
    lua_pushlightuserdata(L, const_cast<ObjectType*>(&type));
    lua_pushcclosure(L, fn, 1);
    lua_setfield(L, -2, name);
}

}  // namespace

std::vector<std::string> OptionTable::names() const {
    std::vector<std::string> out;
    out.reserve(options.size());
    for (const Option& o : options) out.emplace_back(o.name);
    return out;
}

std::string knownNames(const ObjectType& type, bool writable) {
    std::vector<std::string> names;
    for (const Field& f : type.fields)
        if (f.set || !writable) names.emplace_back(f.name);
    if (!writable)
        for (const Method& m : type.methods) names.push_back(std::string(m.name) + "()");
    return joinNames(names);
}

std::vector<std::string> modelMethodNames() {
    std::vector<std::string> names;
    for (const Binding* b : bindings())
        for (const Method& m : b->model_methods) names.emplace_back(m.name);
    std::sort(names.begin(), names.end());
    return names;
}

void registerObjectType(lua_State* L, const ObjectType& type) {
    luaL_newmetatable(L, type.tname);
    void* desc = const_cast<ObjectType*>(&type);
    // Upvalues of __index: the descriptor, the methods, the table field name -> row.
    lua_pushlightuserdata(L, desc);
    lua_createtable(L, 0, static_cast<int>(type.methods.size()));
    for (const Method& m : type.methods) setClosure(L, type, m.fn, m.name);
    lua_createtable(L, 0, static_cast<int>(type.fields.size()));
    for (std::size_t row = 0; row < type.fields.size(); ++row) {
        lua_pushinteger(L, static_cast<lua_Integer>(row));
        lua_setfield(L, -2, type.fields.first[row].name);
    }
    lua_pushlightuserdata(L, desc);
    lua_pushvalue(L, -2);
    lua_pushcclosure(L, objectNewIndex, 2);  // the descriptor, the table of fields
    lua_setfield(L, -5, "__newindex");
    lua_pushcclosure(L, objectIndex, 3);
    lua_setfield(L, -2, "__index");
    setClosure(L, type, objectEq, "__eq");
    setClosure(L, type, objectToString, "__tostring");
    lua_pop(L, 1);
}

void* newObject(lua_State* L, int model_index, const ObjectType& type, std::size_t size) {
    model_index = lua_absindex(L, model_index);
    void* self = lua_newuserdatauv(L, size, 1);
    std::memset(self, 0, size);  // __eq compares blocks: no stray padding bytes
    luaL_setmetatable(L, type.tname);
    lua_pushvalue(L, model_index);
    lua_setiuservalue(L, -2, 1);
    *static_cast<LuaModel**>(self) = static_cast<LuaModel*>(lua_touserdata(L, model_index));
    return self;
}

void* checkObject(lua_State* L, int index, const ObjectType& type, const char* fn) {
    void* self = luaL_testudata(L, index, type.tname);
    if (!self)
        throw ScriptError(std::string(type.what) + ": call it as a method, " + type.var + ":" + fn +
                          "(...) (the first argument is a " + typeName(L, index) + ", not a " +
                          type.what + ")");
    if (!modelOf(self)->model) throw ScriptError(std::string(type.what) + ": its model was closed");
    return self;
}

int objectSet(lua_State* L) {
    const ObjectType& type = descriptor(L);
    return catchexcept(L, [&] {
        void* self = checkObject(L, 1, type, "set");
        const std::string what = type.what;
        applyFields(L, 2, what + ": set{...}",
                    what + ": set{...} takes named fields (name = value, ...)",
                    [&](const std::string& key, int value) {
                        setField(L, type, self, findField(type, key), key, value);
                    });
        return 0;
    });
}

}  // namespace talus::lua
