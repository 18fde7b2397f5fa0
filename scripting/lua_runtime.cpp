// SPDX-License-Identifier: MIT
#include "lua_runtime.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "binding.hpp"
#include "talus/suggest.hpp"

namespace talus::lua {

void pushWhere(lua_State* L) {
    lua_Debug ar;
    // Level 0 is the running C function; walk up to the first frame that has a line (a Lua
    // function), so that a call through pcall or an iterator still names the script line.
    for (int level = 1; lua_getstack(L, level, &ar); ++level) {
        if (lua_getinfo(L, "Sl", &ar) && ar.currentline > 0) {
            lua_pushfstring(L, "%s:%d: ", ar.short_src, ar.currentline);
            return;
        }
    }
    lua_pushliteral(L, "");
}

std::string errorText(lua_State* L, int index) {
    if (lua_type(L, index) == LUA_TSTRING) return lua_tostring(L, index);
    // luaL_tolstring may call __tostring, which may raise: only use it for plain values.
    switch (lua_type(L, index)) {
        case LUA_TNUMBER: {
            lua_pushvalue(L, index);
            std::string s = lua_tostring(L, -1);
            lua_pop(L, 1);
            return s;
        }
        case LUA_TNIL:
            return "nil";
        case LUA_TBOOLEAN:
            return lua_toboolean(L, index) ? "true" : "false";
        default:
            return std::string("(error object is a ") + luaL_typename(L, index) + " value)";
    }
}

namespace detail {
int raise(lua_State* L) { return lua_error(L); }
}  // namespace detail

std::string typeName(lua_State* L, int index) {
    if (lua_type(L, index) == LUA_TUSERDATA && lua_getmetatable(L, index)) {
        lua_pushliteral(L, "__name");
        lua_rawget(L, -2);
        std::string name = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "userdata";
        lua_pop(L, 2);
        return name;
    }
    return luaL_typename(L, index);
}

std::string numberText(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

std::string didYouMeanIn(const std::string& key, const std::string& joined) {
    std::vector<std::string> names;
    std::size_t pos = 0;
    while (pos <= joined.size()) {
        std::size_t end = joined.find(", ", pos);
        if (end == std::string::npos) end = joined.size();
        std::string n = joined.substr(pos, end - pos);
        if (const std::size_t paren = n.find('('); paren != std::string::npos) n.resize(paren);
        if (!n.empty()) names.push_back(n);
        pos = end + 2;
    }
    return didYouMean(key, names);
}

std::string joinNames(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) {
        if (!out.empty()) out += ", ";
        out += n;
    }
    return out;
}

std::string joinNames(std::initializer_list<const char*> names) {
    std::string out;
    for (const char* n : names) {
        if (!out.empty()) out += ", ";
        out += '"';
        out += n;
        out += '"';
    }
    return out;
}

double toNumber(lua_State* L, int index, const std::string& what) {
    if (lua_type(L, index) != LUA_TNUMBER)
        throw ScriptError(what + " must be a number (got " + typeName(L, index) + ")");
    const double v = lua_tonumber(L, index);
    // NaN (0/0) is never an input: the engine uses it for "not set".
    if (std::isnan(v)) throw ScriptError(what + " must be a number (got nan)");
    return v;
}

long long toInteger(lua_State* L, int index, const std::string& what) {
    if (lua_type(L, index) != LUA_TNUMBER)
        throw ScriptError(what + " must be an integer (got " + typeName(L, index) + ")");
    int isint = 0;
    const lua_Integer i = lua_tointegerx(L, index, &isint);
    if (!isint)
        throw ScriptError(what + " must be an integer (got " + numberText(lua_tonumber(L, index)) +
                          ")");
    return static_cast<long long>(i);
}

Vec2 toVec(lua_State* L, int index, const std::string& what) {
    index = lua_absindex(L, index);
    if (lua_type(L, index) != LUA_TTABLE)
        throw ScriptError(what + " must be a vector {x, y} (got " + typeName(L, index) + ")");
    double c[2];
    for (int k = 0; k < 2; ++k) {
        lua_rawgeti(L, index, k + 1);
        const bool ok = lua_type(L, -1) == LUA_TNUMBER;
        c[k] = ok ? lua_tonumber(L, -1) : 0.0;
        lua_pop(L, 1);
        if (!ok)
            throw ScriptError(what + " must be a vector {x, y} of two numbers (component " +
                              std::to_string(k + 1) + " is not a number)");
        if (std::isnan(c[k]))
            throw ScriptError(what + " must be a vector {x, y} of two numbers (component " +
                              std::to_string(k + 1) + " is nan)");
    }
    if (lua_rawlen(L, index) > 2)
        throw ScriptError(what + " must be a vector {x, y} (got " +
                          std::to_string(lua_rawlen(L, index)) + " components)");
    return Vec2(c[0], c[1]);
}

void pushVec(lua_State* L, const Vec2& v) {
    lua_createtable(L, 2, 0);
    lua_pushnumber(L, v.x());
    lua_rawseti(L, -2, 1);
    lua_pushnumber(L, v.y());
    lua_rawseti(L, -2, 2);
}

void setNumber(lua_State* L, const char* key, double v) {
    lua_pushnumber(L, v);
    lua_setfield(L, -2, key);
}

void setInteger(lua_State* L, const char* key, lua_Integer v) {
    lua_pushinteger(L, v);
    lua_setfield(L, -2, key);
}

void setBoolean(lua_State* L, const char* key, bool v) {
    lua_pushboolean(L, v);
    lua_setfield(L, -2, key);
}

void setString(lua_State* L, const char* key, const std::string& v) {
    lua_pushlstring(L, v.data(), v.size());
    lua_setfield(L, -2, key);
}

void pushStringList(lua_State* L, const std::vector<std::string>& list) {
    lua_createtable(L, static_cast<int>(list.size()), 0);
    for (std::size_t i = 0; i < list.size(); ++i) {
        lua_pushstring(L, list[i].c_str());
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
}

int toEnum(lua_State* L, int index, const std::string& what,
           std::initializer_list<const char*> names) {
    if (lua_type(L, index) == LUA_TSTRING) {
        const char* s = lua_tostring(L, index);
        int i = 0;
        for (const char* n : names) {
            if (std::strcmp(n, s) == 0) return i;
            ++i;
        }
        throw ScriptError(what + " must be one of " + joinNames(names) + " (got \"" + s + "\")");
    }
    throw ScriptError(what + " must be one of " + joinNames(names) + " (got " + typeName(L, index) +
                      ")");
}

void requireTable(lua_State* L, int index, const std::string& what) {
    if (lua_type(L, index) != LUA_TTABLE)
        throw ScriptError(what + " must be a table (got " + typeName(L, index) + ")");
}

void* testUserdata(lua_State* L, int index, const char* tname) {
    return luaL_testudata(L, index, tname);
}

std::vector<std::string> sortedKeys(lua_State* L, int index, const std::string& bad_key_message) {
    index = lua_absindex(L, index);
    std::vector<std::string> keys;
    lua_pushnil(L);
    while (lua_next(L, index) != 0) {
        lua_pop(L, 1);
        if (lua_type(L, -1) != LUA_TSTRING) {
            lua_pop(L, 1);
            throw ScriptError(bad_key_message);
        }
        keys.push_back(lua_tostring(L, -1));
    }
    std::sort(keys.begin(), keys.end());
    return keys;
}

// ------------------------------------------------------------------ Options

Options::Options(lua_State* L, int index, std::string what, std::vector<std::string> known,
                 bool optional)
    : m_L(L), m_index(0), m_what(std::move(what)) {
    index = lua_absindex(L, index);
    const int t = lua_type(L, index);
    if (t == LUA_TNONE || t == LUA_TNIL) {
        if (optional) return;
        throw ScriptError(m_what + ": expected a table of options {...} (got " +
                          typeName(L, index) + ")");
    }
    if (t != LUA_TTABLE)
        throw ScriptError(m_what + ": expected a table of options {...} (got " +
                          typeName(L, index) + ")");
    m_index = index;
    // Refuse unknown keys. Collect them first so that the message is deterministic (sorted).
    std::vector<std::string> unknown;
    lua_pushnil(L);
    while (lua_next(L, index) != 0) {
        if (lua_type(L, -2) == LUA_TSTRING) {
            const std::string key = lua_tostring(L, -2);
            if (std::find(known.begin(), known.end(), key) == known.end()) unknown.push_back(key);
        } else {
            lua_pop(L, 2);
            throw ScriptError(m_what +
                              ": options must be named (name = value); found a value "
                              "at a numeric position");
        }
        lua_pop(L, 1);
    }
    if (!unknown.empty()) {
        std::sort(unknown.begin(), unknown.end());
        std::vector<std::string> sorted = known;
        std::sort(sorted.begin(), sorted.end());
        throw ScriptError(m_what + ": unknown option '" + unknown.front() + "'" +
                          didYouMean(unknown.front(), sorted) + " (known: " + joinNames(sorted) +
                          ")");
    }
}

Options::Options(lua_State* L, int index, std::string what, const OptionTable& table, bool optional)
    : Options(L, index, std::move(what), table.names(), optional) {}

std::string Options::field(const char* key) const { return m_what + ": '" + key + "'"; }

int Options::push(const char* key) const {
    if (!m_index) {
        lua_pushnil(m_L);
        return LUA_TNIL;
    }
    lua_pushstring(m_L, key);
    return lua_rawget(m_L, m_index);
}

bool Options::has(const char* key) const {
    const int t = push(key);
    lua_pop(m_L, 1);
    return t != LUA_TNIL;
}

double Options::number(const char* key, double fallback) const {
    if (push(key) == LUA_TNIL) {
        lua_pop(m_L, 1);
        return fallback;
    }
    const bool ok = lua_type(m_L, -1) == LUA_TNUMBER;
    const double v = ok ? lua_tonumber(m_L, -1) : 0.0;
    const std::string got = ok ? "" : typeName(m_L, -1);
    lua_pop(m_L, 1);
    if (!ok) throw ScriptError(field(key) + " must be a number (got " + got + ")");
    // NaN (0/0) is never an input: the engine uses it for "not set".
    if (std::isnan(v)) throw ScriptError(field(key) + " must be a number (got nan)");
    return v;
}

long long Options::integer(const char* key, long long fallback) const {
    if (push(key) == LUA_TNIL) {
        lua_pop(m_L, 1);
        return fallback;
    }
    try {
        const long long v = toInteger(m_L, -1, field(key));
        lua_pop(m_L, 1);
        return v;
    } catch (...) {
        lua_pop(m_L, 1);
        throw;
    }
}

bool Options::boolean(const char* key, bool fallback) const {
    const int t = push(key);
    const bool v = lua_toboolean(m_L, -1);
    lua_pop(m_L, 1);
    if (t == LUA_TNIL) return fallback;
    if (t != LUA_TBOOLEAN)
        throw ScriptError(field(key) + " must be true or false (got " + lua_typename(m_L, t) + ")");
    return v;
}

std::string Options::string(const char* key, const std::string& fallback) const {
    const int t = push(key);
    if (t == LUA_TNIL) {
        lua_pop(m_L, 1);
        return fallback;
    }
    if (t != LUA_TSTRING) {
        const std::string got = typeName(m_L, -1);
        lua_pop(m_L, 1);
        throw ScriptError(field(key) + " must be a string (got " + got + ")");
    }
    std::string v = lua_tostring(m_L, -1);
    lua_pop(m_L, 1);
    return v;
}

Vec2 Options::vec(const char* key, const Vec2& fallback) const {
    if (push(key) == LUA_TNIL) {
        lua_pop(m_L, 1);
        return fallback;
    }
    try {
        const Vec2 v = toVec(m_L, -1, field(key));
        lua_pop(m_L, 1);
        return v;
    } catch (...) {
        lua_pop(m_L, 1);
        throw;
    }
}

int Options::choice(const char* key, int fallback, std::initializer_list<const char*> names) const {
    if (push(key) == LUA_TNIL) {
        lua_pop(m_L, 1);
        return fallback;
    }
    try {
        const int v = toEnum(m_L, -1, field(key), names);
        lua_pop(m_L, 1);
        return v;
    } catch (...) {
        lua_pop(m_L, 1);
        throw;
    }
}

std::vector<std::string> Options::strings(const char* key) const {
    std::vector<std::string> out;
    const int t = push(key);
    if (t == LUA_TSTRING) {
        out.push_back(lua_tostring(m_L, -1));
    } else if (t == LUA_TTABLE) {
        const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(m_L, -1));
        for (lua_Integer i = 1; i <= n; ++i) {
            const bool ok = lua_rawgeti(m_L, -1, i) == LUA_TSTRING;
            if (ok) out.push_back(lua_tostring(m_L, -1));
            lua_pop(m_L, 1);
            if (!ok) {
                lua_pop(m_L, 1);
                throw ScriptError(field(key) + " must be a list of strings (entry " +
                                  std::to_string(i) + " is not a string)");
            }
        }
    } else if (t != LUA_TNIL) {
        const std::string got = typeName(m_L, -1);
        lua_pop(m_L, 1);
        throw ScriptError(field(key) + " must be a string or a list of strings (got " + got + ")");
    }
    lua_pop(m_L, 1);
    return out;
}

std::vector<double> Options::numbers(const char* key) const {
    std::vector<double> out;
    const int t = push(key);
    if (t == LUA_TTABLE) {
        const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(m_L, -1));
        out.reserve(static_cast<std::size_t>(n));
        for (lua_Integer i = 1; i <= n; ++i) {
            const bool ok = lua_rawgeti(m_L, -1, i) == LUA_TNUMBER;
            if (ok) out.push_back(lua_tonumber(m_L, -1));
            lua_pop(m_L, 1);
            if (!ok) {
                lua_pop(m_L, 1);
                throw ScriptError(field(key) + " must be a list of numbers (entry " +
                                  std::to_string(i) + " is not a number)");
            }
        }
    } else if (t != LUA_TNIL) {
        const std::string got = typeName(m_L, -1);
        lua_pop(m_L, 1);
        throw ScriptError(field(key) + " must be a list of numbers (got " + got + ")");
    }
    lua_pop(m_L, 1);
    return out;
}

}  // namespace talus::lua
