// SPDX-License-Identifier: MIT
#include "world/contact_lanes.hpp"

#include <algorithm>
#include <memory>
#include <unordered_map>

#include "talus/errors.hpp"
#include "world/contact_store.hpp"
#include "world/lanes.hpp"
#include "world/permute.hpp"
#include "world/types.hpp"

namespace talus {

uint32_t LaneTable::allocate() {
    if (!m_free.empty()) {
        const uint32_t r = m_free.back();
        m_free.pop_back();
        return r;
    }
    if (m_rows == UINT32_MAX - 1) throw InputError("lanes: more than 2^32 - 2 contacts");
    // (a vector grows geometrically: amortized O(1) rows)
    m_data.resize((std::size_t{m_rows} + 1) * m_size);
    return m_rows++;
}

void LaneTable::reserve(std::size_t more) {
    if (more <= m_free.size()) return;
    const std::size_t rows = m_rows + (more - m_free.size());
    if (rows * m_size > m_data.capacity()) m_data.reserve((rows + rows / 8) * m_size);
}

void LaneTable::reorder(const std::vector<uint32_t>& order) {
    gatherInPlace(order, m_rows, [&](std::size_t i, std::size_t j) {
        std::swap_ranges(row(static_cast<uint32_t>(i)), row(static_cast<uint32_t>(i)) + m_size,
                         row(static_cast<uint32_t>(j)));
    });
    m_data.resize(order.size() * m_size);
    m_rows = static_cast<uint32_t>(order.size());
    m_free.clear();
}

// ------------------------------------------------------------------------ a contact's lane

bool enterLane(ContactStore& cs, Pair& p) {
    Rule& rule = cs.ruleOf(p);
    if (!rule.lanes) rule.lanes = std::make_unique<LaneTable>(*rule.factory->lanes);
    LaneTable& table = *rule.lanes;
    const uint32_t row = table.allocate();
    if (table.law().pack(p.model, table.row(row)) == 0) {
        table.release(row);
        return false;
    }
    p.lane = row;
    return true;
}

void syncLane(const ContactStore& cs, const Pair& p) {
    if (p.lane == kNoLane) return;
    LaneTable& table = *cs.ruleOf(p).lanes;
    table.law().unpack(p.model, table.row(p.lane));
}

void leaveLane(ContactStore& cs, Pair& p) {
    syncLane(cs, p);
    dropLane(cs, p);
}

void dropLane(ContactStore& cs, Pair& p) {
    if (p.lane == kNoLane) return;
    cs.ruleOf(p).lanes->release(p.lane);
    p.lane = kNoLane;
}

void leaveAllLanes(World& world) {
    for (Pair& p : world.contacts.pairs) leaveLane(world.contacts, p);
}

void reorderLanes(World& world) {
    // Each table's rows in the order of their pairs, so that the loop reads them forward.
    std::unordered_map<LaneTable*, std::vector<uint32_t>> order;
    for (Pair& p : world.contacts.pairs) {
        if (p.lane == kNoLane) continue;
        std::vector<uint32_t>& rows = order[world.contacts.ruleOf(p).lanes.get()];
        const auto now = static_cast<uint32_t>(rows.size());
        rows.push_back(p.lane);
        p.lane = now;
    }
    for (auto& rule : world.contacts.rules)
        if (rule->lanes) rule->lanes->reorder(order[rule->lanes.get()]);
}

}  // namespace talus
