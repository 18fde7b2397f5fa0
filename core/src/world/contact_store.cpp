// SPDX-License-Identifier: MIT
// The contact store (contact_store.hpp): pairs, rules and their object pools, the broadphase.
#include "world/contact_store.hpp"

#include <algorithm>
#include <cstddef>
#include <functional>
#include <utility>

#include "talus/errors.hpp"
#include "world/capacity.hpp"

namespace talus {

ObjectPool::ObjectPool(std::size_t block_size) {
    const std::size_t a = alignof(std::max_align_t);
    m_block = (block_size + a - 1) / a * a;
}

void* ObjectPool::allocate() {
    if (m_free.empty()) {
        m_chunks.emplace_back(new unsigned char[m_block * kPerChunk]);
        unsigned char* base = m_chunks.back().get();
        for (std::size_t i = kPerChunk; i-- > 0;) m_free.push_back(base + i * m_block);
    }
    void* p = m_free.back();
    m_free.pop_back();
    return p;
}

void ObjectPool::release(void* p) { m_free.push_back(p); }

std::vector<uint32_t> ObjectPool::blockIndices(const std::vector<const void*>& blocks) const {
    // The chunks by address, to find a block's chunk by bisection.
    std::vector<std::pair<const unsigned char*, std::size_t>> chunks(m_chunks.size());
    for (std::size_t c = 0; c < m_chunks.size(); ++c) chunks[c] = {m_chunks[c].get(), c};
    std::sort(chunks.begin(), chunks.end());
    std::vector<uint32_t> out(blocks.size());
    for (std::size_t k = 0; k < blocks.size(); ++k) {
        const auto* at = static_cast<const unsigned char*>(blocks[k]);
        auto it = std::upper_bound(chunks.begin(), chunks.end(), at,
                                   [](const unsigned char* a, const auto& chunk) {
                                       return std::less<>()(a, chunk.first);
                                   });
        --it;  // (the block lies in a chunk of this pool)
        const auto offset = static_cast<std::size_t>(at - it->first);
        out[k] = static_cast<uint32_t>(it->second * kPerChunk + offset / m_block);
    }
    return out;
}

void ObjectPool::keepFirst(std::size_t used) {
    const std::size_t chunks = (used + kPerChunk - 1) / kPerChunk;
    m_chunks.resize(chunks);
    // Free blocks are taken from the back: the lowest first, as in a new chunk.
    m_free.clear();
    for (std::size_t k = chunks * kPerChunk; k-- > used;) m_free.push_back(block(k));
    m_free.shrink_to_fit();
}

ContactStore::ContactStore()
    : broadphase(std::make_unique<Broadphase>()), wall_broadphase(std::make_unique<Broadphase>()) {}

Pair* ContactStore::pairByKey(ContactKey key) {
    auto it = key_index.find(key.value);
    return it == key_index.end() ? nullptr : &pairs[it->second];
}
const Pair* ContactStore::pairByKey(ContactKey key) const {
    auto it = key_index.find(key.value);
    return it == key_index.end() ? nullptr : &pairs[it->second];
}

void ContactStore::swapState(std::size_t i, std::size_t j) {
    // Everything but the identity (which segment, the key) changes places.
    std::swap(pairs[i], pairs[j]);
    std::swap(pairs[i].end2, pairs[j].end2);
    std::swap(cold[i], cold[j]);
    std::swap(cold[i].key, cold[j].key);
    std::swap(stored[i], stored[j]);
}

GuardWatch& ContactStore::startWatch(Pair& p, PairCold& c) {
    p.watched = true;
    if (c.watch == kNoWatch) {
        if (free_watches.empty()) {
            c.watch = static_cast<uint32_t>(watches.size());
            reserveOneMore(watches);  // (a packing's contacts all start their watch at once)
            watches.emplace_back();
        } else {
            c.watch = free_watches.back();
            free_watches.pop_back();
        }
    }
    GuardWatch& w = watches[c.watch];
    w = GuardWatch{};
    return w;
}

void ContactStore::endWatch(Pair& p, PairCold& c) {
    p.watched = false;
    if (c.watch == kNoWatch) return;
    free_watches.push_back(c.watch);
    c.watch = kNoWatch;
}

void ContactStore::compactWatches() {
    const std::size_t live = watches.size() - free_watches.size();
    if (watches.size() < 1024 || 4 * live > watches.size()) return;
    std::vector<GuardWatch> kept;
    kept.reserve(live);
    for (PairCold& c : cold) {
        if (c.watch == kNoWatch) continue;
        kept.push_back(watches[c.watch]);
        c.watch = static_cast<uint32_t>(kept.size() - 1);
    }
    watches.swap(kept);
    free_watches.clear();
    free_watches.shrink_to_fit();
}

GuardWatch ContactStore::savedWatch(const Pair& p, const PairCold& c) const {
    if (const GuardWatch* w = watchOf(c)) return *w;
    GuardWatch w;
    if (p.active) w.steps = kGuardWatch + 1;
    return w;
}

void ContactStore::restoreWatch(Pair& p, PairCold& c, const GuardWatch& w) {
    c.watch = kNoWatch;
    p.watched = false;
    if (p.active && w.steps <= kGuardWatch) startWatch(p, c) = w;
}

uint16_t ContactStore::ruleIndex(const Rule* rule) const {
    for (std::size_t k = 0; k < rules.size(); ++k)
        if (rules[k].get() == rule) return static_cast<uint16_t>(k);
    throw Error("ruleIndex: a rule not in the store");
}

}  // namespace talus
