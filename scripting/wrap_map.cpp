// SPDX-License-Identifier: MIT
//
// talus.map(n, fn [, {jobs =, on_error =, checkpoint =, key =}]), talus.rank(), talus.ranks():
// independent items (the rocks of a Monte Carlo) on all cores of a machine and across the
// ranks of an mpirun.
//
// How the items are shared. The n indices are cut into contiguous blocks of sizes that differ
// by at most one: first one block per MPI rank, then, inside a rank, the items still to run
// (those the checkpoint does not hold) are cut into one share per worker process
// (map_workers.hpp: the forks, the frames they send, what a failed or dead worker gives).
// With a checkpoint directory the caller writes each value it receives to its own file, and a
// later map with the same key reads them back instead of running those items (map_checkpoint.hpp:
// a damaged file is run again, with a note naming it). Under MPI each rank packs its block's
// values and all ranks exchange them (mpi_world.hpp), so every rank returns the whole list.
//
// Why the results are identical whatever the number of jobs and ranks: fn(i) is computed by
// the same code from the same state (a fork copies the caller's state; another rank runs the
// same script), its value is encoded exactly (numbers by their bits), and the caller builds
// every result by decoding the bytes, including when it ran fn(i) itself (jobs = 1): the
// decoded tables are built the same way on every path.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "lua_bindings.hpp"
#include "map_checkpoint.hpp"
#include "map_codec.hpp"
#include "map_workers.hpp"
#include "mpi_world.hpp"
#include "talus/run_control.hpp"

