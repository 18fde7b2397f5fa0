// SPDX-License-Identifier: MIT
// What m:vtk (wrap_vtk.cpp) and m:picture (wrap_picture.cpp) share: the output userdata,
// per-ball Lua functions, the `fields` option, and the series state save/restore needs.
#pragma once

#include <string>
#include <vector>

#include "lua_bindings.hpp"
#include "picture.hpp"
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

/// An open ParaView series as save/restore stores it (docs/save-format.md, section HOST).
struct SavedVtkSeries {
    vtk::SeriesState state;
    /// Names of its Lua function fields: a save cannot hold them, so such a series is not
    /// continued by a restore (the script goes on with it through m:vtk{append = true}).
    std::vector<std::string> functions;
};
/// The open ParaView series of a model, in the order they were made.
std::vector<SavedVtkSeries> vtkSeriesStates(const LuaModel& lm);
/// Re-opens a saved series on `lm` (a restored model): its .pvd goes on from the saved frames
/// (the next frame numbered `state.next_frame`), every `state.every` steps, without writing a
/// frame now; pushes the series userdata.
void resumeVtkSeries(lua_State* L, LuaModel& lm, const vtk::SeriesState& state);

/// An open picture series (m:picture{every =}) as save/restore stores it.
struct SavedPictureSeries {
    std::string file;  ///< as given: frames are file_NNNNNN.ext
    int64_t every = 0;
    bool speed = false;     ///< color = "speed"
    bool function = false;  ///< color = a Lua function: not saved, the series is not continued
    picture::Settings settings;
    std::vector<std::string> files;  ///< the frames written so far (the next is numbered after)
};
/// The open picture series of a model (pictures with `every`), in the order they were made.
std::vector<SavedPictureSeries> pictureSeriesStates(const LuaModel& lm);
/// Re-opens a saved picture series on `lm` (a restored model), without drawing now; pushes the
/// output userdata (wrap_picture.cpp).
void resumePictureSeries(lua_State* L, LuaModel& lm, const SavedPictureSeries& state);

}  // namespace talus::lua
