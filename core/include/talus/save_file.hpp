// SPDX-License-Identifier: MIT
//
// Save files (docs/save-format.md): m:save / talus.restore write and read the whole state of a
// Model, plus an opaque section of the host (the Lua layer's histories), in a versioned binary
// format with a checksum. The reader never trusts the file: every count, index and enum is
// checked before it is used, and a failure is an InputError naming the file, the section and
// what is wrong, never a crash (tests/core/test_save_restore.cpp sweeps truncations and byte
// flips; tests/fuzz/ fuzzes the reader).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "talus/vec.hpp"

namespace talus {

class Model;
class PluginRegistry;

/// "TALUSSAV": the first 8 bytes of every save file.
inline constexpr char kSaveMagic[8] = {'T', 'A', 'L', 'U', 'S', 'S', 'A', 'V'};
/// Raise when a section is added or a section's layout grows (docs/save-format.md, "Sections");
/// 2: the energy items `script` and `barrier`, the script's pending changes, the guard's
/// severe settings; 3: the servos' equilibrium hold (SRVG);
/// a reader reads every version up to its own and refuses newer ones.
inline constexpr uint32_t kSaveFormatVersion = 3;
/// Written in the saving machine's byte order; read back as another value on a machine of the
/// other order.
inline constexpr uint32_t kSaveByteOrderMark = 0x01020304u;
/// Size of the fixed header: magic, format version, byte-order mark, payload length, checksum.
inline constexpr std::size_t kSaveHeaderSize = 8 + 4 + 4 + 8 + 8;

/// 64-bit FNV-1a over `n` bytes. Each step (xor a byte, multiply by an odd prime) is a
/// bijection of the state, so any change confined to one byte always changes the sum.
uint64_t fnv1a64(const uint8_t* p, std::size_t n, uint64_t h = 0xcbf29ce484222325ull);

/// Appends values in the machine's byte order (the header says which).
class SaveWriter {
public:
    void bytes(const void* p, std::size_t n) {
        const auto* c = static_cast<const uint8_t*>(p);
        m_data.insert(m_data.end(), c, c + n);
    }
    template <class T>
    void pod(const T& v) {
        static_assert(std::is_trivially_copyable_v<T> && !std::is_same_v<T, bool>);
        bytes(&v, sizeof v);
    }
    void u8(uint8_t v) { pod(v); }
    void u32(uint32_t v) { pod(v); }
    void i32(int32_t v) { pod(v); }
    void u64(uint64_t v) { pod(v); }
    void i64(int64_t v) { pod(v); }
    void f64(double v) { pod(v); }
    void boolean(bool v) { u8(v ? 1 : 0); }
    void vec2(const Vec2& v) { f64(v.x()), f64(v.y()); }
    void box(const Box& b) { vec2(b.lo), vec2(b.hi); }
    void str(const std::string& s) {
        u64(s.size());
        bytes(s.data(), s.size());
    }
    template <class T>
    void array(const std::vector<T>& v) {
        static_assert(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>);
        u64(v.size());
        bytes(v.data(), v.size() * sizeof(T));
    }
    void vec2Array(const std::vector<Vec2>& v) {
        u64(v.size());
        for (const Vec2& x : v) vec2(x);
    }
    /// A section: a 4-character tag and its length, patched by endSection.
    void beginSection(const char* tag);
    void endSection();
    std::vector<uint8_t>& data() { return m_data; }

private:
    std::vector<uint8_t> m_data;
    std::vector<std::size_t> m_open;
};

/// Reads what SaveWriter wrote, checking every length against what is left.
class SaveReader {
public:
    /// `where` names the file (and section) in messages; `version` is the file's format
    /// version (what a section reads may depend on it).
    SaveReader(const uint8_t* p, std::size_t n, std::string where,
               uint32_t version = kSaveFormatVersion)
        : m_p(p), m_n(n), m_where(std::move(where)), m_version(version) {}

    [[noreturn]] void fail(const std::string& why) const;
    std::size_t left() const { return m_n - m_pos; }
    bool atEnd() const { return m_pos == m_n; }
    void expectEnd() const;
    const std::string& where() const { return m_where; }
    /// The format version of the file being read.
    uint32_t version() const { return m_version; }
    void setVersion(uint32_t version) { m_version = version; }

