// SPDX-License-Identifier: MIT
// The talus command: runs a Lua script with the `talus` module preloaded.
//
//   talus run [--traceback] script.lua [args...]   args arrive in `arg` (arg[0] = script) and `...`
//   talus --help | --version
//
// Exit status: 0 on success, 1 when the script fails (missing file, syntax error, runtime or
// engine error; the message, with the script line, goes to stderr), 2 for a usage error.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <lua.hpp>
#include <string>
#include <vector>

#include "lua_bindings.hpp"

#ifndef TALUS_VERSION
#error "TALUS_VERSION must be defined by the build (project version)"
#endif

namespace {

const char* const kUsage =
    "usage: talus run [--traceback] script.lua [args...]\n"
    "       talus --help | --version\n"
    "\n"
    "Runs a Lua 5.4 script with the Talus module preloaded as the global `talus`\n"
    "(require(\"talus\") also works). Arguments after the script are in the table `arg`\n"
    "(arg[0] is the script) and in `...`.\n"
    "\n"
    "options:\n"
    "  --traceback   on error, also print the Lua stack traceback\n"
    "\n"
    "Modules are searched in the script's directory, in TALUS_LUA_PATH (directories separated\n"
    "by ':'), and in the Talus scripts directory. Contact-model plugins are searched\n"
    "in TALUS_PLUGIN_PATH, then in the build and install plugin directories.\n"
    "Documentation: docs/getting-started.md and docs/lua-api.md.\n";

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
    prefix += std::string(TALUS_SOURCE_LUA_DIR) + "/lib/?.lua;" + TALUS_SOURCE_LUA_DIR + "/?.lua;" +
              TALUS_INSTALL_LUA_DIR + "/lib/?.lua;" + TALUS_INSTALL_LUA_DIR + "/?.lua;";
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
            std::fprintf(stderr, "talus: error: %s\n", talus::lua::errorText(L, -1).c_str());
            status = 1;
        }
    }
    std::fflush(stdout);
    lua_close(L);  // collects the models: history files are closed here
    return status;
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
    if (a[0] != "run") {
        std::fprintf(stderr, "talus: unknown command '%s'\n\n%s", a[0].c_str(), kUsage);
        return 2;
    }
    std::size_t i = 1;
    bool traceback = false;
    while (i < a.size() && a[i].size() > 1 && a[i][0] == '-' && a[i][1] == '-') {
        if (a[i] == "--traceback") {
            traceback = true;
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
    try {
        return runScript(script, args, traceback, argv[0]);
    } catch (const std::exception& e) {
        // Not expected: the bindings turn exceptions into Lua errors. Report rather than abort.
        std::fprintf(stderr, "talus: internal error: %s\n", e.what());
        return 1;
    }
}
