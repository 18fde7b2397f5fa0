// SPDX-License-Identifier: MIT
//
// The lanes of one contact-model rule (docs/plugin-abi.md, "Lanes"; docs/architecture.md,
// "Force-displacement"): the state of its contacts that run through the model's lane law, one
// row of LaneLaw::state_size doubles per contact, rows side by side. A pair names its row
// (Pair::lane); the rule owns the table as it owns the pool of its objects. Not
// installed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "talus/contact_model.hpp"

namespace talus {

constexpr uint32_t kNoLane = 0xffffffffu;  // Pair::lane of a contact not in the lanes

class LaneTable {
public:
    explicit LaneTable(const LaneLaw& law) : m_law(&law), m_size(std::size_t(law.state_size)) {}
    const LaneLaw& law() const { return *m_law; }
    /// The rows (LaneBatch::state); valid until the next allocate() that grows the table.
    double* state() { return m_data.data(); }
    double* row(uint32_t r) { return m_data.data() + r * m_size; }
    /// A row for a contact entering the lanes (a freed one first).
    uint32_t allocate();
    /// Room for `more` rows entering (beyond the free ones) with an eighth to spare, so that
    /// the many contacts of a packing entering at once grow the table once, not by doubling.
    void reserve(std::size_t more);
    void release(uint32_t r) { m_free.push_back(r); }
    std::size_t used() const { return m_rows - m_free.size(); }
    /// The memory it holds [bytes].
    std::size_t bytes() const {
        return m_data.capacity() * sizeof(double) + m_free.capacity() * sizeof(uint32_t);
    }
    /// Moves row order[k] to row k for every k and drops the rest (and the free list): the
    /// contacts in the order the force loop visits them (sortBalls). In place: no second table.
    void reorder(const std::vector<uint32_t>& order);

private:
    const LaneLaw* m_law;
    std::size_t m_size;  // doubles per row
    std::vector<double> m_data;
    std::vector<uint32_t> m_free;
    uint32_t m_rows = 0;
};

}  // namespace talus
