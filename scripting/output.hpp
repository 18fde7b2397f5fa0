// SPDX-License-Identifier: MIT
// What m:vtk (wrap_vtk.cpp) and m:picture (wrap_picture.cpp) share: the output userdata,
// per-ball Lua functions, the `fields` option, and the series state save/restore needs.
#pragma once

#include <string>
#include <vector>

#include "lua_bindings.hpp"
#include "vtk_writer.hpp"

namespace talus::lua {

inline constexpr const char* kOutputType = "talus.Output";

/// A per-ball value returned by a Lua function: a number, or a vector {x, y}.
struct Value {
    double x = 0.0, y = 0.0;
    bool vector = false;
};
/// Calls the function `ref` with the ball `id`; `what` names it in errors ("vtk: field 'e'").
Value callBallFunction(LuaModel& lm, int ref, BallId id, const std::string& what);

/// Reads `fields = {"force", "mass", damage = function(b) ... end}`: names from `known` (the
/// list part) and named functions (the map part, sorted by name; stored as refs).
void readFields(lua_State* L, LuaModel& lm, const Options& o, const char* what,
                const std::vector<std::string>& known, std::vector<std::string>& names,
                std::vector<std::pair<std::string, int>>& functions);

/// Adds `out` to the model's outputs, writes its first frame when `write_now`, installs its
/// cycle hook when out->every > 0, and pushes its userdata. Returns 1 (values pushed).
int registerOutput(lua_State* L, LuaModel& lm, std::unique_ptr<Output> out, bool write_now);

/// The open ParaView series of a model (save/restore stores them: docs/output.md).
std::vector<vtk::SeriesState> vtkSeriesStates(const LuaModel& lm);
/// Re-opens a saved series on `lm` (a restored model): its .pvd goes on from the saved frames,
/// every `state.every` steps, without writing a frame now; pushes the series userdata. Lua
/// function fields are not part of the state (the script passes them again with m:vtk{append}).
void resumeVtkSeries(lua_State* L, LuaModel& lm, const vtk::SeriesState& state);

}  // namespace talus::lua
