// SPDX-License-Identifier: MIT
// Pictures with cairo (picture.hpp). Layout: the particles fill the picture less a band at the
// bottom (legend and scale bar); the view keeps its aspect ratio and is centred.
#include "picture.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <utility>

#include "talus/errors.hpp"
#include "vtk_writer.hpp"

#ifdef TALUS_HAVE_CAIRO
#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#endif

namespace talus::picture {

std::string frameName(const std::string& file, int64_t n) {
    const auto slash = file.find_last_of('/');
    const auto dot = file.find_last_of('.');
    const bool has_ext = dot != std::string::npos && (slash == std::string::npos || dot > slash);
    char num[32];
    std::snprintf(num, sizeof num, "_%06lld", static_cast<long long>(n));
    return has_ext ? file.substr(0, dot) + num + file.substr(dot) : file + num;
}

#ifndef TALUS_HAVE_CAIRO

bool available() { return false; }

Transform draw(const Model&, const Settings&, const std::vector<double>&, const std::string&,
               const std::vector<Crack>&) {
    throw Error(
        "picture: talus was built without cairo (apt-get install libcairo2-dev, then rebuild: "
        "scripts/build.sh)");
}

#else

bool available() { return true; }

namespace {

struct Rgb {
    double r, g, b;
};

Rgb hex(unsigned v) {
    return {((v >> 16) & 255) / 255.0, ((v >> 8) & 255) / 255.0, (v & 255) / 255.0};
}

// Categorical colours (groups, clumps): the ten of Tableau 10, distinct for most readers.
const unsigned kCategorical[] = {0x4E79A7, 0xF28E2B, 0xE15759, 0x76B7B2, 0x59A14F,
                                 0xEDC948, 0xB07AA1, 0xFF9DA7, 0x9C755F, 0xBAB0AC};
const unsigned kNoCategory = 0xD9D9D9;  // a ball in none of the groups, a free ball
const unsigned kWall = 0x303030;
// Cracks: tension red, shear blue (ColorBrewer's Set1), not black, which the force chains use;
// each drawn on a white rim, so that it stands out on a ball of its own colour.
const unsigned kCrackTension = 0xE41A1C;
const unsigned kCrackShear = 0x377EB8;

// Viridis (perceptually uniform, readable in grey) sampled at nine points; linear in between.
const unsigned kViridis[] = {0x440154, 0x472D7B, 0x3B528B, 0x2C728E, 0x21918C,
                             0x28AE80, 0x5EC962, 0xADDC30, 0xFDE725};

Rgb viridis(double t) {
    if (!std::isfinite(t)) return hex(kNoCategory);
    t = std::clamp(t, 0.0, 1.0) * 8.0;
    const int i = std::min(7, static_cast<int>(t));
    const double f = t - i;
    const Rgb a = hex(kViridis[i]), b = hex(kViridis[i + 1]);
    return {a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b)};
}

void setColor(cairo_t* cr, const Rgb& c) { cairo_set_source_rgb(cr, c.r, c.g, c.b); }

/// 1, 2 or 5 times a power of ten, close to (at most) `target`.
double niceLength(double target) {
    const double p = std::pow(10.0, std::floor(std::log10(target)));
    for (double f : {5.0, 2.0, 1.0})
        if (f * p <= target) return f * p;
    return p;
}

std::string lengthText(double v) {
    char buf[32];
    if (v >= 1000)
        std::snprintf(buf, sizeof buf, "%g km", v / 1000);
    else if (v >= 1)
        std::snprintf(buf, sizeof buf, "%g m", v);
    else if (v >= 0.01)
        std::snprintf(buf, sizeof buf, "%g cm", v * 100);
    else
        std::snprintf(buf, sizeof buf, "%g mm", v * 1000);
    return buf;
}

std::string numberText(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

enum class Format { Png, Svg, Pdf };

Format formatOf(const std::string& file) {
    const auto dot = file.find_last_of('.');
    std::string ext = dot == std::string::npos ? "" : file.substr(dot + 1);
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == "png") return Format::Png;
    if (ext == "svg") return Format::Svg;
    if (ext == "pdf") return Format::Pdf;
    throw Error("picture: '" + file + "': the file name must end in .png, .svg or .pdf");
}

/// The view: given, or everything with a 5% margin.
std::array<double, 4> viewOf(const Model& m, const Settings& s, const std::vector<BallId>& ids,
                             const std::vector<WallId>& walls) {
    std::array<double, 4> v = s.view;
    if (!s.view_set) {
        const double inf = std::numeric_limits<double>::infinity();
        v = {inf, inf, -inf, -inf};
        const auto grow = [&](const Vec2& p, double r) {
            v[0] = std::min(v[0], p.x() - r), v[1] = std::min(v[1], p.y() - r);
            v[2] = std::max(v[2], p.x() + r), v[3] = std::max(v[3], p.y() + r);
        };
        for (const BallId b : ids) grow(m.ballPos(b), m.ballRadius(b));
        for (const WallId w : walls)
            for (const Vec2& p : m.wallPoints(w)) grow(p, 0.0);
        if (!(v[0] < inf)) v = {-1, -1, 1, 1};  // an empty model
        double wv = v[2] - v[0], hv = v[3] - v[1];
        const double pad = 0.05 * std::max({wv, hv, 1e-9});
        v = {v[0] - pad, v[1] - pad, v[2] + pad, v[3] + pad};
    }
    if (!(v[2] - v[0] > 0) || !(v[3] - v[1] > 0))
        throw Error("picture: the view must have xmax > xmin and ymax > ymin");
    return v;
}

/// Where things go: the picture's size, the title at the top, the plot, the bottom band
/// (legend and scale bar), and the transform of the view into the plot (centred).
struct Layout {
    int W = 0, H = 0;
    double band = 0, title_h = 0, plot_h = 0;
    Transform tr;
};

Layout layoutOf(const Settings& s, const std::array<double, 4>& v) {
    const double vw = v[2] - v[0], vh = v[3] - v[1];
    Layout l;
    l.band = (s.legend || s.scale_bar) ? 44.0 : 0.0;
    l.title_h = s.title.empty() ? 0.0 : 26.0;
    l.W = s.width;
    l.H = s.height;
    if (l.H <= 0)
        l.H = static_cast<int>(
            std::lround(std::clamp(l.W * vh / vw, 100.0, 4.0 * l.W) + l.band + l.title_h));
    l.plot_h = l.H - l.band - l.title_h;
    if (l.plot_h < 20)
        throw Error("picture: the picture is too small for its legend (height " +
                    std::to_string(l.H) + ")");
    l.tr.scale = std::min(l.W / vw, l.plot_h / vh);
    l.tr.x0 = 0.5 * (l.W - l.tr.scale * vw) - l.tr.scale * v[0];
    l.tr.y0 = l.title_h + 0.5 * (l.plot_h + l.tr.scale * vh) + l.tr.scale * v[1];
    return l;
}

cairo_surface_t* openSurface(Format fmt, const std::string& file, int W, int H) {
    cairo_surface_t* surface = nullptr;
    switch (fmt) {
        case Format::Png:
            surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, W, H);
            break;
        case Format::Svg:
            surface = cairo_svg_surface_create(file.c_str(), W, H);
            break;
        case Format::Pdf:
            surface = cairo_pdf_surface_create(file.c_str(), W, H);
            break;
    }
    if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
        const std::string why = cairo_status_to_string(cairo_surface_status(surface));
        cairo_surface_destroy(surface);
        throw Error("picture: cannot create '" + file + "' (" + why + ")");
    }
    return surface;
}

