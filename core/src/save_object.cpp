// SPDX-License-Identifier: MIT
#include "talus/save_object.hpp"

#include <cstring>
#include <string>

#include "talus/errors.hpp"

namespace talus {

namespace {
enum Tag : uint8_t { kTagDouble = 1, kTagInt = 2, kTagBool = 3 };
const char* tagName(uint8_t t) {
    return t == kTagDouble ? "a double"
           : t == kTagInt  ? "an int"
           : t == kTagBool ? "a bool"
                           : "an unknown value";
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
    const std::size_t value_index = m_values++;
    if (m_error.empty()) {
        if (m_pos >= m_bytes.size())
            m_error = "the saved state ended early (value " + std::to_string(value_index + 1) +
                      ": expected " + tagName(tag) + ")";
        else if (m_bytes[m_pos] != tag)
            m_error = "value " + std::to_string(value_index + 1) + ": expected " + tagName(tag) +
                      " but the save holds " + tagName(m_bytes[m_pos]) + " (state layout changed?)";
        else if (m_pos + 1 + n > m_bytes.size())
            m_error =
                "the saved state is truncated (value " + std::to_string(value_index + 1) + ")";
    }
    if (!m_error.empty()) {
        std::memset(p, 0, n);
        return;
    }
    std::memcpy(p, m_bytes.data() + m_pos + 1, n);
    m_pos += 1 + n;
}

std::vector<uint8_t> saveContactModel(ContactModel& model) {
    BinarySaveObject so(model.Version());
    model.SaveRestore(so);
    return so.bytes();
}

void restoreContactModel(ContactModel& model, const std::vector<uint8_t>& bytes,
                         int32_t data_version) {
    if (data_version > model.Version())
        throw InputError(std::string("restore: model '") + model.Name() +
                         "' state was saved by version " + std::to_string(data_version) +
                         ", newer than the loaded plugin's version " +
                         std::to_string(model.Version()));
    BinarySaveObject so(bytes, data_version);
    model.SaveRestore(so);
    if (!so.error().empty())
        throw InputError(std::string("restore: model '") + model.Name() + "': " + so.error());
    if (!so.atEnd())
        throw InputError(std::string("restore: model '") + model.Name() +
                         "' read less than was saved (state layout changed?)");
}

void BinarySaveObject::Double(double& v) {
    m_saving ? put(kTagDouble, &v, sizeof v) : get(kTagDouble, &v, sizeof v);
}
void BinarySaveObject::Int(int32_t& v) {
    m_saving ? put(kTagInt, &v, sizeof v) : get(kTagInt, &v, sizeof v);
}
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
