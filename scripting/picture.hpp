// SPDX-License-Identifier: MIT
//
// Quick-look pictures (docs/output.md, "Pictures"): balls, walls, force chains and cracks drawn
// with cairo to PNG, SVG or PDF, with a scale bar and a colour legend. Lua-free: the binding
// (wrap_picture.cpp) computes the per-ball colour values and passes them here.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "crack.hpp"
#include "talus/model.hpp"

namespace talus::picture {

/// True when talus was built with cairo (else draw() throws "talus was built without cairo").
bool available();

enum class ColorBy { Group, Clump, Value, None };

struct Settings {
    int width = 1000, height = 0;  ///< pixels (PNG) or points (SVG, PDF); height 0: from view
    bool view_set = false;
    std::array<double, 4> view{0, 0, 0, 0};  ///< xmin, ymin, xmax, ymax [m]
    ColorBy color = ColorBy::Group;
    std::vector<std::string> groups;  ///< group order for ColorBy::Group (empty: the model's)
    std::string value_name;           ///< legend title of ColorBy::Value ("speed [m/s]")
    bool range_set = false;
    double range_min = 0, range_max = 1;
    bool force_chains = false;  ///< contacts = "force"
    bool cracks = false;        ///< the cracks drawn (crack.hpp)
    double chain_width = 0;     ///< line width of the largest force [m]; 0: 0.6 mean radius
    bool legend = true, scale_bar = true;
    std::string title;
};

/// Where the model's point (x, y) lands in the picture (pixels/points from the top left).
struct Transform {
    double scale = 1, x0 = 0, y0 = 0;  // px = x0 + scale * x, py = y0 - scale * y
    std::array<double, 2> toPixel(double x, double y) const {
        return {x0 + scale * x, y0 - scale * y};
    }
};

/// A path drawn over the model (a tracked body's centre, or points given): a polyline [m].
using Path = std::vector<Vec2>;

/// The colour of path k (ColorBrewer's Dark2, cycled), 0xRRGGBB.
unsigned pathColour(std::size_t k);

/// Draws the model into `file` (format by its extension: .png, .svg, .pdf). `values`: one per
/// particle (free balls and pebbles) in vtk::particleIds() order for ColorBy::Value (NaN: drawn
/// grey). Returns the transform used. Throws talus::Error naming the file on failure.
/// `cracks`: drawn when s.cracks, as segments across the broken bonds, tension red (#E41A1C),
/// shear blue (#377EB8). `paths`: polylines over the balls and walls, 3 px wide, path k in
/// pathColour(k), a dot at its first point.
Transform draw(const Model& m, const Settings& s, const std::vector<double>& values,
               const std::string& file, const std::vector<Crack>& cracks = {},
               const std::vector<Path>& paths = {});

/// The numbered name of frame `n` of a series: "out/frame.png" -> "out/frame_000012.png".
std::string frameName(const std::string& file, int64_t n);

}  // namespace talus::picture
