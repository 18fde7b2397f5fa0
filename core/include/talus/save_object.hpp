// SPDX-License-Identifier: MIT
// A byte-stream ModelSaveObject: each value is written with a one-byte type tag, so a restore
// that reads a different type than was saved stops with an error instead of reading garbage.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "talus/contact_model.hpp"

namespace talus {

class BinarySaveObject final : public ModelSaveObject {
public:
    /// For saving: `version` is the saving model's Version().
    explicit BinarySaveObject(int32_t version);
    /// For restoring from bytes written by a saving BinarySaveObject.
    BinarySaveObject(std::vector<uint8_t> bytes, int32_t data_version);

    bool IsSaving() const override { return m_saving; }
    int32_t DataVersion() const override { return m_version; }
    void Double(double& v) override;
    void Int(int32_t& v) override;
    void Bool(bool& v) override;

    const std::vector<uint8_t>& bytes() const { return m_bytes; }
    /// True when a restore consumed exactly the bytes that were saved.
    bool atEnd() const { return m_pos == m_bytes.size(); }

private:
    void put(uint8_t tag, const void* p, std::size_t n);
    void get(uint8_t tag, void* p, std::size_t n);
    bool m_saving;
    int32_t m_version;
    std::vector<uint8_t> m_bytes;
    std::size_t m_pos = 0;
};

}  // namespace talus