/// The balls' colours: by group (in `order`, noting the groups met for the legend), by clump,
/// by value on the colour scale [vmin, vmax], or none.
struct Colours {
    const Model& m;
    const Settings& s;
    const std::vector<double>& values;
    const std::vector<std::string>& order;
    double vmin, vmax;
    std::vector<bool> group_used;

    Colours(const Model& model, const Settings& settings, const std::vector<double>& vals)
        : m(model),
          s(settings),
          values(vals),
          order(settings.groups.empty() ? model.groupNames() : settings.groups),
          vmin(settings.range_min),
          vmax(settings.range_max),
          group_used(order.size(), false) {
        if (s.color == ColorBy::Value && !s.range_set) {
            vmin = std::numeric_limits<double>::infinity(), vmax = -vmin;
            for (double x : values)
                if (std::isfinite(x)) vmin = std::min(vmin, x), vmax = std::max(vmax, x);
            if (!(vmin <= vmax)) vmin = 0, vmax = 1;
            if (vmax == vmin) vmax = vmin + 1;  // one value: the bottom of the scale
        }
    }

    Rgb of(std::size_t i, BallId b) {
        switch (s.color) {
            case ColorBy::Group: {
                const std::vector<std::string> gs = m.ballGroups(b);
                for (std::size_t k = 0; k < order.size(); ++k)
                    if (std::find(gs.begin(), gs.end(), order[k]) != gs.end()) {
                        group_used[k] = true;
                        return hex(kCategorical[k % 10]);
                    }
                return hex(kNoCategory);
            }
            case ColorBy::Clump: {
                const ClumpId c = m.clumpOf(b);
                return c.valid() ? hex(kCategorical[(c.index - 1) % 10]) : hex(kNoCategory);
            }
            case ColorBy::Value:
                return viridis((values[i] - vmin) / (vmax - vmin));
            case ColorBy::None:
                return hex(kNoCategory);
        }
        return hex(kNoCategory);
    }
};

