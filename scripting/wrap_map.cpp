// SPDX-License-Identifier: MIT
//
// talus.map(n, fn [, {jobs =, on_error =, checkpoint =, key =}]), talus.rank(), talus.ranks():
// independent items (the rocks of a Monte Carlo) on all cores of a machine and across the
// ranks of an mpirun.
//
// How the items are shared. The n indices are cut into contiguous blocks of sizes that differ
// by at most one: first one block per MPI rank, then, inside a rank, the items still to run
// (those the checkpoint does not hold) are cut into one block per worker process. Each worker
// is a fork() of the caller: it inherits the whole Lua state (fn, its upvalues, loaded models
// and modules) and runs fn(i) for the indices of its block, in order.
//
// Failures. on_error = "record" (the default): a worker that meets a failing item sends it as a
// failure frame and goes on; one that dies is replaced by a new fork of the caller (whose state
// the map does not change) for the rest of its block; the item it was running is the failure.
// on_error = "raise": the first failure stops the map (the lowest index, as a serial loop).
// With a checkpoint directory the caller writes each value it receives to its own file, and a
// later map with the same key reads them back instead of running those items.
// Every result is encoded (map_codec.hpp) and sent through a pipe as one frame
//     kind (1 byte: 'v' value, 'e' failure) | index (8 bytes) | length (8 bytes) | bytes
// The caller reads every pipe with poll(), so a worker never blocks on a full pipe while the
// caller waits for another. Under MPI each rank packs its block's values and all ranks exchange
// them (mpi_world.hpp), so every rank returns the whole list.
//
// Why the results are identical whatever the number of jobs and ranks: fn(i) is computed by
// the same code from the same state (a fork copies the caller's state; another rank runs the
// same script), its value is encoded exactly (numbers by their bits), and the caller builds
// every result by decoding the bytes, including when it ran fn(i) itself (jobs = 1): the
// decoded tables are built the same way on every path.
//
// Threads: the engine starts OpenMP threads only for m:threads(n > 1) (the force loop and the
// law of motion; plugins start none), and between steps they only wait in libgomp's pool, so
// fork() copies a consistent process; but the pool does not survive the fork, so a worker keeps
// every model on one thread (Model::singleThreadedProcess): its runs are the same bits anyway
// (docs/architecture.md, "Threads"), and the workers are the parallelism.
//
// Workers end with _exit() after flushing their own stdio buffers: the caller's atexit
// handlers, destructors and (under MPI) MPI's shutdown must run once, in the caller.
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "lua_bindings.hpp"
#include "map_codec.hpp"
#include "mpi_world.hpp"
#include "talus/model.hpp"
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

/// How a failed item is handled (the `on_error` option).
enum class OnError {
    Record,  ///< the item's result is nil, the failure goes into results.failed; the rest runs
    Raise,   ///< the map stops and raises the failure with the lowest index
};

/// Finished values kept on disk as they arrive (the `checkpoint` option), so that a rerun of
/// the same map, after a failure or a killed job, runs only what is missing. One file per item,
/// `<dir>/item_<i>.tmv`, written through a temporary file and a rename (a half-written file is
/// never taken): "talus.map item\n", the key (8-byte length, bytes), the encoded value.
struct Checkpoint {
    std::string dir;  // "" = none
    std::string key;

    bool on() const { return !dir.empty(); }
    std::string file(int64_t i) const { return dir + "/item_" + std::to_string(i) + ".tmv"; }

    /// The stored value of item i, if there is one written with this key. `other` is set when
    /// a file is there but was written with another key (another run: it is run again).
    bool load(int64_t i, std::string& value, bool& other) const {
        other = false;
        std::FILE* f = std::fopen(file(i).c_str(), "rb");
        if (!f) return false;
        std::string bytes;
        char buf[1 << 16];
        std::size_t got;
        while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.append(buf, got);
        std::fclose(f);
        static const std::string magic = "talus.map item\n";
        uint64_t klen = 0;
        if (bytes.size() < magic.size() + 8 || bytes.compare(0, magic.size(), magic) != 0)
            return other = true, false;
        std::memcpy(&klen, bytes.data() + magic.size(), 8);
        const std::size_t at = magic.size() + 8;
        if (bytes.size() - at < klen || bytes.compare(at, klen, key) != 0 || klen != key.size())
            return other = true, false;
        value = bytes.substr(at + klen);
        return !value.empty();
    }

