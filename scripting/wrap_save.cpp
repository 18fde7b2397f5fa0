// SPDX-License-Identifier: MIT
// m:save(file) and talus.restore(file): the whole model in a save file (docs/save-format.md).
// The engine saves its own state (core/src/model_save.cpp); this file adds the Lua layer's part
// in the file's host section: the histories (file, every, columns, rows), which a restore
// re-opens in append mode, the ParaView series (m:vtk) and picture series (m:picture{every =}),
// which a restore continues (same .pvd, next frame numbers), and which callbacks were
// registered. Lua functions cannot be saved: a restore lists what the script must register
// again (on_cycle, on_event, on_warning, and the histories and series with function columns,
// which are not continued).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "lua_bindings.hpp"
#include "output.hpp"
#include "talus/errors.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/save_file.hpp"

namespace talus::lua {

namespace {

// 1: histories and callbacks. 2: then the ParaView and picture series. A restore reads both.
constexpr uint32_t kHostVersion = 3;

const char* energyName(double EnergyTotals::*member) {
    for (const EnergyItem& e : energyItems())
        if (e.member == member) return e.name;
    return "";
}

void writeStrings(SaveWriter& w, const std::vector<std::string>& v) {
    w.u64(v.size());
    for (const std::string& x : v) w.str(x);
}

std::vector<std::string> readStrings(SaveReader& r, const char* what) {
    std::vector<std::string> v(r.count(8, what));
    for (std::string& x : v) x = r.str();
    return v;
}

/// Version 2: the open output series, as they are (vtk_writer.hpp, picture.hpp); version 3 adds
/// each series' `cracks` switch.
void writeSeries(SaveWriter& w, const LuaModel& lm) {
    const std::vector<SavedVtkSeries> vtk = vtkSeriesStates(lm);
    w.u64(vtk.size());
    for (const SavedVtkSeries& v : vtk) {
        const vtk::SeriesState& s = v.state;
        w.str(s.dir), w.str(s.name), w.i64(s.every);
        writeStrings(w, s.fields);
        w.boolean(s.walls), w.boolean(s.contacts);
        w.boolean(s.cracks);
        w.i64(s.next_frame);
        w.u64(s.frames.size());
        for (const vtk::FrameEntry& f : s.frames)
            w.i64(f.frame), w.i64(f.step), w.f64(f.time), w.str(f.file);
        writeStrings(w, v.functions);
    }
    const std::vector<SavedPictureSeries> pics = pictureSeriesStates(lm);
    w.u64(pics.size());
    for (const SavedPictureSeries& p : pics) {
        const picture::Settings& s = p.settings;
        w.str(p.file), w.i64(p.every), w.boolean(p.speed), w.boolean(p.function);
        w.i32(s.width), w.i32(s.height);
        w.boolean(s.view_set);
        for (const double v : s.view) w.f64(v);
        w.i32(static_cast<int32_t>(s.color));
        writeStrings(w, s.groups);
        w.str(s.value_name);
        w.boolean(s.range_set), w.f64(s.range_min), w.f64(s.range_max);
        w.boolean(s.force_chains), w.f64(s.chain_width);
        w.boolean(s.legend), w.boolean(s.scale_bar);
        w.boolean(s.cracks);
        w.str(s.title);
        writeStrings(w, p.files);
    }
}

/// Reads the series of a version-2 host section (checked as the engine's sections are: a
/// damaged file is refused, never half applied) and collects the ones to continue.
void readSeries(SaveReader& r, uint32_t version, const LuaModel& lm,
                std::vector<vtk::SeriesState>& vtk_out, std::vector<SavedPictureSeries>& pic_out,
                std::vector<std::string>& notes) {
    const auto checkGroups = [&](const std::vector<std::string>& groups, const std::string& what) {
        for (const std::string& g : groups)
            if (lm.model->groupIndex(g, false) < 0) r.fail(what + ": unknown group '" + g + "'");
    };
    const std::size_t nv = r.count(8 * 2 + 8 + 8 + 2 + 8 + 8 + 8, "vtk series");
    for (std::size_t i = 0; i < nv; ++i) {
        vtk::SeriesState s;
        s.dir = r.str(), s.name = r.str();
        const std::string what = "vtk series '" + s.dir + "/" + s.name + ".pvd'";
        s.every = r.i64();
        s.fields = readStrings(r, "vtk fields");
        s.walls = r.boolean(), s.contacts = r.boolean();
        if (version >= 3) s.cracks = r.boolean();
        s.next_frame = r.i64();
        s.frames.resize(r.count(8 + 8 + 8 + 8, "vtk frames"));
        for (vtk::FrameEntry& f : s.frames)
            f.frame = r.i64(), f.step = r.i64(), f.time = r.f64(), f.file = r.str();
        const std::vector<std::string> functions = readStrings(r, "vtk function fields");
        if (s.dir.empty() || s.name.empty() || s.name.find('/') != std::string::npos ||
            s.every < 0 || s.every > std::numeric_limits<int>::max())
            r.fail(what + ": invalid settings");
        for (const std::string& f : s.fields) {
            const auto& known = vtk::optionalBallFields();
            if (std::find(known.begin(), known.end(), f) == known.end())
                r.fail(what + ": unknown ball field '" + f + "'");
        }
        int64_t last = -1;
        for (const vtk::FrameEntry& f : s.frames) {
            // Our own names (NAME_NNNNNN.vtm in the series directory), in increasing order.
            if (f.frame <= last || f.file.find('/') != std::string::npos ||
                f.file.rfind(s.name + "_", 0) != 0 || f.file.size() < s.name.size() + 5 ||
                f.file.compare(f.file.size() - 4, 4, ".vtm") != 0)
                r.fail(what + ": invalid frame list");
            last = f.frame;
        }
        if (s.next_frame <= last || s.next_frame > (int64_t(1) << 40))
            r.fail(what + ": invalid next frame number");
        if (!functions.empty()) {
            notes.push_back(what + " is not continued: its field(s) " + joinNames(functions) +
                            " are Lua functions, which a save cannot hold; go on with it with "
                            "m:vtk{dir = \"" +
                            s.dir + "\", name = \"" + s.name +
                            "\", append = true, fields = {...}}");
        } else if (s.every == 0) {
            notes.push_back(what +
                            " was written on request (no 'every'); go on with it with "
                            "m:vtk{dir = \"" +
                            s.dir + "\", name = \"" + s.name + "\", append = true}");
        } else {
            vtk_out.push_back(std::move(s));
        }
    }
    const std::size_t np =
        r.count(8 + 8 + 2 + 8 + 1 + 32 + 4 + 8 + 8 + 17 + 9 + 2 + 8 + 8, "picture series");
    for (std::size_t i = 0; i < np; ++i) {
        SavedPictureSeries p;
        picture::Settings& s = p.settings;
        p.file = r.str();
        const std::string what = "picture series '" + p.file + "'";
        p.every = r.i64(), p.speed = r.boolean(), p.function = r.boolean();
        s.width = r.i32(), s.height = r.i32();
        s.view_set = r.boolean();
        for (double& v : s.view) v = r.f64();
        s.color = r.enumValue<picture::ColorBy>(4, "picture colour");
        s.groups = readStrings(r, "picture groups");
        s.value_name = r.str();
        s.range_set = r.boolean(), s.range_min = r.f64(), s.range_max = r.f64();
        s.force_chains = r.boolean(), s.chain_width = r.f64();
        s.legend = r.boolean(), s.scale_bar = r.boolean();
        if (version >= 3) s.cracks = r.boolean();
        s.title = r.str();
        p.files = readStrings(r, "picture files");
        // The ranges m:picture accepts (wrap_picture.cpp).
        if (p.file.empty() || p.every < 1 || p.every > std::numeric_limits<int>::max() ||
            !(s.width >= 16 && s.width <= 20000) ||
            !(s.height == 0 || (s.height >= 16 && s.height <= 20000)) ||
            (s.view_set && !(s.view[2] > s.view[0] && s.view[3] > s.view[1])) ||
            (s.range_set && !(s.range_max > s.range_min)) || !(s.chain_width >= 0) ||
            !std::isfinite(s.chain_width) ||
            ((p.speed || p.function) != (s.color == picture::ColorBy::Value)))
            r.fail(what + ": invalid settings");
        checkGroups(s.groups, what);
        if (p.function) {
            notes.push_back(what +
                            " is not continued: its 'color' is a Lua function, which a "
                            "save cannot hold; call m:picture again");
            continue;
        }
        pic_out.push_back(std::move(p));
    }
}

/// Version 3: the crack log (crack.hpp), so a restored run's pictures and series draw the cracks
/// made before the save and m:cracks() lists them.
void writeCracks(SaveWriter& w, const LuaModel& lm) {
    w.u64(lm.cracks.size());
    for (const Crack& c : lm.cracks) {
        w.f64(c.time), w.i64(c.step);
        w.f64(c.pos.x()), w.f64(c.pos.y()), w.f64(c.normal.x()), w.f64(c.normal.y());
        w.f64(c.radius), w.i32(c.mode);
        w.u32(c.ball1.index), w.u32(c.ball1.generation);
        w.u32(c.ball2.index), w.u32(c.ball2.generation);
        w.f64(c.sigma), w.f64(c.tau);
    }
}

/// Reads the crack log into `lm` (replacing it: a restored model has an empty log).
void readCracks(SaveReader& r, LuaModel& lm) {
    std::vector<Crack> cracks(r.count(8 * 8 + 4 + 16, "cracks"));
    for (Crack& c : cracks) {
        c.time = r.f64(), c.step = r.i64();
        const double x = r.f64(), y = r.f64(), nx = r.f64(), ny = r.f64();
        c.pos = Vec2(x, y), c.normal = Vec2(nx, ny);
        c.radius = r.f64();
        c.mode = r.i32();
        c.ball1.index = r.u32(), c.ball1.generation = r.u32();
        c.ball2.index = r.u32(), c.ball2.generation = r.u32();
        c.sigma = r.f64(), c.tau = r.f64();
        if (!std::isfinite(c.time) || !std::isfinite(x) || !std::isfinite(y) || !(c.radius >= 0) ||
            !std::isfinite(c.radius) ||
            (c.mode != kBreakNone && c.mode != kBreakTension && c.mode != kBreakShear))
            r.fail("crack " + std::to_string(&c - cracks.data() + 1) + ": invalid values");
    }
    lm.cracks = std::move(cracks);
}

std::vector<uint8_t> hostSection(const LuaModel& lm) {
    SaveWriter w;
    w.u32(kHostVersion);
    uint64_t open = 0;
    for (const auto& h : lm.histories) open += h->open();
    w.u64(open);
    for (const auto& h : lm.histories) {
        if (!h->open()) continue;
        w.str(h->path);
        w.i64(h->every);
        w.i64(h->base_rows + h->rows);  // the file's rows up to this step
        w.u64(h->columns.size());
        for (const History::Column& c : h->columns) {
            w.str(c.name);
            w.i32(static_cast<int32_t>(c.kind));
            w.str(c.kind == History::Column::Energy ? energyName(c.energy) : "");
            w.str(c.group);
        }
    }
    w.u64(lm.cycle_refs.size());
    w.boolean(lm.hasEventHandler(EventKind::BondBreak));
    w.boolean(lm.hasEventHandler(EventKind::ContactCreated));
    w.boolean(lm.warning_ref != LUA_NOREF);
    writeSeries(w, lm);
    writeCracks(w, lm);
    return std::move(w.data());
}

/// Re-creates the histories and collects the notes about what was not restored.
void applyHostSection(lua_State* L, LuaModel& lm, const std::vector<uint8_t>& bytes,
                      const std::string& file, std::vector<std::string>& notes) {
    if (bytes.empty()) return;  // a file written by the engine alone (C++ tests)
    SaveReader r(bytes.data(), bytes.size(), "'" + file + "', section 'HOST'");
    const uint32_t version = r.u32();
    if (version < 1 || version > kHostVersion)
        r.fail("host data version " + std::to_string(version) + " (this build reads 1 to " +
               std::to_string(kHostVersion) + ")");
    const std::size_t nh = r.count(40, "histories");
    std::vector<std::unique_ptr<History>> restored;
    for (std::size_t i = 0; i < nh; ++i) {
        auto h = std::make_unique<History>();
        h->path = r.str();
        h->every = r.i64();
        h->rows = r.i64();
        if (h->every < 1) r.fail("history '" + h->path + "': invalid 'every'");
        const std::size_t nc = r.count(24, "history columns");
        std::vector<std::string> functions;
        for (std::size_t k = 0; k < nc; ++k) {
            History::Column c;
            c.name = r.str();
            c.kind = r.enumValue<History::Column::Kind>(6, "history column kind");
            const std::string item = r.str();
            c.group = r.str();
            if (c.kind == History::Column::Energy) {
                for (const EnergyItem& e : energyItems())
                    if (item == e.name) c.energy = e.member;
                if (!c.energy)
                    r.fail("history '" + h->path + "': unknown energy item '" + item + "'");
            }
            if (!c.group.empty() && lm.model->groupIndex(c.group, false) < 0)
                r.fail("history '" + h->path + "': unknown group '" + c.group + "'");
            if (c.kind == History::Column::Function) functions.push_back(c.name);
            h->columns.push_back(c);
        }
        if (!functions.empty()) {
            notes.push_back("history '" + h->path + "' is not continued: its column(s) " +
                            joinNames(functions) +
                            " are Lua functions, which a save cannot hold; create it again "
                            "with m:history{file = \"" +
                            h->path + "\", append = true, ...} to append to it");
            continue;
        }
        restored.push_back(std::move(h));
    }
    const uint64_t cycles = r.u64();
    const bool bond_break = r.boolean(), contact_created = r.boolean(), warning = r.boolean();
    std::vector<vtk::SeriesState> vtk_series;
    std::vector<SavedPictureSeries> pictures;
    if (version >= 2) readSeries(r, version, lm, vtk_series, pictures, notes);
    if (version >= 3) readCracks(r, lm);
    r.expectEnd();
    for (auto& h : restored) {
        const std::string path = h->path;
        const std::string note = reopenHistory(lm, std::move(h));
        notes.push_back(note.empty() ? "history '" + path + "' continues (appending)" : note);
    }
    for (const vtk::SeriesState& s : vtk_series) {
        resumeVtkSeries(L, lm, s);
        lua_pop(L, 1);  // the series userdata: the model keeps the series
        notes.push_back("vtk series '" + s.dir + "/" + s.name + ".pvd' continues (frame " +
                        std::to_string(s.next_frame) + " next)");
    }
    for (const SavedPictureSeries& p : pictures) {
        resumePictureSeries(L, lm, p);
        lua_pop(L, 1);
        notes.push_back("picture series '" + p.file + "' continues (frame " +
                        std::to_string(p.files.size()) + " next)");
    }
    std::vector<std::string> callbacks;
    if (cycles) callbacks.push_back(std::to_string(cycles) + " m:on_cycle");
    if (bond_break) callbacks.push_back("m:on_event(\"bond_break\")");
    if (contact_created) callbacks.push_back("m:on_event(\"contact_created\")");
    if (warning) callbacks.push_back("m:on_warning");
    if (!callbacks.empty())
        notes.push_back("Lua callbacks are not saved; register them again: " +
                        joinNames(callbacks));
}

const Option kRestoreOptionRows[] = {
    {"quiet", "boolean", "do not print the notes to stderr"},
};
const OptionTable kRestoreOptions = {"talus.RestoreOptions", "talus.restore(file, {...})",
                                     kRestoreOptionRows};

int w_save(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "save");
        if (lua_type(L, 2) != LUA_TSTRING)
            throw ScriptError("save: the file name must be a string (got " + typeName(L, 2) + ")");
        if (lm.running)
            throw ScriptError(
                "save: not from inside a cycle or solve (a callback); save "
                "between run calls");
        saveLuaModel(lm, lua_tostring(L, 2));
        return 0;
    });
}

