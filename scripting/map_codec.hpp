// SPDX-License-Identifier: MIT
//
// The byte format in which talus.map carries one Lua value from the process that computed it
// (a forked worker, another MPI rank, or the caller itself) back to the caller.
//
// Only plain data crosses: nil, booleans, integers, floats, strings and tables of these.
// Numbers keep their subtype and their exact bits (-0.0, inf, nan, subnormals); strings may
// contain zero bytes. A table's keys are written in a canonical order (integers ascending, then
// floats ascending, then false, true, then strings bytewise), so that the bytes of a value do
// not depend on the process's string-hash seed and a decoded table is built the same way
// whichever process computed it. Metatables are not carried; a table reached twice (not a
// cycle) arrives as two copies. Byte order is the machine's own: every process of a run is the
// same binary on machines of one architecture.
#pragma once

#include <cstddef>
#include <cstdint>
#include <lua.hpp>
#include <stdexcept>
#include <string>

namespace talus::lua {

/// A value that cannot cross (a function, userdata, thread, a cycle, a table key that is not
/// plain data). what() says what and where: "a function at result.shape[2]".
class EncodeError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Appends the encoding of the value at `index` to `out`. Reads tables raw (no metamethods).
/// Throws EncodeError for a value that cannot cross.
void encodeValue(lua_State* L, int index, std::string& out);

/// Decodes one value from [data, data + size) and pushes it; throws std::runtime_error if the
/// bytes are not exactly one well-formed value.
void decodeValue(lua_State* L, const char* data, std::size_t size);

/// Whether [data, data + size) is exactly one well-formed value (decodeValue would take it),
/// found without building it.
bool wellFormed(const char* data, std::size_t size);

/// FNV-1a 64 (Fowler, Noll and Vo) of [data, data + size): the checksum of a checkpoint item.
/// Each step of it maps the state one to one, so any change of one byte changes the sum.
uint64_t checksum64(const char* data, std::size_t size);

}  // namespace talus::lua
