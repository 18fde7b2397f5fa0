// SPDX-License-Identifier: MIT
// talus.map's items run in place or by forked workers (map_workers.hpp).
#include "map_workers.hpp"

#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "lua_runtime.hpp"
#include "map_codec.hpp"
#include "mpi_world.hpp"
#include "talus/model.hpp"

namespace talus::lua {

void block(int64_t count, int64_t parts, int64_t w, int64_t& first, int64_t& size) {
    const int64_t base = count / parts, extra = count % parts;
    first = w * base + std::min(w, extra);
    size = base + (w < extra ? 1 : 0);
}

std::string itemName(int64_t i) { return "fn(" + std::to_string(i) + ")"; }

namespace {

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

}  // namespace

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

namespace {

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

}  // namespace

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

namespace {

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

}  // namespace

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

}  // namespace talus::lua
