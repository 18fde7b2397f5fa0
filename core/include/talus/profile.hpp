// SPDX-License-Identifier: MIT
// Time spent per cycle phase (Box2D's b2Profile idea), summed since the last reset.
#pragma once

#include <cstdint>
#include <string>

namespace talus {

struct Profile {
    bool enabled = true;
    double timestep = 0.0;  ///< [s] wall-clock
    double motion = 0.0;
    double detection = 0.0;           ///< broadphase updates and new pairs
    double force_displacement = 0.0;  ///< narrowphase + FDlaw + force sums
    double bookkeeping = 0.0;
    int64_t cycles = 0;
    int64_t proxy_moves = 0;  ///< broadphase re-insertions
    int64_t pairs_created = 0;
    int64_t contacts_created = 0;
    int64_t kernel_steps = 0;     ///< contact steps run by the host's kernel of a model's law
    int64_t kernel_declined = 0;  ///< ... of which the kernel declined (FDlaw ran them)
    int64_t threaded_steps = 0;   ///< steps whose force loop ran on more than one thread
    int64_t sorts = 0;            ///< memory re-orderings of the balls (setSortInterval)
    void reset() { *this = Profile{enabled}; }
    double total() const {
        return timestep + motion + detection + force_displacement + bookkeeping;
    }
    std::string report(std::size_t balls) const;
};

}  // namespace talus