    /// Stores item i's value; a failure to write is reported once on stderr and the map goes
    /// on (the results are still returned; only the rerun loses them).
    void store(int64_t i, const std::string& value) const {
        static const std::string magic = "talus.map item\n";
        const std::string path = file(i), tmp = dir + "/.item_" + std::to_string(i) + ".tmp";
        std::FILE* f = std::fopen(tmp.c_str(), "wb");
        bool ok = f != nullptr;
        if (ok) {
            const uint64_t klen = key.size();
            char len[8];
            std::memcpy(len, &klen, 8);
            ok = std::fwrite(magic.data(), 1, magic.size(), f) == magic.size() &&
                 std::fwrite(len, 1, 8, f) == 8 &&
                 std::fwrite(key.data(), 1, key.size(), f) == key.size() &&
                 std::fwrite(value.data(), 1, value.size(), f) == value.size();
            ok = (std::fclose(f) == 0) && ok;
        }
        if (ok && std::rename(tmp.c_str(), path.c_str()) == 0) return;
        const int err = errno;
        std::remove(tmp.c_str());
        static bool said = false;
        if (!said) {
            said = true;
            std::fprintf(stderr,
                         "talus: warning: map: cannot write the checkpoint file '%s' (%s); the "
                         "map goes on, but a rerun will run such items again\n",
                         path.c_str(), std::strerror(err));
        }
    }
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
    int64_t from_checkpoint = 0;  // items taken from the checkpoint, not run
    int64_t other_key = 0;        // checkpoint files of another run (another key), run again
};

/// Block w of `count` items cut into `parts` contiguous blocks: first index (0-based) and size.
void block(int64_t count, int64_t parts, int64_t w, int64_t& first, int64_t& size) {
    const int64_t base = count / parts, extra = count % parts;
    first = w * base + std::min(w, extra);
    size = base + (w < extra ? 1 : 0);
}

std::string itemName(int64_t i) { return "fn(" + std::to_string(i) + ")"; }

/// Runs fn(i) (fn at stack index `fn`) and encodes its value into `encoded`; on failure returns
/// false with the message in `message`.
bool runItem(lua_State* L, int fn, int64_t i, std::string& encoded, std::string& message) {
    lua_pushvalue(L, fn);
    lua_pushinteger(L, static_cast<lua_Integer>(i));
    if (lua_pcall(L, 1, 1, 0) != LUA_OK) {
        message = itemName(i) + " failed: " + errorText(L, -1);
        lua_pop(L, 1);
        return false;
    }
    encoded.clear();
    try {
        encodeValue(L, -1, encoded);
    } catch (const EncodeError& e) {
        message = itemName(i) + " returned a value that talus.map cannot pass back: " + e.what() +
                  " (only nil, booleans, numbers, strings and tables of these)";
        lua_pop(L, 1);
        return false;
    }
    lua_pop(L, 1);
    return true;
}

void runInPlace(lua_State* L, int fn, const std::vector<int64_t>& todo, int64_t lo, OnError mode,
                const Checkpoint& ckpt, Outcome& out) {
    std::string encoded, message;
    for (const int64_t i : todo) {
        if (runItem(L, fn, i, encoded, message)) {
            if (ckpt.on()) ckpt.store(i, encoded);
            out.values[static_cast<std::size_t>(i - lo)] = encoded;
        } else if (mode == OnError::Record) {
            out.failures.emplace_back(i, message);
        } else {
            out.failed = true;
            out.index = i;
            out.message = message;
            return;
        }
    }
}

// ------------------------------------------------------------------ worker side

