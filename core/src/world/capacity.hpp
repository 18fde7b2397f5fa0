// SPDX-License-Identifier: MIT
//
// The memory of a store's arrays beyond their elements: the spare capacity of a vector grown one
// element at a time (it doubles, so a store built in one go, the balls of a script or a
// packing's pairs at the first step, may hold up to twice what it needs for the rest of the run),
// and the blocks the allocator keeps after they were freed. Not installed.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace talus {

/// Gives back the spare capacity of v when it is more than an eighth of its size (a copy of v
/// for a moment: called where the rest of the model is small, before a run's first step).
template <class T>
void trimCapacity(std::vector<T>& v) {
    if (v.capacity() > v.size() + v.size() / 8) v.shrink_to_fit();
}

/// Room for one more element of v, growing it by a quarter, not by doubling (a store that
/// grows in bursts or right after it was trimmed: the guard's watch of a packing's contacts at
/// its first step, the pairs made after the first step).
template <class T>
void reserveOneMore(std::vector<T>& v) {
    if (v.size() == v.capacity()) v.reserve(v.size() + v.size() / 4 + 16);
}

/// Large blocks (a store's arrays) each in a mapping of their own, given back to the system when
/// freed. glibc's default raises its threshold for that to the size of the last such block freed,
/// after which the arrays a model outgrows while it is built stay in the heap as free pages that
/// still count in its resident set (docs/results/memory.md). Once per process; not where the user
/// set the threshold (glibc's MALLOC_MMAP_THRESHOLD_ or GLIBC_TUNABLES).
inline void mapLargeBlocks() {
#if defined(__GLIBC__)
    static const bool done = [] {
        const char* tunables = std::getenv("GLIBC_TUNABLES");
        if (std::getenv("MALLOC_MMAP_THRESHOLD_") ||
            (tunables && std::strstr(tunables, "mmap_threshold")))
            return false;
        return mallopt(M_MMAP_THRESHOLD, 256 * 1024) == 1;
    }();
    (void)done;
#endif
}

}  // namespace talus