    void bytes(void* out, std::size_t n) {
        if (n > left())
            fail("truncated (needs " + std::to_string(n) + " more bytes, has " +
                 std::to_string(left()) + ")");
        if (n) std::memcpy(out, m_p + m_pos, n);
        m_pos += n;
    }
    template <class T>
    T pod() {
        static_assert(std::is_trivially_copyable_v<T> && !std::is_same_v<T, bool>);
        T v;
        bytes(&v, sizeof v);
        return v;
    }
    uint8_t u8() { return pod<uint8_t>(); }
    uint32_t u32() { return pod<uint32_t>(); }
    int32_t i32() { return pod<int32_t>(); }
    uint64_t u64() { return pod<uint64_t>(); }
    int64_t i64() { return pod<int64_t>(); }
    double f64() { return pod<double>(); }
    bool boolean();
    Vec2 vec2() {
        const double x = f64();
        return Vec2(x, f64());
    }
    Box box() {
        Box b;
        b.lo = vec2();
        b.hi = vec2();
        return b;
    }
    /// A count of elements of `elem_size` bytes each that must fit in what is left.
    std::size_t count(std::size_t elem_size, const char* what);
    std::string str();
    template <class T>
    void array(std::vector<T>& v, const char* what) {
        v.resize(count(sizeof(T), what));
        bytes(v.data(), v.size() * sizeof(T));
    }
    /// An array that must have `n` elements (the parallel arrays of the balls).
    template <class T>
    void array(std::vector<T>& v, std::size_t n, const char* what) {
        array(v, what);
        if (v.size() != n)
            fail(std::string(what) + ": " + std::to_string(v.size()) + " entries where " +
                 std::to_string(n) + " were expected");
    }
    void vec2Array(std::vector<Vec2>& v, const char* what) {
        v.resize(count(16, what));
        for (Vec2& x : v) x = vec2();
    }
    /// An integer enum value in [0, n).
    template <class E>
    E enumValue(int32_t n, const char* what) {
        const int32_t v = i32();
        if (v < 0 || v >= n) fail(std::string(what) + ": invalid value " + std::to_string(v));
        return static_cast<E>(v);
    }
    /// The next section, which must have tag `tag`; returns a reader over its bytes.
    SaveReader section(const char* tag);
    /// Whether the next section is `tag`: a section added later, absent from older files.
    bool nextSection(const char* tag) const {
        return left() >= 4 && std::memcmp(m_p + m_pos, tag, 4) == 0;
    }
    /// Tag of the next section without consuming it ("" at the end).
    std::string peekTag() const;

private:
    const uint8_t* m_p;
    std::size_t m_n;
    std::size_t m_pos = 0;
    std::string m_where;
    uint32_t m_version;
};

/// What a restore hands back besides the model.
struct RestoredModel {
    std::unique_ptr<Model> model;
    std::vector<uint8_t> host;       ///< the host's opaque section (empty when none)
    std::string engine_version;      ///< the version of Talus that wrote the file
    std::vector<std::string> notes;  ///< things the user should know (plugin versions differ)
};

/// Writes `model` (and the host's section) to `path`: to `path`.tmp first, flushed, then
/// renamed over `path`, so a crash during a save leaves the previous file intact. Throws
/// InputError naming the file when it cannot be written.
void saveModelFile(const Model& model, const std::string& path,
                   const std::vector<uint8_t>& host = {});
/// The bytes of a save file (what saveModelFile writes).
std::vector<uint8_t> saveModelBytes(const Model& model, const std::vector<uint8_t>& host = {});

/// Reads a save file. Throws InputError naming the file and what is wrong: not a save file,
/// another format version or byte order, truncated, checksum mismatch (corrupted), a contact
/// model whose plugin is missing or whose data version the loaded plugin cannot read, or an
/// inconsistent section.
RestoredModel restoreModelFile(const std::string& path, PluginRegistry& registry);
/// The same from bytes; `name` names them in messages. `verify_checksum` = false is for the
/// fuzz target only (it lets mutated bytes reach the section parsers).
RestoredModel restoreModelBytes(const uint8_t* data, std::size_t size, const std::string& name,
                                PluginRegistry& registry, bool verify_checksum = true);

}  // namespace talus