bool writeAll(int fd, const char* p, std::size_t len) {
    while (len > 0) {
        const ssize_t k = ::write(fd, p, len);
        if (k < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        p += k;
        len -= static_cast<std::size_t>(k);
    }
    return true;
}

bool writeFrame(int fd, char kind, int64_t index, const std::string& bytes) {
    char head[17];
    head[0] = kind;
    const uint64_t len = bytes.size();
    std::memcpy(head + 1, &index, 8);
    std::memcpy(head + 9, &len, 8);
    return writeAll(fd, head, sizeof head) && writeAll(fd, bytes.data(), bytes.size());
}

struct WorkerJob {
    const std::vector<int64_t>* items;  // the indices to run, in order
    int fd;
    bool record;      // go on after a failed item (OnError::Record)
    int status;       // exit status for _exit
    int64_t current;  // the item being run
};

/// The body of a worker, run under lua_pcall: a Lua error that escapes the per-item pcall (out
/// of memory while encoding) ends up there, never back in the caller's script frames.
int workerBody(lua_State* L) {
    auto* job = static_cast<WorkerJob*>(lua_touserdata(L, 1));
    lua_settop(L, 0);
    lua_pushvalue(L, lua_upvalueindex(1));  // fn
    const int fn = 1;
    std::string encoded, message;
    job->status = 0;
    for (const int64_t i : *job->items) {
        job->current = i;
        if (runItem(L, fn, i, encoded, message)) {
            if (!writeFrame(job->fd, 'v', i, encoded)) {
                job->status = 3;  // the caller is gone
                break;
            }
        } else {
            if (!writeFrame(job->fd, 'e', i, message)) job->status = 3;
            if (!job->record || job->status != 0) break;
        }
    }
    return 0;
}

[[noreturn]] void workerMain(lua_State* L, int fn, const std::vector<int64_t>& items, bool record,
                             int fd) {
    WorkerJob job{&items, fd, record, 4, items.empty() ? 0 : items.front()};
    try {
        lua_pushvalue(L, fn);
        lua_pushcclosure(L, workerBody, 1);
        lua_pushlightuserdata(L, &job);
        if (lua_pcall(L, 1, 0, 0) != LUA_OK) {
            writeFrame(
                fd, 'e', job.current,
                itemName(job.current) + " failed in its worker, outside fn: " + errorText(L, -1));
            job.status = 5;
        }
    } catch (...) {
        job.status = 6;
    }
    // What fn printed or wrote to files it left open; the caller flushed its own buffers
    // before the fork, so nothing is written twice.
    std::fflush(nullptr);
    ::close(fd);
    ::_exit(job.status);
}

// ------------------------------------------------------------------ caller side

struct Worker {
    pid_t pid = -1;
    int fd = -1;
    std::vector<int64_t> items;  // the indices of its block still to come, in order
    std::size_t next = 0;        // position in items of the value expected next
    std::string buf;
    std::size_t used = 0;  // bytes of buf already parsed
    bool eof = false;
    bool killed = false;        // we sent SIGTERM (a worker of a lower block failed)
    bool sent_failure = false;  // an 'e' frame arrived (raise mode: it stopped there)
    bool reaped = false;
    int status = 0;
    int64_t block_lo = 0, block_hi = 0;  // for messages: the range of its block

    bool done() const { return next >= items.size(); }
    int64_t current() const { return done() ? block_hi : items[next]; }
};

/// Owns the workers: whatever happens in the caller, they are stopped and reaped.
class Workers {
public:
    std::vector<Worker> w;
    ~Workers() {
        for (Worker& x : w) {
            if (x.fd >= 0) ::close(x.fd);
            if (x.pid > 0 && !x.reaped) {
                ::kill(x.pid, SIGKILL);
                int st;
                while (::waitpid(x.pid, &st, 0) < 0 && errno == EINTR) {
                }
            }
        }
    }
    /// Stops the workers whose blocks start after `index` (a failure there, raise mode): they
    /// cannot fail at a lower index. Workers of lower blocks run on, so that the failure
    /// reported is the one of the lowest index, the one a serial loop would meet first,
    /// whatever the jobs.
    void stopAbove(int64_t index) {
        for (Worker& x : w)
            if (x.pid > 0 && !x.eof && !x.killed && !x.items.empty() && x.items.front() > index) {
                ::kill(x.pid, SIGTERM);
                x.killed = true;
            }
    }
};

/// Forks worker k over x.items (from position x.next on).
void startWorker(lua_State* L, int fn, Workers& ws, std::size_t k, bool record) {
    Worker& x = ws.w[k];
    x.items.erase(x.items.begin(), x.items.begin() + static_cast<std::ptrdiff_t>(x.next));
    x.next = 0;
    x.buf.clear();
    x.used = 0;
    x.eof = x.killed = x.sent_failure = x.reaped = false;
    x.status = 0;
    int fds[2];
    if (::pipe(fds) != 0)
        throw std::runtime_error(std::string("map: cannot create a pipe: ") + std::strerror(errno));
    // Buffers the caller has not written yet would be copied into the worker.
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid < 0) {
        const int err = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        throw std::runtime_error(std::string("map: cannot start a worker process: ") +
                                 std::strerror(err));
    }
    if (pid == 0) {
        talus::Model::singleThreadedProcess();
        ::close(fds[0]);
        for (std::size_t j = 0; j < ws.w.size(); ++j)
            if (j != k && ws.w[j].fd >= 0) ::close(ws.w[j].fd);
        workerMain(L, fn, x.items, record, fds[1]);
    }
    ::close(fds[1]);
    x.pid = pid;
    x.fd = fds[0];
}

