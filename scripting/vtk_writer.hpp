// SPDX-License-Identifier: MIT
//
// ParaView output (docs/output.md, "ParaView output"): VTK XML files written directly, with the
// data in one raw binary appended block per file (little- or big-endian as the host, UInt64
// block headers). Debian's VTK 9 C++ library would pull in ~40 packages for what is a few
// hundred lines of file format; the files are checked by reading them back with VTK's own
// readers (python3-vtk9, tests/scripting/output/vtk_readback.py).
//
// One frame = three PolyData files (balls as vertices with per-point arrays, walls as
// polylines, contacts as two-point lines with per-cell arrays; a fourth of the cracks, segments
// across the broken bonds, when asked) bound by a multiblock file
// NAME_NNNNNN.vtm, and NAME.pvd lists the frames with their simulated times. Three parts rather
// than one .vtp: the three kinds carry different arrays, and VTK arrays span every point or
// cell of a dataset, so one file would pad every ball array onto wall and contact points.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "crack.hpp"
#include "talus/model.hpp"

namespace talus::vtk {

/// Every particle drawn or written: the free balls (Model::ballIds(), which skips pebbles), then
/// the pebbles of each clump in clump order. A pebble's state is the one the engine keeps in its
/// ball slot (position, rigid-body velocity, the clump's spin, the clump's groups).
std::vector<BallId> particleIds(const Model& m);

/// A per-ball array computed by the caller (e.g. a Lua function), in the order of
/// particleIds(): 1 component (scalar) or 3 (a vector; z = 0).
struct BallArray {
    std::string name;
    int components = 1;
    std::vector<double> values;  // components * ball count
};

/// Optional built-in ball arrays, by name (docs/output.md lists them).
const std::vector<std::string>& optionalBallFields();

/// One frame of the series in the .pvd.
struct FrameEntry {
    int64_t frame = 0;  ///< number in the file name
    int64_t step = 0;
    double time = 0.0;
    std::string file;  ///< the .vtm, relative to the series directory
};

/// What a series needs to go on after a restore (save/restore stores it; `append = true`
/// rebuilds it from the .pvd on disk).
struct SeriesState {
    std::string dir;                  ///< directory of the files
    std::string name;                 ///< NAME.pvd, NAME_NNNNNN.vtm, ...
    int64_t every = 0;                ///< steps between frames (0: only on request)
    std::vector<std::string> fields;  ///< optional built-in ball fields
    bool walls = true, contacts = true;
    bool cracks = false;  ///< the cracks part (the bonds broken so far)
    int64_t next_frame = 0;
    std::vector<FrameEntry> frames;
};

class Series {
public:
    /// Creates `dir` (one level) if needed. A fresh series (state.frames empty) starts at frame 0.
    explicit Series(SeriesState state);

    /// Writes one frame of the model now and rewrites the .pvd (through a temporary file and a
    /// rename, so the collection on disk is always whole). `extra`: caller-computed ball arrays;
    /// `cracks`: the cracks part, when the series has one. Throws talus::Error naming the file
    /// on a write failure.
    void writeFrame(const Model& m, const std::vector<BallArray>& extra,
                    const std::vector<Crack>& cracks = {});

    const SeriesState& state() const { return m_state; }
    std::string pvdPath() const;

    /// Reads the frames of an existing NAME.pvd written by Series (append = true); the frames
    /// later than `time` are dropped (a restored run rewrites them). Missing file: none.
    static std::vector<FrameEntry> readPvd(const std::string& dir, const std::string& name,
                                           double time);

private:
    void writePvd() const;
    SeriesState m_state;
};

}  // namespace talus::vtk
