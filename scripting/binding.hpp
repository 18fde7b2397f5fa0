// SPDX-License-Identifier: MIT
//
// The registration tables of the Lua API. Every bound type has one descriptor (its fields, with
// a getter and a setter, its methods, a line of documentation for each), every call that takes
// a table of options has one option table, and every wrap_<thing>.cpp hands its rows to the
// module as one Binding. From these rows, and from nothing else, are made:
//   * the metatables and the one generic __index / __newindex / __eq / __tostring (binding.cpp);
//   * the lists of known names that an unknown name's error gives, with its "did you mean";
//   * the LuaLS annotations an editor completes from (`talus --lua-annotations FILE`,
//     lua_annotations.cpp).
// Adding a method, a field or an option is one row, as adding a granular sub-model to LAMMPS is
// a row of its registration table or a shape pair to Box2D a row of its s_registers.
//
// Types are written as LuaLS writes them: "number", "integer", "boolean", "string", "string[]",
// "talus.Vec" (a vector {x, y}), "talus.Ball", "\"disk\"|\"sphere\"" (an enum), "fun(m:
// talus.Model)".
#pragma once

#include <cstddef>
#include <lua.hpp>
#include <string>
#include <vector>

#include "lua_runtime.hpp"

namespace talus::lua {

/// A view of a static array of rows (C++17 has no std::span).
template <class T>
struct Rows {
    const T* first = nullptr;
    std::size_t count = 0;
    constexpr Rows() = default;
    template <std::size_t N>
    constexpr Rows(const T (&rows)[N]) : first(rows), count(N) {}  // NOLINT: implicit on purpose
    const T* begin() const { return first; }
    const T* end() const { return first + count; }
    std::size_t size() const { return count; }
    bool empty() const { return count == 0; }
};

/// One method of a type (m:ball, b:set), or one function of the module (talus.map).
struct Method {
    const char* name;
    lua_CFunction fn;
    const char* doc;      ///< one line, shown by the editor
    const char* params;   ///< "def: talus.BallDef", "n: integer, every?: integer"; "" for none
    const char* returns;  ///< "talus.Ball", "number, string"; "" when it returns nothing
};

/// One option of a table of options (m:ball{pos =, radius =, ...}).
struct Option {
    const char* name;
    const char* type;
    const char* doc;
    bool required = false;  ///< the call refuses a table without it
};

/// The options one call takes in a table: what Options accepts (an unknown name is an error that
/// lists them all) and the class an editor completes the table from.
struct OptionTable {
    const char* cls;  ///< "talus.BallDef"
    const char* doc;
    Rows<Option> options;
    /// The option names, in the table's order.
    std::vector<std::string> names() const;
};

/// One field of a userdata type: `b.pos` reads it through get, `b.pos = v` writes it through set.
/// `self` is the userdata's block (a Ref struct of its file); the userdata is at stack index 1.
struct Field {
    const char* name;
    const char* type;
    const char* doc;
    void (*get)(lua_State* L, void* self);  ///< pushes the value
    /// Writes the value at stack index `value`; `what` names the field in errors ("ball: 'pos'").
    /// Null: the field is read-only.
    void (*set)(lua_State* L, void* self, int value, const std::string& what) = nullptr;
};

/// A userdata type that refers into a model: a ball, a wall, a contact, a history... Its block
/// is a standard-layout struct whose first member is `LuaModel* lm` (the generic functions read
/// the model through it); newObject() zero-fills the block, and two userdata of the type are
/// equal (==) when their blocks are.
struct ObjectType {
    const char* tname;  ///< the metatable's name and the editor's class: "talus.Ball"
    const char* what;   ///< the type in messages: "ball"
    const char* var;    ///< a variable in messages: "b" (call it as a method, b:set(...))
    const char* doc;
    Rows<Field> fields;
    Rows<Method> methods;
    /// tostring(): pushes the text (self is never null; its model may be closed).
    void (*describe)(lua_State* L, void* self) = nullptr;
    /// Said after the writable fields in errors: "model properties: c:set_prop(name, value)".
    const char* writable_note = nullptr;
};

/// A value of the module (talus.version).
struct Constant {
    const char* name;
    const char* type;
    const char* doc;
    void (*push)(lua_State* L);
};

/// What one wrap_<thing>.cpp adds to the API. luaopen_talus walks every Binding (bindings(),
/// lua_module.cpp): the model's methods, the module's functions and values, the userdata types;
/// the option tables are there for the annotations.
struct Binding {
    const char* name;  ///< "bodies": a section title in the annotations
    Rows<Method> model_methods;
    Rows<Method> functions;
    Rows<const ObjectType*> types;
    Rows<const OptionTable*> options;
    Rows<Constant> constants;
};

/// Every Binding of the module, in the order luaopen_talus registers them (lua_module.cpp).
Rows<const Binding*> bindings();

// ------------------------------------------------------------------ generic functions

/// Registers the metatable of `type`: its methods (each a closure with the descriptor as upvalue
/// 1, so objectSet can find it) reached through the generic __index, and the generic
/// __newindex, __eq and __tostring.
void registerObjectType(lua_State* L, const ObjectType& type);

/// A new userdata of `type` with a zero-filled block of `size` bytes, whose user value keeps the
/// model userdata at `model_index` alive. Returns the block (its first member is the LuaModel*).
void* newObject(lua_State* L, int model_index, const ObjectType& type, std::size_t size);
template <class Ref>
Ref* newObject(lua_State* L, int model_index, const ObjectType& type) {
    return static_cast<Ref*>(newObject(L, model_index, type, sizeof(Ref)));
}

/// The block of the `type` userdata at `index`, its model still open; throws ScriptError
/// "ball: call it as a method, b:fn(...) (...)" for another value, "ball: its model was closed".
void* checkObject(lua_State* L, int index, const ObjectType& type, const char* fn);
template <class Ref>
Ref& checkObject(lua_State* L, int index, const ObjectType& type, const char* fn) {
    return *static_cast<Ref*>(checkObject(L, index, type, fn));
}

/// The method `set{...}` of a type with writable fields: writes the fields of the table given, in
/// sorted order, as `obj.name = value` would.
int objectSet(lua_State* L);

/// "id, pos, vel, ..., set(), delete()": the names an unknown field's error lists (the writable
/// fields only when `writable`, then without the methods).
std::string knownNames(const ObjectType& type, bool writable);

/// Every method name of the model, sorted (the unknown-method error's list).
std::vector<std::string> modelMethodNames();

}  // namespace talus::lua