/// Parses the complete frames in x.buf; stores values into out; records a failure.
void parseFrames(Worker& x, Outcome& out, int64_t lo, Workers& all, OnError mode,
                 const Checkpoint& ckpt) {
    for (;;) {
        const std::size_t avail = x.buf.size() - x.used;
        if (avail < 17) break;
        const char* head = x.buf.data() + x.used;
        int64_t index;
        uint64_t len;
        std::memcpy(&index, head + 1, 8);
        std::memcpy(&len, head + 9, 8);
        if (avail - 17 < len) break;
        const char kind = head[0];
        if ((kind != 'v' && kind != 'e') || x.done() || index != x.items[x.next])
            throw std::runtime_error("map: corrupt frame from worker " + std::to_string(x.pid));
        std::string bytes(head + 17, static_cast<std::size_t>(len));
        x.used += 17 + static_cast<std::size_t>(len);
        if (kind == 'v') {
            if (ckpt.on()) ckpt.store(index, bytes);
            out.values[static_cast<std::size_t>(index - lo)] = std::move(bytes);
            ++x.next;
        } else if (mode == OnError::Record) {
            out.failures.emplace_back(index, std::move(bytes));
            ++x.next;  // the worker goes on with its next item
        } else {
            x.sent_failure = true;
            if (!out.failed || index < out.index) {
                out.failed = true;
                out.index = index;
                out.message = std::move(bytes);
            }
            all.stopAbove(index);  // the map fails: workers of higher blocks need not run on
        }
    }
    if (x.used > (1u << 20) && x.used * 2 > x.buf.size()) {
        x.buf.erase(0, x.used);
        x.used = 0;
    }
}

std::string describeExit(const Worker& x, int64_t jobs, std::size_t k) {
    std::string who = "worker " + std::to_string(k + 1) + " of " + std::to_string(jobs) +
                      (mpi::size() > 1 ? " on rank " + std::to_string(mpi::rank()) : "") +
                      " (pid " + std::to_string(x.pid) + ", indices " + std::to_string(x.block_lo) +
                      ".." + std::to_string(x.block_hi) + ")";
    std::string when = !x.done() ? " while running " + itemName(x.current()) : "";
    if (WIFSIGNALED(x.status)) {
        const int sig = WTERMSIG(x.status);
        const char* name = strsignal(sig);
        return who + " was killed by signal " + std::to_string(sig) + " (" + (name ? name : "?") +
               ")" + when;
    }
    if (WIFEXITED(x.status) && WEXITSTATUS(x.status) != 0)
        return who + " exited with status " + std::to_string(WEXITSTATUS(x.status)) + when;
    return who + " ended without returning " + itemName(x.current()) + " (did fn call os.exit?)";
}

void reap(Worker& x) {
    while (::waitpid(x.pid, &x.status, 0) < 0) {
        if (errno != EINTR) throw std::runtime_error("map: waitpid failed");
    }
    x.reaped = true;
}

