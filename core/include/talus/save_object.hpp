// SPDX-License-Identifier: MIT
// A byte-stream ModelSaveObject: each value is written with a one-byte type tag, so a restore
// that reads a different type than was saved is detected instead of reading garbage. Nothing is
// thrown through the plugin's SaveRestore (the boundary carries status only): a mismatch is
// recorded, later reads return zeros, and restoreContactModel() reports it naming the model.
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
    /// Empty, or what went wrong first during a restore.
    const std::string& error() const { return m_error; }

private:
    void put(uint8_t tag, const void* p, std::size_t n);
    void get(uint8_t tag, void* p, std::size_t n);
    bool m_saving;
    int32_t m_version;
    std::vector<uint8_t> m_bytes;
    std::size_t m_pos = 0;
    std::size_t m_values = 0;
    std::string m_error;
};

/// Saves a contact model's state (its SaveRestore) to bytes.
std::vector<uint8_t> saveContactModel(ContactModel& model);
/// Restores a contact model from bytes written by saveContactModel for `data_version`; throws
/// InputError naming the model if the bytes do not match what the model reads.
void restoreContactModel(ContactModel& model, const std::vector<uint8_t>& bytes,
                         int32_t data_version);

}  // namespace talus
