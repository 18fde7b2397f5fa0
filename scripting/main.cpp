// SPDX-License-Identifier: MIT
// The talus command: runs a Lua script with the `talus` module preloaded.
//
//   talus run [--traceback] [--quiet] [--save-on-interrupt FILE] script.lua [args...]
//             args arrive in `arg` (arg[0] = script) and `...`
//   talus --lua-annotations FILE   the API as LuaLS annotations, for editors
//   talus --help | --version
//
// Exit status: 0 on success, 1 when the script fails (missing file, syntax error, runtime or
// engine error; the message, with the script line, goes to stderr), 2 for a usage error, 130
// when Ctrl-C stopped the run (docs/output.md, "Ctrl-C").
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <lua.hpp>
#include <memory>
#include <string>
#include <vector>

#include "lua_annotations.hpp"
#include "lua_bindings.hpp"
#include "mpi_world.hpp"
#include "progress.hpp"
#include "talus/run_control.hpp"

#ifndef TALUS_VERSION
#error "TALUS_VERSION must be defined by the build (project version)"
#endif

namespace {

const char* const kUsage =
    "usage: talus run [--traceback] [--quiet] [--save-on-interrupt FILE] [--threads N]\n"
    "                 script.lua [args...]\n"
    "       talus --lua-annotations FILE\n"
    "       talus --help | --version\n"
    "\n"
    "Runs a Lua 5.4 script with the Talus module preloaded as the global `talus`\n"
    "(require(\"talus\") also works). Arguments after the script are in the table `arg`\n"
    "(arg[0] is the script) and in `...`.\n"
    "\n"
    "options:\n"
    "  --traceback   on error, also print the Lua stack traceback\n"
    "  --quiet       no progress line (on a terminal: one line rewritten in place; else\n"
    "                a line of its own every minute of a long run, TALUS_PROGRESS_INTERVAL)\n"
    "  --save-on-interrupt FILE\n"
    "                on Ctrl-C, save the model whose run stopped to FILE (as m:save does)\n"
    "  --threads N   threads of every model's force loop (default 1, or TALUS_THREADS);\n"
    "                results are the same for any N; m:threads(n) sets one model's\n"
    "\n"
    "Ctrl-C stops a running cycle/solve at the end of its step (histories are flushed) and\n"
    "ends the script with exit status 130; a second Ctrl-C kills at once.\n"
    "\n"
    "Modules are searched in the script's directory, in TALUS_LUA_PATH (directories separated\n"
    "by ':'), and in the Talus scripts directory. Contact-model plugins are searched\n"
    "in TALUS_PLUGIN_PATH, then in the build and install plugin directories.\n"
    "--lua-annotations FILE writes the API as LuaLS annotations for an editor (the installed\n"
    "copy is share/talus/lua-annotations/talus.lua).\n"
    "Documentation: docs/getting-started.md and docs/lua-api.md.\n";

bool g_stderr_tty = false;

/// SIGINT: the first one asks the running cycle/solve to stop at the end of its step
/// (run_control.hpp); the second kills as SIGINT does by default (a script stuck in a Lua loop
/// that never cycles). Only async-signal-safe calls here: an atomic store, write, signal, raise.
extern "C" void onInterrupt(int) {
    if (talus::stopRequested()) {
        std::signal(SIGINT, SIG_DFL);
        std::raise(SIGINT);
        return;
    }
    talus::requestStop();
    static const char tty_msg[] =
        "\r\033[Ktalus: Ctrl-C: stopping at the end of the current step (Ctrl-C again kills)\n";
    static const char msg[] =
        "talus: Ctrl-C: stopping at the end of the current step (Ctrl-C again kills)\n";
    const char* m = g_stderr_tty ? tty_msg : msg;
    const std::size_t n = g_stderr_tty ? sizeof tty_msg - 1 : sizeof msg - 1;
    [[maybe_unused]] const ssize_t w = ::write(STDERR_FILENO, m, n);
}

/// Forwards Ctrl-C to the run (above), unless SIGINT is ignored (a job started in the
/// background of a non-interactive shell): then it stays ignored, as the shell asked.
void installInterruptHandler() {
    struct sigaction old {};
    if (::sigaction(SIGINT, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) return;
    struct sigaction sa {};
    sa.sa_handler = onInterrupt;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;  // a read/write in progress goes on; the run stops at the step end
    ::sigaction(SIGINT, &sa, nullptr);
}

/// --save-on-interrupt FILE: when Ctrl-C stops a run call, the model it was cycling is saved to
/// FILE as m:save would (histories flushed, temporary file and rename), at the end of the step
/// where it stopped, before the error goes on to the script. Each model once: a later run call
/// that Ctrl-C refuses (beforeStart) finds it saved. A second model stopped in the same process
/// (an on_cycle callback that cycles another model: the inner one first) goes to FILE.2,
/// FILE.3, ... A nested run
/// call of the same model leaves the save to its outermost call, and a talus.map worker (a
/// fork: another pid) saves nothing, so that workers do not overwrite the caller's file.
void installSaveOnInterrupt(const std::string& file) {
    const pid_t owner = ::getpid();
    auto saved = std::make_shared<std::vector<const talus::lua::LuaModel*>>();
    talus::lua::setInterruptHook([file, owner, saved](lua_State*, talus::lua::LuaModel& lm,
                                                      const talus::Interrupted&) {
        if (::getpid() != owner || lm.running > 0 || !lm.model) return;
        if (std::find(saved->begin(), saved->end(), &lm) != saved->end()) return;
        const std::string path =
            saved->empty() ? file : file + "." + std::to_string(saved->size() + 1);
        try {
            talus::lua::saveLuaModel(lm, path);
            saved->push_back(&lm);
            talus::lua::clearProgressLine();
            std::fprintf(stderr, "talus: saved the model at step %lld (t = %.9g s) to %s\n",
                         static_cast<long long>(lm.model->step()), lm.model->time(), path.c_str());
        } catch (const std::exception& e) {
            // The interrupt goes on (exit 130); the failed save is said, not hidden.
            std::fprintf(stderr, "talus: --save-on-interrupt: %s\n", e.what());
        }
    });
}

/// print() that first erases the progress line, so the script's output never lands on it.
int printAfterProgress(lua_State* L) {
    talus::lua::clearProgressLine();
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, 0);
    return 0;
}

void wrapPrint(lua_State* L) {
    lua_getglobal(L, "print");
    lua_pushcclosure(L, printAfterProgress, 1);
    lua_setglobal(L, "print");
}

/// Message handler for --traceback: the error message followed by the Lua traceback.
int tracebackHandler(lua_State* L) {
    const char* msg = lua_tostring(L, 1);
    if (!msg) msg = "(error object is not a string)";
    luaL_traceback(L, L, msg, 1);
    return 1;
}

std::string directoryOf(const std::string& path) {
    const auto slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    if (slash == 0) return "/";
    return path.substr(0, slash);
}

/// Puts the script's directory, TALUS_LUA_PATH and the Talus script directories (scripts/lib and
/// scripts/, source tree then install) in front of package.path, so `require` finds modules
/// shipped in scripts/lib from any directory.
void setPackagePath(lua_State* L, const std::string& script) {
    std::string prefix = directoryOf(script) + "/?.lua;";
    if (const char* env = std::getenv("TALUS_LUA_PATH")) {
        std::string dirs = env;
        std::size_t start = 0;
        while (start <= dirs.size()) {
            const std::size_t end = dirs.find(':', start);
            const std::string dir =
                dirs.substr(start, end == std::string::npos ? end : end - start);
            if (!dir.empty()) prefix += dir + "/?.lua;";
            if (end == std::string::npos) break;
            start = end + 1;
        }
    }
    // scripts/lib holds the shipped library modules (rockfall, ...); scripts/ itself stays for
    // older scripts that keep modules next to the examples.
    // A module of several files is a folder with an init.lua (require("material")).
    prefix += std::string(TALUS_SOURCE_LUA_DIR) + "/lib/?.lua;" + TALUS_SOURCE_LUA_DIR +
              "/lib/?/init.lua;" + TALUS_SOURCE_LUA_DIR + "/?.lua;" + TALUS_INSTALL_LUA_DIR +
              "/lib/?.lua;" + TALUS_INSTALL_LUA_DIR + "/lib/?/init.lua;" + TALUS_INSTALL_LUA_DIR +
              "/?.lua;";
    lua_getglobal(L, "package");
    lua_getfield(L, -1, "path");
    const char* old = lua_tostring(L, -1);
    const std::string path = prefix + (old ? old : "");
    lua_pop(L, 1);
    lua_pushstring(L, path.c_str());
    lua_setfield(L, -2, "path");
    lua_pop(L, 1);
}

/// Registers `talus` in package.preload and loads it into the global `talus`.
void preloadTalus(lua_State* L) {
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_PRELOAD_TABLE);
    lua_pushcfunction(L, luaopen_talus);
    lua_setfield(L, -2, "talus");
    lua_pop(L, 1);
    luaL_requiref(L, "talus", luaopen_talus, 1);
    lua_pop(L, 1);
}