/// Balls: filled disks with a thin darker rim (only where the rim is not all there is).
/// Returns their mean radius [m].
double drawBalls(cairo_t* cr, const Model& m, const std::vector<BallId>& ids, const Transform& tr,
                 Colours& colours) {
    double mean_r = 0;
    for (std::size_t i = 0; i < ids.size(); ++i) {
        const Vec2 p = m.ballPos(ids[i]);
        const double r = m.ballRadius(ids[i]);
        mean_r += r;
        const auto c = tr.toPixel(p.x(), p.y());
        const double rp = r * tr.scale;
        cairo_new_path(cr);
        cairo_arc(cr, c[0], c[1], rp, 0, 2 * M_PI);
        const Rgb col = colours.of(i, ids[i]);
        setColor(cr, col);
        if (rp > 3) {
            cairo_fill_preserve(cr);
            cairo_set_source_rgb(cr, 0.6 * col.r, 0.6 * col.g, 0.6 * col.b);
            cairo_set_line_width(cr, std::min(1.0, 0.15 * rp));
            cairo_stroke(cr);
        } else {
            cairo_fill(cr);
        }
    }
    return ids.empty() ? 0.0 : mean_r / static_cast<double>(ids.size());
}

void drawWalls(cairo_t* cr, const Model& m, const std::vector<WallId>& walls, const Transform& tr) {
    setColor(cr, hex(kWall));
    cairo_set_line_width(cr, 2.0);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    for (const WallId w : walls) {
        const std::vector<Vec2> pts = m.wallPoints(w);
        cairo_new_path(cr);
        for (std::size_t k = 0; k < pts.size(); ++k) {
            const auto q = tr.toPixel(pts[k].x(), pts[k].y());
            if (k == 0)
                cairo_move_to(cr, q[0], q[1]);
            else
                cairo_line_to(cr, q[0], q[1]);
        }
        if (m.wallClosed(w)) cairo_close_path(cr);
        cairo_stroke(cr);
    }
}

void strokeLine(cairo_t* cr, const std::array<double, 2>& a, const std::array<double, 2>& b) {
    cairo_move_to(cr, a[0], a[1]);
    cairo_line_to(cr, b[0], b[1]);
    cairo_stroke(cr);
}

/// Force chains: centre to centre (contact point for a wall), width in proportion to |normal
/// force|, the largest drawn `chain_width` wide; compression black, tension red.
void drawForceChains(cairo_t* cr, const Model& m, const Settings& s, const Transform& tr,
                     double mean_r) {
    const std::vector<ContactInfo> cs = m.contacts(true);
    double fmax = 0;
    for (const ContactInfo& c : cs) fmax = std::max(fmax, std::fabs(c.normal_force));
    // Default: 0.6 of the mean radius, so that the chains stay inside the balls they join.
    const double wmax =
        (s.chain_width > 0 ? s.chain_width : (mean_r > 0 ? 0.6 * mean_r : 0.01)) * tr.scale;
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
    if (!(fmax > 0)) return;
    for (const ContactInfo& c : cs) {
        const double f = c.normal_force;
        const double wpx = wmax * std::fabs(f) / fmax;
        if (wpx < 0.05) continue;  // invisible anyway
        const Vec2 a = m.ballPos(c.ball1);
        const Vec2 b = c.wall.valid() ? c.point : m.ballPos(c.ball2);
        if (f >= 0)
            cairo_set_source_rgba(cr, 0.05, 0.05, 0.05, 0.85);
        else
            cairo_set_source_rgba(cr, 0.85, 0.1, 0.1, 0.85);
        cairo_set_line_width(cr, wpx);
        strokeLine(cr, tr.toPixel(a.x(), a.y()), tr.toPixel(b.x(), b.y()));
    }
}

