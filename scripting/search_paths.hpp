// SPDX-License-Identifier: MIT
//
// Where the talus command finds the plugins and Lua modules shipped with it: relative to its own
// executable, so that an installed tree can be moved (or packaged under another prefix) and the
// build tree works as it is. The user's directories come first:
//
//   plugins:     TALUS_PLUGIN_PATH, then <exe dir>/plugins (build tree) and
//                <exe dir>/../lib/talus/plugins (install)
//   Lua modules: the script's directory, TALUS_LUA_PATH (?.lua and ?/init.lua), then <exe
//   dir>/../scripts (the build
//                tree's source scripts/) and <exe dir>/../share/talus/scripts (install), each as
//                lib/?.lua, lib/?/init.lua and ?.lua
//
// (The relative paths are those of the build's layout, GNUInstallDirs; see
// scripting/CMakeLists.txt.) Only the shipped directories that exist are searched; when none
// does, all are kept so that an error message says where Talus looked.
#pragma once

#include <string>
#include <vector>

namespace talus::lua {

/// The directory of the running executable (/proc/self/exe; without /proc, argv0 as a path or
/// looked up on PATH), or empty when it cannot be told.
std::string executableDirectory(const char* argv0);

/// The shipped plugin directories, for PluginRegistry::appendSearchDirectory.
std::vector<std::string> shippedPluginDirectories(const std::string& exe_dir);

/// The shipped Lua script directories (each holds lib/ with the library modules).
std::vector<std::string> shippedLuaDirectories(const std::string& exe_dir);

/// TALUS_LUA_PATH's directories, in order (empty entries skipped).
std::vector<std::string> luaPathFromEnvironment();

/// The package.path entries for a script in `script_dir`: the script's directory,
/// TALUS_LUA_PATH, then the shipped directories (module files and folders with an init.lua).
std::string packagePathPrefix(const std::string& script_dir, const std::string& exe_dir);

}  // namespace talus::lua
