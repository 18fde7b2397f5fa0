// SPDX-License-Identifier: MIT
//
// "Did you mean": the known names closest to a name that is not known, for every "unknown
// name" error (contact models, properties, options, fields, methods; the Lua libraries reach it
// through talus.did_you_mean). Header-only: the engine and the scripting layer share it.
// Internal (core/internal/ is not installed).
//
// Closeness is the optimal-string-alignment distance (Damerau 1964; Levenshtein 1966): the
// fewest insertions, deletions, substitutions and swaps of two neighbouring characters that
// turn one name into the other, letters compared without case. "linaer" is one swap from
// "linear", "knn" one deletion from "kn". A name is suggested when it is within a third of the
// typed name's length (at least 1 edit, at most 3), so that "fric" is not offered for "kn".
#pragma once

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <string>
#include <vector>

namespace talus {

/// Optimal-string-alignment distance between a and b, ignoring case.
inline std::size_t editDistance(const std::string& a, const std::string& b) {
    const auto low = [](char c) {
        return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    };
    const std::size_t n = a.size(), m = b.size();
    // Three rows of the dynamic-programming table: i - 2, i - 1 and i.
    std::vector<std::size_t> two(m + 1), one(m + 1), cur(m + 1);
    for (std::size_t j = 0; j <= m; ++j) one[j] = j;
    for (std::size_t i = 1; i <= n; ++i) {
        cur[0] = i;
        for (std::size_t j = 1; j <= m; ++j) {
            const std::size_t cost = low(a[i - 1]) == low(b[j - 1]) ? 0 : 1;
            cur[j] = std::min({one[j] + 1, cur[j - 1] + 1, one[j - 1] + cost});
            if (i > 1 && j > 1 && low(a[i - 1]) == low(b[j - 2]) && low(a[i - 2]) == low(b[j - 1]))
                cur[j] = std::min(cur[j], two[j - 2] + 1);
        }
        std::swap(two, one);
        std::swap(one, cur);
    }
    return one[m];
}

/// The candidates closest to `name` within max(1, min(3, |name| / 3)) edits, nearest first (ties
/// in the order given), at most three; none when `name` is itself a candidate.
inline std::vector<std::string> closeNames(const std::string& name,
                                           const std::vector<std::string>& candidates) {
    const std::size_t limit = std::max<std::size_t>(1, std::min<std::size_t>(3, name.size() / 3));
    std::vector<std::pair<std::size_t, std::size_t>> found;  // (distance, index)
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        const std::size_t d = editDistance(name, candidates[i]);
        if (d == 0) return {};
        if (d <= limit) found.emplace_back(d, i);
    }
    std::stable_sort(found.begin(), found.end(),
                     [](const auto& x, const auto& y) { return x.first < y.first; });
    std::vector<std::string> out;
    for (const auto& f : found) {
        const std::string& c = candidates[f.second];
        if (std::find(out.begin(), out.end(), c) == out.end()) out.push_back(c);
        if (out.size() == 3) break;
    }
    return out;
}

/// "; did you mean 'linear'?" (or "'a' or 'b'", "'a', 'b' or 'c'"), or "" when no candidate is
/// close: the piece an "unknown name" error puts after the name.
inline std::string didYouMean(const std::string& name, const std::vector<std::string>& candidates) {
    const std::vector<std::string> close = closeNames(name, candidates);
    if (close.empty()) return "";
    std::string text = "; did you mean ";
    for (std::size_t i = 0; i < close.size(); ++i) {
        if (i) text += i + 1 == close.size() ? " or " : ", ";
        text += "'" + close[i] + "'";
    }
    return text + "?";
}

}  // namespace talus