void runForked(lua_State* L, int fn, const std::vector<int64_t>& todo, int64_t lo, int64_t jobs,
               OnError mode, const Checkpoint& ckpt, Outcome& out) {
    const int64_t count = static_cast<int64_t>(todo.size());
    const bool record = mode == OnError::Record;
    Workers ws;
    ws.w.resize(static_cast<std::size_t>(jobs));
    for (int64_t k = 0; k < jobs; ++k) {
        Worker& x = ws.w[static_cast<std::size_t>(k)];
        int64_t first, size;
        block(count, jobs, k, first, size);
        x.items.assign(todo.begin() + first, todo.begin() + first + size);
        x.block_lo = x.items.front();
        x.block_hi = x.items.back();
        startWorker(L, fn, ws, static_cast<std::size_t>(k), record);
    }

    std::vector<pollfd> pfds;
    std::vector<std::size_t> which;
    char chunk[1 << 16];
    for (;;) {
        pfds.clear();
        which.clear();
        for (std::size_t k = 0; k < ws.w.size(); ++k)
            if (!ws.w[k].eof) {
                pfds.push_back({ws.w[k].fd, POLLIN, 0});
                which.push_back(k);
            }
        if (pfds.empty()) break;
        if (::poll(pfds.data(), pfds.size(), -1) < 0) {
            if (errno == EINTR) continue;
            throw std::runtime_error(std::string("map: poll failed: ") + std::strerror(errno));
        }
        for (std::size_t p = 0; p < pfds.size(); ++p) {
            if (!(pfds[p].revents & (POLLIN | POLLHUP | POLLERR))) continue;
            const std::size_t k = which[p];
            Worker& x = ws.w[k];
            const ssize_t got = ::read(x.fd, chunk, sizeof chunk);
            if (got < 0) {
                if (errno == EINTR || errno == EAGAIN) continue;
                throw std::runtime_error(std::string("map: reading a worker failed: ") +
                                         std::strerror(errno));
            }
            if (got > 0) {
                x.buf.append(chunk, static_cast<std::size_t>(got));
                parseFrames(x, out, lo, ws, mode, ckpt);
                continue;
            }
            x.eof = true;
            ::close(x.fd);
            x.fd = -1;
            if (x.killed || x.sent_failure || x.done()) continue;
            // Ended before its last value without saying why: it died (or called os.exit)
            // while running its next item.
            if (!record) {
                ws.stopAbove(x.current());  // reported once reaped, below
                continue;
            }
            // Record mode: that item failed; a new worker (a fork of the caller, whose state
            // the map has not changed) goes on with the rest of the block.
            reap(x);
            // Status 5: an error outside fn, already sent as that item's failure frame.
            if (!(WIFEXITED(x.status) && WEXITSTATUS(x.status) == 5)) {
                out.failures.emplace_back(x.current(),
                                          describeExit(x, static_cast<int64_t>(ws.w.size()), k));
                ++x.next;
            }
            if (!x.done()) startWorker(L, fn, ws, k, record);
        }
    }

    for (std::size_t k = 0; k < ws.w.size(); ++k) {
        Worker& x = ws.w[k];
        if (!x.reaped) reap(x);
        if (x.killed || x.sent_failure || record) continue;  // stopped by us, or said why
        const bool clean = WIFEXITED(x.status) && WEXITSTATUS(x.status) == 0;
        if (clean && x.done()) continue;
        // Died, or stopped early without a failure frame: report with its index range.
        if (!out.failed || x.current() < out.index) {
            out.failed = true;
            out.index = x.current();
            out.message = describeExit(x, static_cast<int64_t>(ws.w.size()), k);
        }
    }
}

// ------------------------------------------------------------------ jobs

int64_t usableCores() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (::sched_getaffinity(0, sizeof set, &set) == 0) {
        const int c = CPU_COUNT(&set);
        if (c > 0) return c;
    }
    const long c = ::sysconf(_SC_NPROCESSORS_ONLN);
    return c > 0 ? c : 1;
}

