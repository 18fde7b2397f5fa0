// SPDX-License-Identifier: MIT
// The Lua API as LuaLS annotations (`---@class`, `---@field`, `---@param`, `---@return`), made
// from the registration tables of binding.hpp, for editors: `talus --lua-annotations FILE`.
#pragma once

#include <string>

namespace talus::lua {

/// The annotation file's text. Throws std::runtime_error naming the row when a method, field or
/// option has no line of documentation, a signature is malformed, or a type names a class that
/// is not registered.
std::string luaAnnotations();

/// Writes luaAnnotations() to `path`; throws std::runtime_error naming the file on failure.
void writeLuaAnnotations(const std::string& path);

}  // namespace talus::lua