/// Cracks: a segment across each broken bond through the point where it broke, as long as the
/// bond is wide (crack.hpp), on top of everything; at least 3 px wide so that a crack is seen
/// on a picture of thousands of balls.
void drawCracks(cairo_t* cr, const std::vector<Crack>& cracks, const Transform& tr) {
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
    for (const Crack& c : cracks) {
        if (!(c.radius > 0)) continue;
        const Vec2 a = c.end1(), b = c.end2();
        const auto pa = tr.toPixel(a.x(), a.y()), pb = tr.toPixel(b.x(), b.y());
        const double w = std::clamp(0.1 * 2 * c.radius * tr.scale, 3.0, 8.0);
        // a white rim first, so that a crack stands out on a ball of its own colour
        cairo_set_source_rgb(cr, 1, 1, 1);
        cairo_set_line_width(cr, w + 3);
        strokeLine(cr, pa, pb);
        setColor(cr, hex(c.mode == kBreakShear ? kCrackShear : kCrackTension));
        cairo_set_line_width(cr, w);
        strokeLine(cr, pa, pb);
    }
}

/// The scale bar at the left of the bottom band (its top at `by`); returns where the legend
/// starts.
double drawScaleBar(cairo_t* cr, const Layout& l, double x, double by) {
    const double len = niceLength(0.2 * l.W / l.tr.scale);
    const double lpx = len * l.tr.scale;
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 2);
    cairo_move_to(cr, x, by + 28);
    cairo_line_to(cr, x + lpx, by + 28);
    cairo_move_to(cr, x, by + 23);
    cairo_line_to(cr, x, by + 33);
    cairo_move_to(cr, x + lpx, by + 23);
    cairo_line_to(cr, x + lpx, by + 33);
    cairo_stroke(cr);
    cairo_move_to(cr, x, by + 16);
    cairo_show_text(cr, lengthText(len).c_str());
    return x + lpx + 30;
}

/// The legend of the balls' colours from `x` on; returns where it ends.
double drawColourLegend(cairo_t* cr, const Settings& s, const Colours& colours, const Layout& l,
                        double x, double by) {
    cairo_text_extents_t ext;
    if (s.color == ColorBy::Group) {
        for (std::size_t k = 0; k < colours.order.size(); ++k) {
            if (!colours.group_used[k]) continue;
            setColor(cr, hex(kCategorical[k % 10]));
            cairo_rectangle(cr, x, by + 16, 14, 14);
            cairo_fill(cr);
            cairo_set_source_rgb(cr, 0, 0, 0);
            cairo_move_to(cr, x + 19, by + 28);
            cairo_show_text(cr, colours.order[k].c_str());
            cairo_text_extents(cr, colours.order[k].c_str(), &ext);
            x += 19 + ext.x_advance + 16;
        }
    } else if (s.color == ColorBy::Value) {
        const double bw = std::min(220.0, std::max(60.0, l.W - x - 120));
        for (int k = 0; k < 64; ++k) {
            setColor(cr, viridis((k + 0.5) / 64));
            cairo_rectangle(cr, x + bw * k / 64, by + 20, bw / 64 + 0.5, 12);
            cairo_fill(cr);
        }
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_move_to(cr, x, by + 14);
        cairo_show_text(cr, numberText(colours.vmin).c_str());
        const std::string top = numberText(colours.vmax);
        cairo_text_extents(cr, top.c_str(), &ext);
        cairo_move_to(cr, x + bw - ext.x_advance, by + 14);
        cairo_show_text(cr, top.c_str());
        cairo_move_to(cr, x + bw + 10, by + 31);
        cairo_show_text(cr, s.value_name.c_str());
        x += bw + 10;
    } else if (s.color == ColorBy::Clump) {
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_move_to(cr, x, by + 28);
        cairo_show_text(cr, "colour: one per clump (free balls grey)");
    }
    return x;
}