int runScript(const std::string& script, const std::vector<std::string>& args, bool traceback,
              const char* argv0) {
    lua_State* L = luaL_newstate();
    if (!L) {
        std::fprintf(stderr, "talus: cannot create a Lua state (out of memory)\n");
        return 1;
    }
    luaL_openlibs(L);
    wrapPrint(L);
    preloadTalus(L);
    setPackagePath(L, script);

    lua_createtable(L, static_cast<int>(args.size()), 3);
    lua_pushstring(L, argv0);
    lua_rawseti(L, -2, -2);
    lua_pushliteral(L, "run");
    lua_rawseti(L, -2, -1);
    lua_pushstring(L, script.c_str());
    lua_rawseti(L, -2, 0);
    for (std::size_t i = 0; i < args.size(); ++i) {
        lua_pushstring(L, args[i].c_str());
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_setglobal(L, "arg");

    int status = 0;
    if (traceback) lua_pushcfunction(L, tracebackHandler);
    const int handler = traceback ? lua_gettop(L) : 0;
    if (luaL_loadfile(L, script.c_str()) != LUA_OK) {
        // "cannot open x.lua: No such file or directory", or "x.lua:3: syntax error near ..."
        std::fprintf(stderr, "talus: error: %s\n", talus::lua::errorText(L, -1).c_str());
        status = 1;
    } else {
        for (const std::string& a : args) lua_pushstring(L, a.c_str());
        if (lua_pcall(L, static_cast<int>(args.size()), 0, handler) != LUA_OK) {
            std::fflush(stdout);
            talus::lua::clearProgressLine();
            // After Ctrl-C the error is the run's "interrupted (Ctrl-C) at step N" (or one
            // raised by a script that caught it): say so, and exit as SIGINT would (130).
            const bool interrupted = talus::stopRequested();
            std::fprintf(stderr, "talus: %s: %s\n", interrupted ? "interrupted" : "error",
                         talus::lua::errorText(L, -1).c_str());
            status = interrupted ? 130 : 1;
        } else if (talus::stopRequested()) {
            // The script handled the stop itself (m:solve returned "interrupted") and ended.
            std::fflush(stdout);
            std::fprintf(stderr, "talus: interrupted (Ctrl-C); the script ended normally\n");
            status = 130;
        }
    }
    std::fflush(stdout);
    lua_close(L);  // collects the models: history files are closed here
    return status;
}

/// talus --lua-annotations FILE: the API as LuaLS annotations (lua_annotations.hpp).
int writeAnnotations(const std::vector<std::string>& a) {
    if (a.size() != 2 || a[1].empty()) {
        std::fprintf(stderr, "talus: --lua-annotations needs a file name\n\n%s", kUsage);
        return 2;
    }
    try {
        talus::lua::writeLuaAnnotations(a[1]);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "talus: error: %s\n", e.what());
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const std::vector<std::string> a(argv + 1, argv + argc);
    if (a.empty()) {
        std::fputs(kUsage, stderr);
        return 2;
    }
    if (a[0] == "--help" || a[0] == "-h" || a[0] == "help") {
        std::fputs(kUsage, stdout);
        return 0;
    }
    if (a[0] == "--version" || a[0] == "-v" || a[0] == "version") {
        std::printf("talus %s (%s)\n", TALUS_VERSION, LUA_RELEASE);
        return 0;
    }
    if (a[0] == "--lua-annotations") return writeAnnotations(a);
    if (a[0] != "run") {
        std::fprintf(stderr, "talus: unknown command '%s'\n\n%s", a[0].c_str(), kUsage);
        return 2;
    }
    std::size_t i = 1;
    bool traceback = false;
    bool quiet = false;
    std::string save_on_interrupt;
    while (i < a.size() && a[i].size() > 1 && a[i][0] == '-' && a[i][1] == '-') {
        if (a[i] == "--traceback") {
            traceback = true;
        } else if (a[i] == "--quiet") {
            quiet = true;
        } else if (a[i] == "--threads") {
            // Every model's default (Model::threads) through TALUS_THREADS.
            char* end = nullptr;
            const long n = i + 1 < a.size() ? std::strtol(a[i + 1].c_str(), &end, 10) : 0;
            if (i + 1 >= a.size() || *end != '\0' || n < 1 || n > 1024) {
                std::fprintf(stderr, "talus: --threads needs a thread count from 1 to 1024\n\n%s",
                             kUsage);
                return 2;
            }
            ::setenv("TALUS_THREADS", a[++i].c_str(), 1);
        } else if (a[i] == "--save-on-interrupt") {
            if (i + 1 >= a.size() || a[i + 1].empty()) {
                std::fprintf(stderr, "talus: --save-on-interrupt needs a file name\n\n%s", kUsage);
                return 2;
            }
            save_on_interrupt = a[++i];
        } else if (a[i] == "--") {
            ++i;
            break;
        } else {
            std::fprintf(stderr, "talus: unknown option '%s'\n\n%s", a[i].c_str(), kUsage);
            return 2;
        }
        ++i;
    }
    if (i >= a.size()) {
        std::fprintf(stderr, "talus: run: no script given\n\n%s", kUsage);
        return 2;
    }
    const std::string script = a[i];
    const std::vector<std::string> args(a.begin() + static_cast<std::ptrdiff_t>(i + 1), a.end());
    // Under mpirun only (talus.rank/ranks/map); a plain run does not touch MPI.
    talus::mpi::start();
    g_stderr_tty = ::isatty(STDERR_FILENO) == 1;
    // Progress on rank 0 only: under mpirun every rank runs the same script, and one log line a
    // minute per rank would bury the job's output.
    talus::lua::setProgressStyle(quiet || talus::mpi::rank() != 0 ? talus::lua::ProgressStyle::Off
                                 : g_stderr_tty ? talus::lua::ProgressStyle::Terminal
                                                : talus::lua::ProgressStyle::Log);
    installInterruptHandler();
    if (!save_on_interrupt.empty()) installSaveOnInterrupt(save_on_interrupt);
    int status = 1;
    try {
        status = runScript(script, args, traceback, argv[0]);
    } catch (const std::exception& e) {
        // Not expected: the bindings turn exceptions into Lua errors. Report rather than abort.
        std::fprintf(stderr, "talus: internal error: %s\n", e.what());
    }
    std::fflush(nullptr);
    talus::mpi::finish(status != 0);
    return status;
}
