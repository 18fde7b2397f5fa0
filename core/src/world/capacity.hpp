// SPDX-License-Identifier: MIT
//
// The spare capacity of a store's arrays: a vector grown one element at a time doubles, so a
// store built in one go (the balls of a script, a packing's pairs at the first step) may hold up
// to twice what it needs for the rest of the run. Not installed.
#pragma once

#include <cstddef>
#include <vector>

namespace talus {

/// Gives back the spare capacity of v when it is more than an eighth of its size (a copy of v
/// for a moment: called where the rest of the model is small, before a run's first step).
template <class T>
void trimCapacity(std::vector<T>& v) {
    if (v.capacity() > v.size() + v.size() / 8) v.shrink_to_fit();
}

/// Room for one more element of v, growing it by a quarter, not by doubling (a store that
/// grows in bursts, such as the guard's watch of a packing's contacts at its first step).
template <class T>
void reserveOneMore(std::vector<T>& v) {
    if (v.size() == v.capacity()) v.reserve(v.size() + v.size() / 4 + 16);
}

}  // namespace talus
