// SPDX-License-Identifier: MIT
//
// How talus.map runs a block of its items: in place, one after the other (runInPlace), or by
// worker processes (runForked). Each worker is a fork() of the caller: it inherits the whole
// Lua state (fn, its upvalues, loaded models and modules) and runs fn(i) for the indices of its
// share of the block, in order.
//
// Every result is encoded (map_codec.hpp) and sent through a pipe as one frame
//     kind (1 byte: 'v' value, 'e' failure) | index (8 bytes) | length (8 bytes) | bytes
// The caller reads every pipe with poll(), so a worker never blocks on a full pipe while the
// caller waits for another; it stores each value it receives in the checkpoint as it arrives.
//
// Failures. OnError::Record: a worker that meets a failing item sends it as a failure frame and
// goes on; one that dies is replaced by a new fork of the caller (whose state the map does not
// change) for the rest of its share; the item it was running is the failure. OnError::Raise:
// the first failure stops the map (the lowest index, as a serial loop): workers of higher
// shares are stopped, those of lower ones run on.
//
// Threads: the engine starts OpenMP threads only for m:threads(n > 1) (the force loop and the
// law of motion; plugins start none), and between steps they only wait in libgomp's pool, so
// fork() copies a consistent process; but the pool does not survive the fork, so a worker keeps
// every model on one thread (Model::singleThreadedProcess): its runs are the same bits anyway
// (docs/architecture.md, "Threads"), and the workers are the parallelism.
//
// Workers end with _exit() after flushing their own stdio buffers: the caller's atexit
// handlers, destructors and (under MPI) MPI's shutdown must run once, in the caller.
#pragma once

#include <cstdint>
#include <lua.hpp>
#include <string>
#include <utility>
#include <vector>

#include "map_checkpoint.hpp"

namespace talus::lua {

/// How a failed item is handled (the `on_error` option).
enum class OnError {
    Record,  ///< the item's result is nil, the failure goes into results.failed; the rest runs
    Raise,   ///< the map stops and raises the failure with the lowest index
};

/// What running some items of [lo, hi] gave: one encoded value per index ("" for an item with
/// no value: failed in record mode, or not run because the map stopped), the failures.
struct Outcome {
    std::vector<std::string> values;  // values[i - lo]
    // Raise mode: the first failure (the lowest index).
    bool failed = false;
    int64_t index = 0;    // the failed item (for a dead worker: the one it was running)
    std::string message;  // "fn(5) failed: script.lua:12: boom"
    // Record mode: every failed item, in index order once sorted.
    std::vector<std::pair<int64_t, std::string>> failures;
    CheckpointCounts held;  // what the checkpoint held for [lo, hi]
};

/// Block w of `count` items cut into `parts` contiguous blocks: first index (0-based) and size.
void block(int64_t count, int64_t parts, int64_t w, int64_t& first, int64_t& size);

/// "fn(5)": how messages name item 5.
std::string itemName(int64_t i);

/// Runs the items `todo` (indices in [lo, ...], fn at stack index `fn`) one after the other in
/// this process, each value into out.values[i - lo] and the checkpoint.
void runInPlace(lua_State* L, int fn, const std::vector<int64_t>& todo, int64_t lo, OnError mode,
                const Checkpoint& ckpt, Outcome& out);

/// The same with `jobs` forked workers, each given a contiguous share of `todo`. Throws
/// std::runtime_error for a system failure (no pipe, no fork, a corrupt frame); the workers are
/// stopped and reaped whatever happens.
void runForked(lua_State* L, int fn, const std::vector<int64_t>& todo, int64_t lo, int64_t jobs,
               OnError mode, const Checkpoint& ckpt, Outcome& out);

/// The default number of worker processes: TALUS_JOBS, else the cores this process may use.
int64_t defaultJobs();

}  // namespace talus::lua