int w_restore(lua_State* L) {
    return catchexcept(L, [&] {
        if (lua_type(L, 1) != LUA_TSTRING)
            throw ScriptError("restore: the file name must be a string (got " + typeName(L, 1) +
                              ")");
        const std::string path = lua_tostring(L, 1);
        const Options o(L, 2, "restore", kRestoreOptions, true);
        const bool quiet = o.boolean("quiet", false);
        RestoredModel r = restoreModelFile(path, PluginRegistry::global());
        pushNewModel(L, std::move(r.model));
        LuaModel& lm = checkModel(L, -1, "restore");
        applyHostSection(L, lm, r.host, path, r.notes);
        if (!quiet)
            for (const std::string& n : r.notes)
                std::fprintf(stderr, "talus: restore '%s': %s\n", path.c_str(), n.c_str());
        pushStringList(L, r.notes);
        return 2;
    });
}

const Method kSaveMethods[] = {
    {"save", w_save, "saves the model (with its histories and output series) to a file",
     "file: string", ""},
};

const Method kSaveFunctions[] = {
    {"restore", w_restore,
     "a model from a save file, and notes on what was not restored (Lua callbacks, ...)",
     "file: string, options?: talus.RestoreOptions", "talus.Model, string[]"},
};

const OptionTable* const kOptionTables[] = {&kRestoreOptions};

}  // namespace

extern const Binding kSaveBinding = {
    "save and restore", kSaveMethods, kSaveFunctions, {}, kOptionTables, {}};

void saveLuaModel(LuaModel& lm, const std::string& path) {
    // Rows written so far go to the file first: the save and the CSV agree on the step.
    lm.flushHistories();
    saveModelFile(*lm.model, path, hostSection(lm));
}

}  // namespace talus::lua
