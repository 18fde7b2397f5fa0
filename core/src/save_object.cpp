// SPDX-License-Identifier: MIT
#include "talus/save_object.hpp"

#include <cstring>

#include "talus/errors.hpp"

namespace talus {

namespace {
enum Tag : uint8_t { kTagDouble = 1, kTagInt = 2, kTagBool = 3 };
const char* tagName(uint8_t t) {
    return t == kTagDouble ? "double" : t == kTagInt ? "int" : t == kTagBool ? "bool" : "unknown";
}
}  // namespace

BinarySaveObject::BinarySaveObject(int32_t version) : m_saving(true), m_version(version) {}

BinarySaveObject::BinarySaveObject(std::vector<uint8_t> bytes, int32_t data_version)
    : m_saving(false), m_version(data_version), m_bytes(std::move(bytes)) {}

void BinarySaveObject::put(uint8_t tag, const void* p, std::size_t n) {
    m_bytes.push_back(tag);
    const auto* c = static_cast<const uint8_t*>(p);
    m_bytes.insert(m_bytes.end(), c, c + n);
}

void BinarySaveObject::get(uint8_t tag, void* p, std::size_t n) {
    if (m_pos >= m_bytes.size())
        throw InputError("restore: the saved model state ended early (expected a " +
                         std::string(tagName(tag)) + ")");
    if (m_bytes[m_pos] != tag)
        throw InputError(std::string("restore: expected a ") + tagName(tag) + " but the save holds a " +
                         tagName(m_bytes[m_pos]) + " (model state layout changed?)");
    if (m_pos + 1 + n > m_bytes.size()) throw InputError("restore: truncated model state");
    std::memcpy(p, m_bytes.data() + m_pos + 1, n);
    m_pos += 1 + n;
}

void BinarySaveObject::Double(double& v) { m_saving ? put(kTagDouble, &v, sizeof v) : get(kTagDouble, &v, sizeof v); }
void BinarySaveObject::Int(int32_t& v) { m_saving ? put(kTagInt, &v, sizeof v) : get(kTagInt, &v, sizeof v); }
void BinarySaveObject::Bool(bool& v) {
    uint8_t b = v ? 1 : 0;
    if (m_saving) {
        put(kTagBool, &b, 1);
    } else {
        get(kTagBool, &b, 1);
        v = b != 0;
    }
}

}  // namespace talus
