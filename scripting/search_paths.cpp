// SPDX-License-Identifier: MIT
// The talus command's search paths, relative to its executable (search_paths.hpp).
#include "search_paths.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

// Relative to the directory of the talus executable, from scripting/CMakeLists.txt.
#ifndef TALUS_BUILD_PLUGIN_DIR_FROM_BIN
#error "TALUS_BUILD_PLUGIN_DIR_FROM_BIN must be defined by the build"
#endif
#ifndef TALUS_INSTALL_PLUGIN_DIR_FROM_BIN
#error "TALUS_INSTALL_PLUGIN_DIR_FROM_BIN must be defined by the build"
#endif
#ifndef TALUS_BUILD_LUA_DIR_FROM_BIN
#error "TALUS_BUILD_LUA_DIR_FROM_BIN must be defined by the build"
#endif
#ifndef TALUS_INSTALL_LUA_DIR_FROM_BIN
#error "TALUS_INSTALL_LUA_DIR_FROM_BIN must be defined by the build"
#endif

namespace fs = std::filesystem;

namespace talus::lua {

namespace {

/// `exe_dir`/`relative`, without `..` where the directory exists; the directories that exist,
/// or all of them when none does (then an error message still names where Talus looked).
std::vector<std::string> besideExecutable(const std::string& exe_dir,
                                          std::initializer_list<const char*> relative) {
    std::vector<std::string> existing, all;
    if (exe_dir.empty()) return all;
    for (const char* rel : relative) {
        std::error_code ec;
        const fs::path p = fs::weakly_canonical(fs::path(exe_dir) / rel, ec);
        const std::string dir =
            ec ? (fs::path(exe_dir) / rel).lexically_normal().string() : p.string();
        all.push_back(dir);
        if (fs::is_directory(p, ec)) existing.push_back(dir);
    }
    return existing.empty() ? all : existing;
}

/// "a:b::c" -> {"a", "b", "", "c"} (PATH-style lists; an empty entry is kept).
std::vector<std::string> splitColons(const std::string& text) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (std::size_t end; (end = text.find(':', start)) != std::string::npos; start = end + 1)
        parts.push_back(text.substr(start, end - start));
    parts.push_back(text.substr(start));
    return parts;
}

/// Without /proc (a bare chroot): argv0 itself when it names a path, else the first executable
/// of that name on PATH (an empty entry is the current directory), as the shell found it.
fs::path executableFromArgv0(const std::string& argv0) {
    std::error_code ec;
    if (argv0.find('/') != std::string::npos) {
        const fs::path exe = fs::canonical(argv0, ec);
        return ec ? fs::path() : exe;
    }
    const char* path = std::getenv("PATH");
    if (argv0.empty() || !path) return {};
    for (const std::string& dir : splitColons(path)) {
        const fs::path candidate = fs::path(dir.empty() ? "." : dir) / argv0;
        if (fs::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0) {
            const fs::path exe = fs::canonical(candidate, ec);
            if (!ec) return exe;
        }
    }
    return {};
}

}  // namespace

std::string executableDirectory(const char* argv0) {
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec || exe.empty()) exe = executableFromArgv0(argv0 ? argv0 : "");
    if (exe.empty()) return {};
    return exe.parent_path().string();
}

std::vector<std::string> shippedPluginDirectories(const std::string& exe_dir) {
    // The build tree's first: a build never picks up an older install's plugins.
    return besideExecutable(exe_dir,
                            {TALUS_BUILD_PLUGIN_DIR_FROM_BIN, TALUS_INSTALL_PLUGIN_DIR_FROM_BIN});
}

std::vector<std::string> shippedLuaDirectories(const std::string& exe_dir) {
    return besideExecutable(exe_dir,
                            {TALUS_BUILD_LUA_DIR_FROM_BIN, TALUS_INSTALL_LUA_DIR_FROM_BIN});
}

std::vector<std::string> luaPathFromEnvironment() {
    std::vector<std::string> dirs;
    if (const char* env = std::getenv("TALUS_LUA_PATH"))
        for (const std::string& dir : splitColons(env))
            if (!dir.empty()) dirs.push_back(dir);
    return dirs;
}

std::string packagePathPrefix(const std::string& script_dir, const std::string& exe_dir) {
    std::string prefix = script_dir + "/?.lua;";
    for (const std::string& dir : luaPathFromEnvironment())
        prefix += dir + "/?.lua;" + dir + "/?/init.lua;";
    // lib/ holds the shipped library modules (rockfall, ...); a module of several files is a
    // folder with an init.lua (require("material")). The scripts directory itself stays on the
    // path for older scripts that keep modules next to the examples.
    for (const std::string& dir : shippedLuaDirectories(exe_dir))
        prefix += dir + "/lib/?.lua;" + dir + "/lib/?/init.lua;" + dir + "/?.lua;";
    return prefix;
}

}  // namespace talus::lua
