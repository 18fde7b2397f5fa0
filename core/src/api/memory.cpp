// SPDX-License-Identifier: MIT
//
// The memory a model needs as it grows, checked before it is allocated (docs/physics/guard.md,
// "Memory"). A model of 1e7 balls ran the machine out of memory at its first cycle and the kernel
// killed the process with no message; now the cycle (or the ball) that would not fit is refused
// with what it needs and what there is.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "api/operations.hpp"
#include "talus/errors.hpp"
#include "world/messages.hpp"

namespace talus {

namespace {

// Bytes per ball and per pair, measured on a dense hexagonal pack of 50 000 to 400 000 disks
// (docs/results/memory.md): a ball's arrays 282 B, with what the first cycle adds for it (its
// broadphase node, the step's per-ball scratch) 527 B; a broadphase pair 684 B apart and 853 B
// touching with `linear` (208 B model object), 1 200 B with `pbond` (464 B): its records, the key
// index, the force loop's scratch and lane row, and its model object, counted here at the rules'
// largest. A dense 2D pack has 3.0 pairs per ball, and no scene has many more.
constexpr double kBallBytes = 530.0;
constexpr double kPairBytes = 700.0;  // plus the model object
constexpr double kPairsPerBall = 3.0;
// Below this the check does not read /proc/meminfo: no model is refused for a few megabytes.
constexpr double kCheckFrom = 64.0 * 1024.0 * 1024.0;

/// MemAvailable of /proc/meminfo [bytes]; negative when it cannot be read (no check then).
double memAvailable() {
    std::FILE* f = std::fopen("/proc/meminfo", "r");
    if (!f) return -1.0;
    char line[256];
    double kb = -1.0;
    while (std::fgets(line, sizeof line, f))
        if (std::strncmp(line, "MemAvailable:", 13) == 0) {
            kb = std::strtod(line + 13, nullptr);
            break;
        }
    std::fclose(f);
    return kb >= 0.0 ? kb * 1024.0 : -1.0;
}

std::string bytesText(double b) {
    const char* unit[] = {"B", "kB", "MB", "GB", "TB"};
    int k = 0;
    while (b >= 1000.0 && k < 4) b /= 1000.0, ++k;
    return messageNumber(b, 3) + " " + unit[k];
}

}  // namespace

void requireMemory(World& world, std::size_t balls, const char* what) {
    double object = 0.0;  // the largest contact-model object of the rules
    for (const auto& r : world.contacts.rules)
        if (r->pool) object = std::max(object, static_cast<double>(r->pool->blockSize()));
    const double per_pair = kPairBytes + object;
    const double counted = static_cast<double>(world.guard_state.memory_counted_balls);
    const double fresh = std::max(0.0, static_cast<double>(balls) - counted);
    // What the model holds now, and what the balls it has not run yet will add with their pairs.
    const double pairs = static_cast<double>(world.contacts.pairs.size());
    const double held = counted * kBallBytes + pairs * per_pair;
    const double more = fresh * (kBallBytes + kPairsPerBall * per_pair);
    const double limit = world.settings.guard.memory_limit;
    if (more < kCheckFrom && !(limit > 0.0)) return;
    const double available = limit > 0.0 ? limit - held : memAvailable();
    if (!(available >= 0.0 && more > available) && !(limit > 0.0 && held + more > limit)) return;
    throw InputError(
        std::string(what) + ": the model would need about " + bytesText(held + more) + " (" +
        std::to_string(balls) + " balls at about " + bytesText(kBallBytes) + " each, with about " +
        messageNumber(kPairsPerBall, 2) + " contact pairs each at " + bytesText(per_pair) + "), " +
        bytesText(more) + " more than it holds now, and " +
        (limit > 0.0 ? "m:guard{memory_limit =} allows " + bytesText(limit) + " in all"
                     : "the machine has " + bytesText(available) +
                           " available (MemAvailable in /proc/meminfo)") +
        ": make the model smaller (fewer or larger balls), or run it on a larger machine "
        "(docs/physics/guard.md, \"Memory\")");
}

}  // namespace talus
