// SPDX-License-Identifier: MIT
// The stop flag of run_control.hpp.
#include "talus/run_control.hpp"

#include <atomic>

namespace talus {

namespace {
// Lock-free on every platform we build for (checked below), so a signal handler may store it.
std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the stop flag must be lock-free");
}  // namespace

void requestStop() noexcept { g_stop.store(true, std::memory_order_relaxed); }
bool stopRequested() noexcept { return g_stop.load(std::memory_order_relaxed); }
void clearStopRequest() noexcept { g_stop.store(false, std::memory_order_relaxed); }

}  // namespace talus
