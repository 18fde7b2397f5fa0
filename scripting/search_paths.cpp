// SPDX-License-Identifier: MIT
// The talus command's search paths, relative to its executable (search_paths.hpp).
#include "search_paths.hpp"

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

}  // namespace

std::string executableDirectory(const char* argv0) {
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec && argv0 && std::string(argv0).find('/') != std::string::npos)
        exe = fs::canonical(argv0, ec);
    if (ec || exe.empty()) return {};
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
    const char* env = std::getenv("TALUS_LUA_PATH");
    if (!env) return dirs;
    const std::string text = env;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t end = text.find(':', start);
        const std::string dir = text.substr(start, end == std::string::npos ? end : end - start);
        if (!dir.empty()) dirs.push_back(dir);
        if (end == std::string::npos) break;
        start = end + 1;
    }
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
