// SPDX-License-Identifier: MIT
// m:picture{file =, color =, contacts =, every =, ...}: quick-look pictures with cairo
// (picture.hpp; docs/output.md, "Pictures").
#include <sys/stat.h>

#include <cmath>

#include "lua_bindings.hpp"
#include "output.hpp"
#include "picture.hpp"
#include "vtk_writer.hpp"

namespace talus::lua {

namespace {

struct PictureOutput : Output {
    picture::Settings settings;
    std::string file;       // as given
    bool numbered = false;  // every =: file_000000.png, ...
    bool speed = false;     // color = "speed"
    std::vector<std::string> written_files;
    picture::Transform transform;

    void write(LuaModel& lm) override {
        std::vector<double> values;
        if (settings.color == picture::ColorBy::Value) {
            const std::vector<BallId> ids = vtk::particleIds(*lm.model);
            values.reserve(ids.size());
            for (const BallId b : ids) {
                if (speed) {
                    values.push_back(lm.model->ballVel(b).norm());
                } else {
                    const Value v =
                        callBallFunction(lm, functions[0].second, b, "picture: 'color'");
                    if (v.vector)
                        throw ScriptError(
                            "picture: 'color' function returned a vector; return a number");
                    values.push_back(v.x);
                }
            }
        }
        const std::string name =
            numbered ? picture::frameName(file, static_cast<int64_t>(written_files.size())) : file;
        // A missing last directory level is made (as m:vtk does), so `every =` frames can go
        // to a folder of their own.
        const auto slash = name.find_last_of('/');
        if (slash != std::string::npos && slash > 0) ::mkdir(name.substr(0, slash).c_str(), 0777);
        transform = picture::draw(*lm.model, settings, values, name, lm.cracks);
        written_files.push_back(name);
        ++written;
    }
    std::string describe() const override { return "picture '" + file + "'"; }
    bool pixel(double x, double y, double& px, double& py) const override {
        const auto p = transform.toPixel(x, y);
        px = p[0], py = p[1];
        return true;
    }
    std::vector<std::string> files() const override { return written_files; }
    std::string mainFile() const override {
        return written_files.empty() ? file : written_files.back();
    }
};

const Option kPictureOptionRows[] = {
    {"file", "string", "a .png, .svg or .pdf path (with every: file_000000.png, ...)", true},
    {"color", "\"group\"|\"speed\"|\"clump\"|\"none\"|fun(ball: talus.Ball): number",
     "what colours the balls (default group)"},
    {"contacts", "\"force\"|\"none\"", "force chains (default) or none"},
    {"cracks", "boolean", "draw the cracks (default false)"},
    {"every", "integer", "a numbered picture every `every` steps"},
    {"size", "integer[]", "{width, height} in pixels, 16..20000"},
    {"view", "number[]", "{xmin, ymin, xmax, ymax} [m] (default: the whole model)"},
    {"groups", "string[]", "draw only the bodies of these groups"},
    {"range", "number[]", "{min, max} of the colour scale"},
    {"legend", "boolean", "draw the legend (default true)"},
    {"scale_bar", "boolean", "draw the scale bar (default true)"},
    {"title", "string", "a title above the picture"},
    {"chain_width", "number", "width of the strongest force chain [m] (0: 0.6 mean radius)"},
    {"label", "string", "the colour scale's label (color = \"speed\" or a function)"},
};
const OptionTable kPictureOptions = {"talus.PictureOptions", "m:picture{...}: quick-look pictures",
                                     kPictureOptionRows};

/// The file and its format, and `every` (numbered frames).
void readFile(const Options& o, PictureOutput& out) {
    out.file = o.string("file", "");
    if (out.file.empty())
        throw ScriptError("picture: 'file' is required (a .png, .svg or .pdf path)");
    const auto dot = out.file.find_last_of('.');
    const std::string ext = dot == std::string::npos ? "" : lower(out.file.substr(dot));
    if (ext != ".png" && ext != ".svg" && ext != ".pdf")
        throw ScriptError("picture: 'file' must end in .png, .svg or .pdf (got '" + out.file +
                          "')");
    const long long every = o.integer("every", 0);
    if (o.has("every") && every < 1)
        throw ScriptError("picture: 'every' must be >= 1 (got " + std::to_string(every) + ")");
    out.every = static_cast<int>(every);
    out.numbered = every > 0;
}

/// color = "group" | "speed" | "clump" | "none" | function(ball) -> number, and its label.
void readColor(const Options& o, LuaModel& lm, PictureOutput& out) {
    lua_State* L = o.state();
    picture::Settings& s = out.settings;
    const int ct = o.push("color");
    if (ct == LUA_TFUNCTION) {
        s.color = picture::ColorBy::Value;
        out.functions.emplace_back("color", storeRef(L, lm, -1));
        s.value_name = o.string("label", "value");
    } else if (ct == LUA_TNIL || ct == LUA_TSTRING) {
        const int c = o.choice("color", 0, {"group", "speed", "clump", "none"});
        s.color = c == 0   ? picture::ColorBy::Group
                  : c == 1 ? picture::ColorBy::Value
                  : c == 2 ? picture::ColorBy::Clump
                           : picture::ColorBy::None;
        out.speed = c == 1;
        if (out.speed) s.value_name = o.string("label", "speed [m/s]");
    } else {
        const std::string got = typeName(L, -1);
        lua_pop(L, 1);
        throw ScriptError(
            "picture: 'color' must be \"group\", \"speed\", \"clump\", \"none\" or a "
            "function(ball) returning a number (got " +
            got + ")");
    }
    lua_pop(L, 1);
    if (o.has("label") && s.color != picture::ColorBy::Value)
        throw ScriptError(
            "picture: 'label' names the colour scale of color = \"speed\" or a function; it has "
            "no use with this colour");
}

/// size, view and range: the picture's frame and the colour scale's.
void readGeometry(const Options& o, picture::Settings& s) {
    if (o.has("size")) {
        const std::vector<double> sz = o.numbers("size");
        if (sz.size() != 2 || !(sz[0] >= 16 && sz[0] <= 20000) ||
            !(sz[1] >= 16 && sz[1] <= 20000) || sz[0] != std::floor(sz[0]) ||
            sz[1] != std::floor(sz[1]))
            throw ScriptError(
                "picture: 'size' must be {width, height}, whole numbers in 16..20000");
        s.width = static_cast<int>(sz[0]), s.height = static_cast<int>(sz[1]);
    }
    if (o.has("view")) {
        const std::vector<double> v = o.numbers("view");
        if (v.size() != 4 || !(v[2] > v[0]) || !(v[3] > v[1]))
            throw ScriptError(
                "picture: 'view' must be {xmin, ymin, xmax, ymax} with xmax > xmin and ymax > "
                "ymin");
        s.view_set = true;
        s.view = {v[0], v[1], v[2], v[3]};
    }
    if (o.has("range")) {
        const std::vector<double> r = o.numbers("range");
        if (r.size() != 2 || !(r[1] > r[0]))
            throw ScriptError("picture: 'range' must be {min, max} with max > min");
        s.range_set = true;
        s.range_min = r[0], s.range_max = r[1];
    }
}

/// What is drawn besides the balls: contacts, groups, cracks, legend, scale bar, title.
void readContent(const Options& o, LuaModel& lm, picture::Settings& s) {
    if (o.has("contacts")) s.force_chains = o.choice("contacts", 0, {"force", "none"}) == 0;
    if (o.has("groups")) {
        s.groups = o.strings("groups");
        Model& m = *lm.model;
        for (const std::string& g : s.groups)
            if (m.groupIndex(g, false) < 0)
                throw ScriptError(
                    "picture: unknown group '" + g + "' in 'groups' (groups: " +
                    (m.groupNames().empty() ? std::string("none") : joinNames(m.groupNames())) +
                    ")");
    }
    s.cracks = o.boolean("cracks", false);
    s.legend = o.boolean("legend", true);
    s.scale_bar = o.boolean("scale_bar", true);
    s.title = o.string("title", "");
    s.chain_width = o.number("chain_width", 0.0);
    if (!(s.chain_width >= 0))
        throw ScriptError("picture: 'chain_width' must be >= 0 [m] (0: 0.6 of the mean radius)");
}

int w_picture(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "picture");
        const Options o(L, 2, "picture", kPictureOptions);
        if (!picture::available())
            throw ScriptError(
                "picture: talus was built without cairo (apt-get install libcairo2-dev, then "
                "rebuild with scripts/build.sh)");
        auto out = std::make_unique<PictureOutput>();
        readFile(o, *out);
        readColor(o, lm, *out);
        readGeometry(o, out->settings);
        readContent(o, lm, out->settings);
        return registerOutput(L, lm, std::move(out), true);
    });
}