/// Two short samples of the cracks' colours and their names, after the colour legend.
double drawCrackLegend(cairo_t* cr, double x, double by) {
    cairo_text_extents_t ext;
    x += 10;
    for (const auto& [colour, name] :
         {std::pair<unsigned, const char*>{kCrackTension, "tension crack"},
          std::pair<unsigned, const char*>{kCrackShear, "shear crack"}}) {
        setColor(cr, hex(colour));
        cairo_set_line_width(cr, 3);
        cairo_move_to(cr, x, by + 23);
        cairo_line_to(cr, x + 16, by + 23);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_move_to(cr, x + 21, by + 28);
        cairo_show_text(cr, name);
        cairo_text_extents(cr, name, &ext);
        x += 21 + ext.x_advance + 16;
    }
    return x;
}

/// The title, and the bottom band: scale bar at the left, legends to its right.
void drawAnnotations(cairo_t* cr, const Settings& s, const Colours& colours, const Layout& l) {
    cairo_set_source_rgb(cr, 0, 0, 0);
    if (!s.title.empty()) {
        cairo_set_font_size(cr, 15);
        cairo_move_to(cr, 8, 18);
        cairo_show_text(cr, s.title.c_str());
        cairo_set_font_size(cr, 13);
    }
    const double by = l.H - l.band;
    double x = 10;
    if (s.scale_bar) x = drawScaleBar(cr, l, x, by);
    if (!s.legend) return;
    x = drawColourLegend(cr, s, colours, l, x, by);
    if (s.cracks) x = drawCrackLegend(cr, x, by);
    if (s.force_chains) {
        cairo_text_extents_t ext;
        cairo_set_source_rgb(cr, 0, 0, 0);
        const std::string t = "lines: contact force (width ~ |Fn|)";
        cairo_text_extents(cr, t.c_str(), &ext);
        cairo_move_to(cr, std::max(x + 10, l.W - ext.x_advance - 10), by + 28);
        cairo_show_text(cr, t.c_str());
    }
}

/// Writes the PNG (or finishes the SVG or PDF) and releases the surface.
void finishSurface(cairo_surface_t* surface, Format fmt, const std::string& file) {
    cairo_status_t st = CAIRO_STATUS_SUCCESS;
    if (fmt == Format::Png)
        st = cairo_surface_write_to_png(surface, file.c_str());
    else
        cairo_surface_finish(surface);
    if (st == CAIRO_STATUS_SUCCESS) st = cairo_surface_status(surface);
    cairo_surface_destroy(surface);
    if (st != CAIRO_STATUS_SUCCESS)
        throw Error("picture: cannot write '" + file + "' (" + cairo_status_to_string(st) + ")");
}

}  // namespace

Transform draw(const Model& m, const Settings& s, const std::vector<double>& values,
               const std::string& file, const std::vector<Crack>& cracks) {
    const Format fmt = formatOf(file);
    const std::vector<BallId> ids = vtk::particleIds(m);
    const std::vector<WallId> walls = m.wallIds();
    const Layout l = layoutOf(s, viewOf(m, s, ids, walls));

    cairo_surface_t* surface = openSurface(fmt, file, l.W, l.H);
    cairo_t* cr = cairo_create(surface);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 13);

    // The model clipped to the plot area: the band stays readable.
    cairo_save(cr);
    cairo_rectangle(cr, 0, l.title_h, l.W, l.plot_h);
    cairo_clip(cr);
    Colours colours(m, s, values);
    const double mean_r = drawBalls(cr, m, ids, l.tr, colours);
    drawWalls(cr, m, walls, l.tr);
    if (s.force_chains) drawForceChains(cr, m, s, l.tr, mean_r);
    if (s.cracks) drawCracks(cr, cracks, l.tr);
    cairo_restore(cr);

    drawAnnotations(cr, s, colours, l);
    cairo_destroy(cr);
    finishSurface(surface, fmt, file);
    return l.tr;
}

#endif  // TALUS_HAVE_CAIRO

}  // namespace talus::picture
