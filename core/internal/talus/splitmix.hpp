// SPDX-License-Identifier: MIT
// SplitMix64 (Steele, Lea & Flood 2014): a tiny fixed-seed generator that gives the same stream
// on every platform, so that scenes, tests and benchmarks never depend on the standard library's
// distributions. Internal (core/internal/ is not installed): the engine (m:bond's drawn
// properties), the scene builders and the tests share it.
#pragma once

#include <cstdint>

namespace talus {

class SplitMix64 {
public:
    explicit SplitMix64(uint64_t seed) : m_state(seed) {}
    uint64_t next() {
        uint64_t z = (m_state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, 1), 53 random bits.
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    /// Uniform integer in [0, n); the modulo bias (n / 2^64) is far below anything measurable.
    uint64_t below(uint64_t n) { return next() % n; }

private:
    uint64_t m_state;
};

}  // namespace talus
