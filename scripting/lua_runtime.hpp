// SPDX-License-Identifier: MIT
//
// Shared helpers of the Lua bindings (the role of LÖVE's common/runtime.h).
//
// Design note: errors and longjmp
// -------------------------------
// The system Lua is built as C, so lua_error() and every luaL_check*() leave a function with
// longjmp. A longjmp across a C++ frame with live objects skips their destructors, which is
// undefined behaviour. So the bindings follow one rule:
//
//   * every binding body runs inside catchexcept(L, [&] { ... }), and inside it nothing raises
//     a Lua error: argument and option checks throw ScriptError (a C++ exception) instead, and
//     option tables are read with raw access (no metamethods that could raise);
//   * catchexcept catches the exception, lets the handler finish (the exception object and all
//     locals are destroyed), and only then calls lua_error with the message on the stack.
//
// Lua functions the engine calls back (on_cycle, on_event, history columns) run under
// lua_pcall; a failure there becomes a CallbackError thrown through the engine, which
// unwinds C++ normally and is raised as a Lua error by the catchexcept of the run call.
//
// Every message is prefixed with the position of the nearest Lua frame ("rock.lua:12: "),
// so a user sees the script line that made the call.
#pragma once

#include <initializer_list>
#include <lua.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "talus/vec.hpp"

namespace talus::lua {

struct OptionTable;  // binding.hpp

/// Bad input from a script (wrong type, unknown option). Raised as a Lua error with the line.
class ScriptError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A Lua error inside a callback; its message already carries the callback's own position, so
/// it is raised again unchanged.
class CallbackError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Pushes "chunk:line: " of the nearest Lua function on the call stack (the script line that
/// called the binding, even through pcall), or "" if there is none.
void pushWhere(lua_State* L);

/// Message of the error value on top of the stack (any type), for rethrowing as CallbackError.
std::string errorText(lua_State* L, int index);

namespace detail {
int raise(lua_State* L);  // lua_error with the message already pushed
}

/// Runs `body` (returning the number of Lua results it pushed) and turns any C++ exception
/// into a Lua error once the handler has finished. See the design note above.
template <class Body>
int catchexcept(lua_State* L, const Body& body) {
    int results = 0;
    bool failed = false;
    try {
        results = body();
    } catch (const CallbackError& e) {
        lua_pushstring(L, e.what());
        failed = true;
    } catch (const std::exception& e) {
        pushWhere(L);
        lua_pushstring(L, e.what());
        lua_concat(L, 2);
        failed = true;
    } catch (...) {
        pushWhere(L);
        lua_pushstring(L, "unknown C++ exception");
        lua_concat(L, 2);
        failed = true;
    }
    if (failed) return detail::raise(L);
    return results;
}

// ------------------------------------------------------------------ values

/// Lua type name of the value at `index`, for messages ("number", "table", "talus.Ball").
std::string typeName(lua_State* L, int index);

/// Formats a number the way messages show it (%g).
std::string numberText(double v);

/// Joins names as "a, b, c".
std::string joinNames(const std::vector<std::string>& names);
/// "; did you mean 'x'?" for an unknown `key` among the names of a list as the errors print it
/// ("a, b, c()": "()" marks a method), or "" when none is close (talus/suggest.hpp).
std::string didYouMeanIn(const std::string& key, const std::string& joined);
std::string joinNames(std::initializer_list<const char*> names);

/// Reads a vector {x, y} at `index`; throws ScriptError naming `what` if it is not one.
Vec2 toVec(lua_State* L, int index, const std::string& what);
void pushVec(lua_State* L, const Vec2& v);

/// Reads a number at `index` (integers included); throws ScriptError naming `what`.
double toNumber(lua_State* L, int index, const std::string& what);
/// Reads an integer-valued number; throws ScriptError naming `what` (1.5 is refused).
long long toInteger(lua_State* L, int index, const std::string& what);

/// t[key] = v for the table on top of the stack (the tables of results).
void setNumber(lua_State* L, const char* key, double v);
void setInteger(lua_State* L, const char* key, lua_Integer v);
void setBoolean(lua_State* L, const char* key, bool v);
void setString(lua_State* L, const char* key, const std::string& v);

/// Pushes a table of strings {"a", "b"}.
void pushStringList(lua_State* L, const std::vector<std::string>& list);

/// Parses an enum string: returns the index of `text` in `names`, or throws ScriptError
/// "<what> must be one of "a", "b" (got "c")".
int toEnum(lua_State* L, int index, const std::string& what,
           std::initializer_list<const char*> names);

// ------------------------------------------------------------------ option tables

/// A table of named options ({radius = 0.1, pos = {0, 1}}), read with raw access. The
/// constructor refuses a non-table and any key that is not in `known`, listing the known ones
/// (a typo such as `radus = 0.1` is an error, not a silently ignored option).
class Options {
public:
    /// `index` may be absent/nil when `optional`; then every getter returns its fallback.
    Options(lua_State* L, int index, std::string what, std::vector<std::string> known,
            bool optional = false);
    /// The options of `table` (binding.hpp): the names its rows declare.
    Options(lua_State* L, int index, std::string what, const OptionTable& table,
            bool optional = false);

    bool has(const char* key) const;
    /// Pushes the raw value of `key` (possibly nil) and returns its Lua type.
    int push(const char* key) const;

    double number(const char* key, double fallback) const;
    long long integer(const char* key, long long fallback) const;
    bool boolean(const char* key, bool fallback) const;
    std::string string(const char* key, const std::string& fallback) const;
    Vec2 vec(const char* key, const Vec2& fallback) const;
    int choice(const char* key, int fallback, std::initializer_list<const char*> names) const;
    /// A string or a list of strings.
    std::vector<std::string> strings(const char* key) const;
    /// A list of numbers.
    std::vector<double> numbers(const char* key) const;

    const std::string& what() const { return m_what; }
    int index() const { return m_index; }
    lua_State* state() const { return m_L; }
    bool present() const { return m_index != 0; }
    /// Field name as messages show it: "ball: 'radius'".
    std::string field(const char* key) const;

private:
    lua_State* m_L;
    int m_index;  // absolute stack index; 0 when absent
    std::string m_what;
};

/// Throws ScriptError if the value at `index` is not a table (argument `what`).
void requireTable(lua_State* L, int index, const std::string& what);

/// Userdata of metatable `tname` at `index`, or nullptr (never raises).
void* testUserdata(lua_State* L, int index, const char* tname);

/// The string keys of the table at `index`, sorted (so that set{...} applies them in an order
/// that does not depend on table iteration); a non-string key raises `bad_key_message`.
std::vector<std::string> sortedKeys(lua_State* L, int index, const std::string& bad_key_message);

/// For each string key of the table at `table`, in sorted order, calls set(key, value_index):
/// the body of an object's set{...} method. `what` names the call in errors.
template <class SetField>
void applyFields(lua_State* L, int table, const std::string& what, const std::string& bad_key,
                 SetField set) {
    requireTable(L, table, what);
    for (const std::string& k : sortedKeys(L, table, bad_key)) {
        lua_pushstring(L, k.c_str());
        lua_rawget(L, table);
        set(k, lua_gettop(L));
        lua_pop(L, 1);
    }
}

}  // namespace talus::lua