const Method kPictureMethods[] = {
    {"picture", w_picture, "a picture of the model now (and one every `every` steps)",
     "options: talus.PictureOptions", "talus.Output"},
};

const OptionTable* const kOptionTables[] = {&kPictureOptions};

}  // namespace

std::vector<SavedPictureSeries> pictureSeriesStates(const LuaModel& lm) {
    std::vector<SavedPictureSeries> out;
    for (const auto& o : lm.outputs)
        if (const auto* p = dynamic_cast<const PictureOutput*>(o.get());
            p && p->open && p->numbered) {
            SavedPictureSeries s;
            s.file = p->file;
            s.every = p->every;
            s.speed = p->speed;
            s.function = !p->functions.empty();
            s.settings = p->settings;
            s.files = p->written_files;
            out.push_back(std::move(s));
        }
    return out;
}

void resumePictureSeries(lua_State* L, LuaModel& lm, const SavedPictureSeries& state) {
    auto out = std::make_unique<PictureOutput>();
    out->settings = state.settings;
    out->file = state.file;
    out->numbered = true;
    out->speed = state.speed;
    out->every = static_cast<int>(state.every);
    out->written_files = state.files;  // the next frame is numbered after them
    registerOutput(L, lm, std::move(out), false);
}

extern const Binding kPictureBinding = {"pictures", kPictureMethods, {}, {}, kOptionTables, {}};

}  // namespace talus::lua