namespace talus::lua {

namespace {

/// Maps running in this process (a worker inherits its parent's count). A map called from
/// inside fn runs its items in place: forking again would multiply the processes, and under
/// MPI the ranks run different items, so a collective exchange could never match up.
int g_depth = 0;

class DepthGuard {
public:
    DepthGuard() { ++g_depth; }
    ~DepthGuard() { --g_depth; }
    DepthGuard(const DepthGuard&) = delete;
    DepthGuard& operator=(const DepthGuard&) = delete;
};

const Option kMapOptionRows[] = {
    {"jobs", "integer", "worker processes (default: the usable cores, or TALUS_JOBS)"},
    {"on_error", "\"record\"|\"raise\"",
     "record: a failed item is nil and listed in results.failed (default); raise: stop"},
    {"checkpoint", "string", "a directory where every finished value is kept for a rerun"},
    {"key", "string", "names what the items are: an item stored with another key runs again"},
};
const OptionTable kMapOptions = {"talus.MapOptions", "talus.map(n, fn, {...})", kMapOptionRows};

// ------------------------------------------------------------------ MPI exchange

void put64(std::string& s, uint64_t v) {
    char b[8];
    std::memcpy(b, &v, 8);
    s.append(b, 8);
}

uint64_t get64(const std::string& s, std::size_t& pos) {
    if (s.size() - pos < 8) throw std::runtime_error("map: corrupt data from another rank");
    uint64_t v;
    std::memcpy(&v, s.data() + pos, 8);
    pos += 8;
    return v;
}

/// This rank's outcome as bytes: 'F' index message (raise mode), or 'V' then per item its
/// length and bytes (0: no value), the failures (count, then index, length, message each), the
/// items taken from the checkpoint, those of another key and the damaged ones.
std::string pack(const Outcome& o) {
    std::string s;
    if (o.failed) {
        s.push_back('F');
        put64(s, static_cast<uint64_t>(o.index));
        s += o.message;
        return s;
    }
    s.push_back('V');
    for (const std::string& v : o.values) {
        put64(s, v.size());
        s += v;
    }
    put64(s, o.failures.size());
    for (const auto& [i, msg] : o.failures) {
        put64(s, static_cast<uint64_t>(i));
        put64(s, msg.size());
        s += msg;
    }
    put64(s, static_cast<uint64_t>(o.held.taken));
    put64(s, static_cast<uint64_t>(o.held.other_key));
    put64(s, static_cast<uint64_t>(o.held.damaged));
    return s;
}

std::string getBytes(const std::string& s, std::size_t& pos) {
    const uint64_t len = get64(s, pos);
    if (s.size() - pos < len) throw std::runtime_error("map: corrupt data from another rank");
    std::string v = s.substr(pos, static_cast<std::size_t>(len));
    pos += static_cast<std::size_t>(len);
    return v;
}

/// pack() read back, for rank r's block of n items among `ranks`.
Outcome unpack(const std::string& s, int64_t n, int64_t ranks, int64_t r) {
    Outcome o;
    if (s.empty()) throw std::runtime_error("map: corrupt data from another rank");
    std::size_t pos = 1;
    if (s[0] == 'F') {
        o.failed = true;
        o.index = static_cast<int64_t>(get64(s, pos));
        o.message = s.substr(pos);
        return o;
    }
    int64_t first, size;
    block(n, ranks, r, first, size);
    o.values.resize(static_cast<std::size_t>(size));
    for (auto& v : o.values) v = getBytes(s, pos);
    const uint64_t nf = get64(s, pos);
    for (uint64_t k = 0; k < nf; ++k) {
        const auto i = static_cast<int64_t>(get64(s, pos));
        o.failures.emplace_back(i, getBytes(s, pos));
    }
    o.held.taken = static_cast<int64_t>(get64(s, pos));
    o.held.other_key = static_cast<int64_t>(get64(s, pos));
    o.held.damaged = static_cast<int64_t>(get64(s, pos));
    return o;
}

// ------------------------------------------------------------------ Lua functions

/// talus.map's arguments, checked.
struct MapRequest {
    long long n = 0;
    int64_t jobs = 1;
    OnError mode = OnError::Record;
    Checkpoint ckpt;
    bool nested = false;      ///< called from inside fn: runs in place
    bool collective = false;  ///< the ranks of an mpirun share the items
};

MapRequest readRequest(lua_State* L) {
    MapRequest r;
    r.n = toInteger(L, 1, "map: n (the number of items)");
    if (r.n < 0) throw ScriptError("map: n must be >= 0 (got " + std::to_string(r.n) + ")");
    if (lua_type(L, 2) != LUA_TFUNCTION)
        throw ScriptError("map: fn must be a function (got " + typeName(L, 2) + ")");
    const Options opts(L, 3, "map", kMapOptions, true);
    int64_t jobs = opts.integer("jobs", 0);
    const bool jobs_given = opts.has("jobs");
    if (jobs_given && jobs < 1)
        throw ScriptError(opts.field("jobs") + " must be >= 1 (got " + std::to_string(jobs) + ")");
    r.mode =
        opts.choice("on_error", 0, {"record", "raise"}) == 0 ? OnError::Record : OnError::Raise;
    r.ckpt.dir = opts.string("checkpoint", "");
    r.ckpt.key = opts.string("key", "");
    if (opts.has("checkpoint") && r.ckpt.dir.empty())
        throw ScriptError(opts.field("checkpoint") + " must be a directory name");
    if (opts.has("key") && !r.ckpt.on())
        throw ScriptError(opts.field("key") + " goes with 'checkpoint' (a directory)");
    r.nested = g_depth > 0;
    // Under MPI the ranks already use the cores (mpirun -n <cores per machine>), and a fork
    // under MPI is fragile with some interconnects: one process per rank unless asked.
    if (!jobs_given) jobs = mpi::size() > 1 ? 1 : defaultJobs();
    r.jobs = r.nested ? 1 : jobs;
    r.collective = !r.nested && mpi::size() > 1;
    return r;
}

/// Runs this process's items [lo, hi] (fn at stack index 2): those the checkpoint holds are
/// taken from it, the others run in place or in workers.
Outcome runBlock(lua_State* L, const MapRequest& r, int64_t lo, int64_t hi) {
    Outcome mine;
    mine.values.assign(static_cast<std::size_t>(std::max<int64_t>(0, hi - lo + 1)), std::string());
    DepthGuard depth;
    if (r.ckpt.on()) r.ckpt.open();
    const std::vector<int64_t> todo = r.ckpt.take(lo, hi, mine.values, mine.held);
    const int fn = 2;
    const int64_t workers = std::min<int64_t>(r.jobs, static_cast<int64_t>(todo.size()));
    try {
        if (workers <= 1)
            runInPlace(L, fn, todo, lo, r.mode, r.ckpt, mine);
        else
            runForked(L, fn, todo, lo, workers, r.mode, r.ckpt, mine);
    } catch (const std::exception& e) {
        // A system failure (no pipe, no fork, corrupt frame) becomes this block's failure:
        // under MPI it must still reach the exchange, or the other ranks would wait there for
        // this one forever.
        if (!r.collective) throw;
        std::string text = e.what();
        if (text.rfind("map: ", 0) == 0) text.erase(0, 5);
        mine.failed = true;
        mine.index = lo;
        mine.message = text;
    }
    return mine;
}

/// Every rank's outcome, in rank order (this one alone without MPI).
std::vector<Outcome> gather(Outcome mine, const MapRequest& r) {
    std::vector<Outcome> ranks;
    if (!r.collective) {
        ranks.push_back(std::move(mine));
        return ranks;
    }
    const std::vector<std::string> all = mpi::allgather(pack(mine));
    for (std::size_t k = 0; k < all.size(); ++k)
        ranks.push_back(
            unpack(all[k], r.n, static_cast<int64_t>(all.size()), static_cast<int64_t>(k)));
    return ranks;
}

/// Ctrl-C reaches the workers with the caller (one process group): the items it stopped failed
/// as "interrupted", and the values left would look like a whole map. Raises, as an interrupted
/// run call does; the finished items are in the checkpoint for a rerun. When every item had
/// finished, the map returns them.
void raiseIfInterrupted(const std::vector<Outcome>& ranks, const MapRequest& r) {
    if (!talus::stopRequested()) return;
    int64_t done = 0;
    for (const Outcome& o : ranks)
        for (const std::string& v : o.values) done += v.empty() ? 0 : 1;
    if (done >= r.n) return;
    throw ScriptError("map: interrupted (Ctrl-C) with " + std::to_string(done) + " of " +
                      std::to_string(r.n) + " items done" +
                      (r.ckpt.on() ? "; they are kept in the checkpoint '" + r.ckpt.dir +
                                         "': a rerun with it runs only the others"
                                   : ""));
}

/// What the map says on stderr (rank 0, outermost map): the items taken from the checkpoint,
/// and the failures.
struct MapSummary {
    std::vector<std::pair<int64_t, std::string>> failures;  // sorted by index
    CheckpointCounts held;
};

/// Pushes the list of results (decoding every value) and sums up the ranks' outcomes.
MapSummary pushResults(lua_State* L, const std::vector<Outcome>& ranks, long long n) {
    MapSummary sum;
    lua_createtable(L, static_cast<int>(std::min<long long>(n, 1 << 24)), 0);
    lua_Integer i = 1;
    for (const Outcome& o : ranks) {
        for (const std::string& v : o.values) {
            if (!v.empty()) {
                decodeValue(L, v.data(), v.size());
                lua_rawseti(L, -2, i);
            }
            ++i;
        }
        sum.failures.insert(sum.failures.end(), o.failures.begin(), o.failures.end());
        sum.held += o.held;
    }
    std::sort(sum.failures.begin(), sum.failures.end());
    return sum;
}

/// results.failed = {{index =, message =}, ...}, in index order, on the list on top.
void pushFailures(lua_State* L, const MapSummary& sum) {
    lua_createtable(L, static_cast<int>(sum.failures.size()), 0);
    for (std::size_t k = 0; k < sum.failures.size(); ++k) {
        lua_createtable(L, 0, 2);
        setInteger(L, "index", static_cast<lua_Integer>(sum.failures[k].first));
        setString(L, "message", sum.failures[k].second);
        lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    lua_setfield(L, -2, "failed");
}

void report(const MapSummary& sum, const MapRequest& r) {
    if (sum.held.any()) {
        std::fflush(stdout);
        std::fprintf(stderr, "talus: map: %lld of %lld items taken from the checkpoint '%s'",
                     static_cast<long long>(sum.held.taken), r.n, r.ckpt.dir.c_str());
        if (sum.held.other_key > 0)
            std::fprintf(stderr, "; %lld stored by another run (another key) were run again",
                         static_cast<long long>(sum.held.other_key));
        if (sum.held.damaged > 0)
            std::fprintf(stderr, "; %lld damaged (run again)",
                         static_cast<long long>(sum.held.damaged));
        std::fprintf(stderr, "\n");
    }
    if (!sum.failures.empty()) {
        clearProgressLine();
        std::fflush(stdout);
        std::fprintf(stderr,
                     "talus: warning: map: %zu of %lld items failed (their results are nil; "
                     "results.failed lists index and message)%s; the first: %s\n",
                     sum.failures.size(), r.n,
                     r.ckpt.on() ? "; a rerun with the same checkpoint runs only those" : "",
                     sum.failures.front().second.c_str());
    }
}

int w_map(lua_State* L) {
    return catchexcept(L, [&] {
        const MapRequest r = readRequest(L);
        int64_t lo = 1, hi = r.n;
        if (r.collective) {
            int64_t first, size;
            block(r.n, mpi::size(), mpi::rank(), first, size);
            lo = 1 + first;
            hi = lo + size - 1;
        }
        lua_settop(L, 3);
        const std::vector<Outcome> ranks = gather(runBlock(L, r, lo, hi), r);
        // The failure with the lowest index, the same on every rank.
        const Outcome* failed = nullptr;
        for (const Outcome& o : ranks)
            if (o.failed && (!failed || o.index < failed->index)) failed = &o;
        if (failed) throw ScriptError("map: " + failed->message);
        raiseIfInterrupted(ranks, r);
        const MapSummary sum = pushResults(L, ranks, r.n);
        if (!sum.failures.empty()) pushFailures(L, sum);
        if (mpi::rank() == 0 && !r.nested) report(sum, r);
        return 1;
    });
}

int w_rank(lua_State* L) {
    lua_pushinteger(L, mpi::rank());
    return 1;
}

int w_ranks(lua_State* L) {
    lua_pushinteger(L, mpi::size());
    return 1;
}

const Method kMapFunctions[] = {
    {"map", w_map, "{fn(1), ..., fn(n)}, computed on all cores and across MPI ranks",
     "n: integer, fn: fun(i: integer): any, options?: talus.MapOptions", "table"},
    {"rank", w_rank, "this process's MPI rank (0-based); 0 without mpirun", "", "integer"},
    {"ranks", w_ranks, "the number of MPI ranks; 1 without mpirun", "", "integer"},
};

const OptionTable* const kOptionTables[] = {&kMapOptions};

}  // namespace

extern const Binding kMapBinding = {"independent runs", {}, kMapFunctions, {}, kOptionTables, {}};

}  // namespace talus::lua
