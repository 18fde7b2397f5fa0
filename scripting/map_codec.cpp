// SPDX-License-Identifier: MIT
// The value format of talus.map (see map_codec.hpp). One tag byte per value:
//   'n' nil | 'f' false | 't' true
//   'i' integer: 8 bytes (lua_Integer)      | 'd' float: 8 bytes (the double's bits)
//   's' string: 8-byte length, then the bytes
//   'T' table: 8-byte pair count, then key, value, key, value... in canonical key order
#include "map_codec.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

namespace talus::lua {

namespace {

// Nesting deeper than this is refused on both sides: it bounds the C++ recursion (and the Lua
// stack slots a decoded value needs) far below any stack limit, and no result record nests so.
constexpr int kMaxDepth = 200;

void putByte(std::string& out, char c) { out.push_back(c); }

void put64(std::string& out, uint64_t v) {
    char b[8];
    std::memcpy(b, &v, 8);
    out.append(b, 8);
}

/// A table key, kept so that keys can be written in canonical order.
struct Key {
    int rank;  // 0 integer, 1 float, 2 boolean, 3 string
    lua_Integer i = 0;
    double d = 0;
    bool b = false;
    std::string s;
};

bool keyLess(const Key& a, const Key& b) {
    if (a.rank != b.rank) return a.rank < b.rank;
    switch (a.rank) {
        case 0:
            return a.i < b.i;
        case 1:
            return a.d < b.d;  // never nan: Lua refuses nan keys
        case 2:
            return a.b < b.b;
        default:
            return a.s < b.s;  // bytewise (std::string compares as unsigned char)
    }
}

bool isIdentifier(const std::string& s) {
    if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
    for (char c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
    return true;
}

/// The key as a path step: ".name", "[3]", "[1.5]", "[true]", "[\"two words\"]".
std::string pathStep(const Key& k) {
    char buf[64];
    switch (k.rank) {
        case 0:
            std::snprintf(buf, sizeof buf, "[%lld]", static_cast<long long>(k.i));
            return buf;
        case 1:
            std::snprintf(buf, sizeof buf, "[%.17g]", k.d);
            return buf;
        case 2:
            return k.b ? "[true]" : "[false]";
        default:
            if (isIdentifier(k.s)) return "." + k.s;
            return "[\"" + k.s + "\"]";
    }
}

class Encoder {
public:
    Encoder(lua_State* L, std::string& out) : m_L(L), m_out(out) {}

    void value(int index) {
        index = lua_absindex(m_L, index);
        switch (lua_type(m_L, index)) {
            case LUA_TNIL:
                putByte(m_out, 'n');
                return;
            case LUA_TBOOLEAN:
                putByte(m_out, lua_toboolean(m_L, index) ? 't' : 'f');
                return;
            case LUA_TNUMBER:
                if (lua_isinteger(m_L, index)) {
                    putByte(m_out, 'i');
                    const lua_Integer v = lua_tointeger(m_L, index);
                    char b[8];
                    std::memcpy(b, &v, 8);
                    m_out.append(b, 8);
                } else {
                    putByte(m_out, 'd');
                    const double v = lua_tonumber(m_L, index);
                    char b[8];
                    std::memcpy(b, &v, 8);  // the bits: -0.0, nan payloads, subnormals exact
                    m_out.append(b, 8);
                }
                return;
            case LUA_TSTRING: {
                std::size_t len = 0;
                const char* s = lua_tolstring(m_L, index, &len);
                putByte(m_out, 's');
                put64(m_out, len);
                m_out.append(s, len);
                return;
            }
            case LUA_TTABLE:
                table(index);
                return;
            default:
                fail(std::string("a ") + luaL_typename(m_L, index));
        }
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        std::string path = "result";
        for (const auto& p : m_path) path += p;
        throw EncodeError(what + " at " + path);
    }

    void table(int index) {
        const void* self = lua_topointer(m_L, index);
        if (std::find(m_open.begin(), m_open.end(), self) != m_open.end())
            fail("a cycle (a table that contains itself)");
        if (static_cast<int>(m_open.size()) >= kMaxDepth)
            fail("tables nested deeper than " + std::to_string(kMaxDepth) + " levels");
        if (!lua_checkstack(m_L, 4)) fail("no Lua stack space left");
        m_open.push_back(self);

        std::vector<Key> keys;
        lua_pushnil(m_L);
        while (lua_next(m_L, index) != 0) {
            lua_pop(m_L, 1);  // the value; keep the key for lua_next
            Key k;
            switch (lua_type(m_L, -1)) {
                case LUA_TNUMBER:
                    if (lua_isinteger(m_L, -1)) {
                        k.rank = 0;
                        k.i = lua_tointeger(m_L, -1);
                    } else {
                        k.rank = 1;
                        k.d = lua_tonumber(m_L, -1);
                    }
                    break;
                case LUA_TBOOLEAN:
                    k.rank = 2;
                    k.b = lua_toboolean(m_L, -1);
                    break;
                case LUA_TSTRING: {
                    std::size_t len = 0;
                    const char* s = lua_tolstring(m_L, -1, &len);  // a string: no conversion
                    k.rank = 3;
                    k.s.assign(s, len);
                    break;
                }
                default: {
                    const std::string t = luaL_typename(m_L, -1);
                    lua_pop(m_L, 1);
                    fail("a " + t + " used as a table key");
                }
            }
            keys.push_back(std::move(k));
        }
        std::sort(keys.begin(), keys.end(), keyLess);

        putByte(m_out, 'T');
        put64(m_out, keys.size());
        for (const Key& k : keys) {
            pushKey(k);
            value(-1);  // the key itself (plain data)
            lua_rawget(m_L, index);
            m_path.push_back(pathStep(k));
            value(-1);
            m_path.pop_back();
            lua_pop(m_L, 1);
        }
        m_open.pop_back();
    }

    void pushKey(const Key& k) {
        switch (k.rank) {
            case 0:
                lua_pushinteger(m_L, k.i);
                break;
            case 1:
                lua_pushnumber(m_L, k.d);
                break;
            case 2:
                lua_pushboolean(m_L, k.b);
                break;
            default:
                lua_pushlstring(m_L, k.s.data(), k.s.size());
        }
    }

    lua_State* m_L;
    std::string& m_out;
    std::vector<const void*> m_open;  // tables on the path from the root (cycle detection)
    std::vector<std::string> m_path;  // ".a", "[3]": where the value being written sits
};

/// Reads one value; pushes what it reads onto L, or only checks the bytes when L is null.
class Decoder {
public:
    Decoder(lua_State* L, const char* data, std::size_t size)
        : m_L(L), m_p(data), m_end(data + size) {}

    /// Reads one value; returns its tag.
    char value(int depth) {
        if (depth > kMaxDepth) bad("nesting too deep");
        if (m_L && !lua_checkstack(m_L, 3)) bad("no Lua stack space left");
        const char tag = byte();
        switch (tag) {
            case 'n':
                if (m_L) lua_pushnil(m_L);
                return tag;
            case 'f':
            case 't':
                if (m_L) lua_pushboolean(m_L, tag == 't');
                return tag;
            case 'i': {
                lua_Integer v;
                bytes(&v, 8);
                if (m_L) lua_pushinteger(m_L, v);
                return tag;
            }
            case 'd': {
                double v;
                bytes(&v, 8);
                if (m_L) lua_pushnumber(m_L, v);
                return tag;
            }
            case 's': {
                const uint64_t len = u64();
                if (len > static_cast<uint64_t>(m_end - m_p)) bad("string runs past the end");
                if (m_L) lua_pushlstring(m_L, m_p, static_cast<std::size_t>(len));
                m_p += len;
                return tag;
            }
            case 'T':
                table(depth);
                return tag;
            default:
                bad("unknown tag");
        }
    }

    bool atEnd() const { return m_p == m_end; }

private:
    void table(int depth) {
        const uint64_t pairs = u64();
        // Every pair takes at least two bytes: a corrupt count fails here, not in an allocation.
        if (pairs > static_cast<uint64_t>(m_end - m_p) / 2) bad("table count too large");
        if (m_L) lua_createtable(m_L, 0, 0);
        for (uint64_t k = 0; k < pairs; ++k) {
            if (value(depth + 1) == 'n') bad("nil table key");
            value(depth + 1);
            if (m_L) lua_rawset(m_L, -3);
        }
    }

    [[noreturn]] static void bad(const char* what) {
        throw std::runtime_error(std::string("map: corrupt result data (") + what + ")");
    }
    char byte() {
        if (m_p == m_end) bad("truncated");
        return *m_p++;
    }
    void bytes(void* dst, std::size_t n) {
        if (static_cast<std::size_t>(m_end - m_p) < n) bad("truncated");
        std::memcpy(dst, m_p, n);
        m_p += n;
    }
    uint64_t u64() {
        uint64_t v;
        bytes(&v, 8);
        return v;
    }

    lua_State* m_L;
    const char* m_p;
    const char* m_end;
};

}  // namespace

void encodeValue(lua_State* L, int index, std::string& out) {
    const int top = lua_gettop(L);
    index = lua_absindex(L, index);
    try {
        Encoder(L, out).value(index);
    } catch (...) {
        lua_settop(L, top);  // a failure inside a table leaves keys and values on the stack
        throw;
    }
}

void decodeValue(lua_State* L, const char* data, std::size_t size) {
    const int top = lua_gettop(L);
    Decoder d(L, data, size);
    try {
        d.value(0);
        if (!d.atEnd()) throw std::runtime_error("map: corrupt result data (trailing bytes)");
    } catch (...) {
        lua_settop(L, top);
        throw;
    }
}

bool wellFormed(const char* data, std::size_t size) {
    try {
        Decoder d(nullptr, data, size);
        d.value(0);
        return d.atEnd();
    } catch (const std::runtime_error&) {
        return false;
    }
}

uint64_t checksum64(const char* data, std::size_t size) {
    uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a's offset basis and prime (64 bits)
    for (std::size_t i = 0; i < size; ++i) {
        h ^= static_cast<unsigned char>(data[i]);
        h *= 0x100000001b3ull;
    }
    return h;
}

}  // namespace talus::lua
