// SPDX-License-Identifier: MIT
//
// Reordering a store in place: the pairs, their cold and stored records, the kernel rows and the
// contact objects are put in the force loop's order every few hundred steps (sortBalls), and a
// copy of each would hold the store twice at that moment, the largest transient of a packing's
// run. Not installed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

namespace talus {

/// Puts the element at position order[k] at position k for every k, by swapping two positions
/// at a time (swap(i, j)), with 8 bytes of bookkeeping per position instead of a copy of the
/// elements. `order` names distinct positions below `size`; the elements of the positions it does
/// not name end up at positions order.size() and beyond, in no particular order.
template <class Swap>
void gatherInPlace(const std::vector<uint32_t>& order, std::size_t size, Swap&& swap) {
    std::vector<uint32_t> where(size), who(size);  // element -> its position now, and back
    std::iota(where.begin(), where.end(), 0u);
    std::iota(who.begin(), who.end(), 0u);
    for (std::size_t k = 0; k < order.size(); ++k) {
        // Positions below k hold order[0..k-1] already, so the element is at k or beyond.
        const uint32_t at = where[order[k]];
        if (at == k) continue;
        swap(k, static_cast<std::size_t>(at));
        std::swap(who[k], who[at]);
        where[who[k]] = static_cast<uint32_t>(k);
        where[who[at]] = at;
    }
}

}  // namespace talus
