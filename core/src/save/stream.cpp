// SPDX-License-Identifier: MIT
//
// The save file's reader and writer (talus/save_file.hpp): sections as a tag and a length, and
// the checks every read makes against what is left.
#include <cstring>
#include <string>

#include "talus/errors.hpp"
#include "talus/save_file.hpp"

namespace talus {

uint64_t fnv1a64(const uint8_t* p, std::size_t n, uint64_t h) {
    for (std::size_t i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

void SaveWriter::beginSection(const char* tag) {
    bytes(tag, 4);
    m_open.push_back(m_data.size());
    u64(0);
}

void SaveWriter::endSection() {
    const std::size_t at = m_open.back();
    m_open.pop_back();
    const uint64_t len = m_data.size() - at - 8;
    std::memcpy(m_data.data() + at, &len, 8);
}

void SaveReader::fail(const std::string& why) const {
    throw InputError("restore: " + m_where + ": " + why);
}

void SaveReader::expectEnd() const {
    if (!atEnd()) fail(std::to_string(left()) + " unexpected bytes at the end");
}

bool SaveReader::boolean() {
    const uint8_t v = u8();
    if (v > 1) fail("invalid boolean " + std::to_string(v));
    return v != 0;
}

std::size_t SaveReader::count(std::size_t elem_size, const char* what) {
    const uint64_t n = u64();
    if (elem_size && n > left() / elem_size)
        fail(std::string(what) + ": count " + std::to_string(n) + " does not fit in the " +
             std::to_string(left()) + " bytes left");
    return static_cast<std::size_t>(n);
}

std::string SaveReader::str() {
    std::string s(count(1, "string"), '\0');
    bytes(s.data(), s.size());
    return s;
}

std::string SaveReader::peekTag() const {
    if (left() < 4) return "";
    return std::string(reinterpret_cast<const char*>(m_p + m_pos), 4);
}

SaveReader SaveReader::section(const char* tag) {
    if (left() < 12) fail(std::string("section '") + tag + "' is missing (the file ends early)");
    char got[4];
    bytes(got, 4);
    if (std::memcmp(got, tag, 4) != 0) {
        std::string g;
        for (char c : got) g += (c >= 32 && c < 127) ? c : '?';
        fail(std::string("expected section '") + tag + "', found '" + g + "'");
    }
    const std::size_t n = count(1, tag);
    SaveReader sub(m_p + m_pos, n, m_where + ", section '" + tag + "'", m_version);
    m_pos += n;
    return sub;
}

}  // namespace talus