/// The default number of worker processes: TALUS_JOBS, else the cores this process may use.
int64_t defaultJobs() {
    if (const char* env = std::getenv("TALUS_JOBS")) {
        char* end = nullptr;
        errno = 0;
        const long long v = std::strtoll(env, &end, 10);
        if (errno != 0 || end == env || *end != '\0' || v < 1)
            throw ScriptError(std::string("map: TALUS_JOBS must be a positive integer (got '") +
                              env + "')");
        return v;
    }
    return usableCores();
}

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
/// items taken from the checkpoint and those of another key.
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
    put64(s, static_cast<uint64_t>(o.from_checkpoint));
    put64(s, static_cast<uint64_t>(o.other_key));
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
    o.from_checkpoint = static_cast<int64_t>(get64(s, pos));
    o.other_key = static_cast<int64_t>(get64(s, pos));
    return o;
}

// ------------------------------------------------------------------ Lua functions

int w_map(lua_State* L) {
    return catchexcept(L, [&] {
        const long long n = toInteger(L, 1, "map: n (the number of items)");
        if (n < 0) throw ScriptError("map: n must be >= 0 (got " + std::to_string(n) + ")");
        if (lua_type(L, 2) != LUA_TFUNCTION)
            throw ScriptError("map: fn must be a function (got " + typeName(L, 2) + ")");
        const Options opts(L, 3, "map", {"jobs", "on_error", "checkpoint", "key"}, true);
        int64_t jobs = opts.integer("jobs", 0);
        const bool jobs_given = opts.has("jobs");
        if (jobs_given && jobs < 1)
            throw ScriptError(opts.field("jobs") + " must be >= 1 (got " + std::to_string(jobs) +
                              ")");
        const OnError mode =
            opts.choice("on_error", 0, {"record", "raise"}) == 0 ? OnError::Record : OnError::Raise;
        Checkpoint ckpt;
        ckpt.dir = opts.string("checkpoint", "");
        ckpt.key = opts.string("key", "");
        if (opts.has("checkpoint") && ckpt.dir.empty())
            throw ScriptError(opts.field("checkpoint") + " must be a directory name");
        if (opts.has("key") && !ckpt.on())
            throw ScriptError(opts.field("key") + " goes with 'checkpoint' (a directory)");
        const bool nested = g_depth > 0;
        // Under MPI the ranks already use the cores (mpirun -n <cores per machine>), and a
        // fork under MPI is fragile with some interconnects: one process per rank unless asked.
        if (!jobs_given) jobs = mpi::size() > 1 ? 1 : defaultJobs();
        if (nested) jobs = 1;
        const bool collective = !nested && mpi::size() > 1;

        int64_t lo = 1, hi = n;
        if (collective) {
            int64_t first, size;
            block(n, mpi::size(), mpi::rank(), first, size);
            lo = 1 + first;
            hi = lo + size - 1;
        }
        lua_settop(L, 3);
        const int fn = 2;
        Outcome mine;
        mine.values.assign(static_cast<std::size_t>(std::max<int64_t>(0, hi - lo + 1)),
                           std::string());
        {
            DepthGuard depth;
            // The items to run: all of this rank's block but those the checkpoint holds.
            std::vector<int64_t> todo;
            if (ckpt.on()) {
                std::error_code ec;
                std::filesystem::create_directories(ckpt.dir, ec);
                if (ec)
                    throw ScriptError("map: cannot create the checkpoint directory '" + ckpt.dir +
                                      "' (" + ec.message() + ")");
            }
            for (int64_t i = lo; i <= hi; ++i) {
                bool other = false;
                if (ckpt.on() && ckpt.load(i, mine.values[static_cast<std::size_t>(i - lo)], other))
                    ++mine.from_checkpoint;
                else
                    todo.push_back(i);
                mine.other_key += other;
            }
            const int64_t workers = std::min<int64_t>(jobs, static_cast<int64_t>(todo.size()));
            try {
                if (workers <= 1)
                    runInPlace(L, fn, todo, lo, mode, ckpt, mine);
                else
                    runForked(L, fn, todo, lo, workers, mode, ckpt, mine);
            } catch (const std::exception& e) {
                // A system failure (no pipe, no fork, corrupt frame) becomes this block's
                // failure: under MPI it must still reach the exchange, or the other ranks
                // would wait there for this one forever.
                if (!collective) throw;
                std::string text = e.what();
                if (text.rfind("map: ", 0) == 0) text.erase(0, 5);
                mine.failed = true;
                mine.index = lo;
                mine.message = text;
            }
        }

        // Every rank's values, in rank order (one rank without MPI).
        std::vector<Outcome> ranks;
        if (collective) {
            const std::vector<std::string> all = mpi::allgather(pack(mine));
            for (std::size_t r = 0; r < all.size(); ++r)
                ranks.push_back(
                    unpack(all[r], n, static_cast<int64_t>(all.size()), static_cast<int64_t>(r)));
        } else {
            ranks.push_back(std::move(mine));
        }
        // The failure with the lowest index, the same on every rank.
        const Outcome* failed = nullptr;
        for (const Outcome& o : ranks)
            if (o.failed && (!failed || o.index < failed->index)) failed = &o;
        if (failed) throw ScriptError("map: " + failed->message);
        // Ctrl-C reaches the workers with the caller (one process group): the items it stopped
        // failed as "interrupted", and the values left would look like a whole map. Raise, as
        // an interrupted run call does; the finished items are in the checkpoint for a rerun.
        if (talus::stopRequested()) {
            int64_t done = 0;
            for (const Outcome& o : ranks)
                for (const std::string& v : o.values) done += v.empty() ? 0 : 1;
            if (done < n)
                throw ScriptError("map: interrupted (Ctrl-C) with " + std::to_string(done) +
                                  " of " + std::to_string(n) + " items done" +
                                  (ckpt.on() ? "; they are kept in the checkpoint '" + ckpt.dir +
                                                   "': a rerun with it runs only the others"
                                             : ""));
        }

        lua_createtable(L, static_cast<int>(std::min<long long>(n, 1 << 24)), 0);
        lua_Integer i = 1;
        std::vector<std::pair<int64_t, std::string>> failures;
        int64_t from_checkpoint = 0, other_key = 0;
        for (const Outcome& o : ranks) {
            for (const std::string& v : o.values) {
                if (!v.empty()) {
                    decodeValue(L, v.data(), v.size());
                    lua_rawseti(L, -2, i);
                }
                ++i;
            }
            failures.insert(failures.end(), o.failures.begin(), o.failures.end());
            from_checkpoint += o.from_checkpoint;
            other_key += o.other_key;
        }
        std::sort(failures.begin(), failures.end());
        const bool speak = mpi::rank() == 0 && !nested;
        if (speak && (from_checkpoint > 0 || other_key > 0)) {
            std::fflush(stdout);
            std::fprintf(stderr, "talus: map: %lld of %lld items taken from the checkpoint '%s'",
                         static_cast<long long>(from_checkpoint), n, ckpt.dir.c_str());
            if (other_key > 0)
                std::fprintf(stderr, "; %lld stored by another run (another key) were run again",
                             static_cast<long long>(other_key));
            std::fprintf(stderr, "\n");
        }
        if (!failures.empty()) {
            // results.failed = {{index =, message =}, ...}, in index order.
            lua_createtable(L, static_cast<int>(failures.size()), 0);
            for (std::size_t k = 0; k < failures.size(); ++k) {
                lua_createtable(L, 0, 2);
                lua_pushinteger(L, static_cast<lua_Integer>(failures[k].first));
                lua_setfield(L, -2, "index");
                lua_pushlstring(L, failures[k].second.data(), failures[k].second.size());
                lua_setfield(L, -2, "message");
                lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
            }
            lua_setfield(L, -2, "failed");
            if (speak) {
                clearProgressLine();
                std::fflush(stdout);
                std::fprintf(stderr,
                             "talus: warning: map: %zu of %lld items failed (their results are "
                             "nil; results.failed lists index and message)%s; the first: %s\n",
                             failures.size(), n,
                             ckpt.on() ? "; a rerun with the same checkpoint runs only those" : "",
                             failures.front().second.c_str());
            }
        }
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

}  // namespace

extern const luaL_Reg kMapFunctions[] = {
    {"map", w_map},
    {"rank", w_rank},
    {"ranks", w_ranks},
    {nullptr, nullptr},
};

}  // namespace talus::lua
