// SPDX-License-Identifier: MIT
// m:vtk{dir =, every =, name =, fields =, walls =, contacts =, cracks =, append =}: ParaView series
// (vtk_writer.hpp; docs/output.md). Also the userdata both outputs return (m:vtk and
// m:picture): out:write(), out:close(), out:pixel(x, y), out.file, out.files, out.frames.
#include <algorithm>
#include <cmath>

#include "lua_bindings.hpp"
#include "output.hpp"
#include "vtk_writer.hpp"

namespace talus::lua {

namespace {

const Option kVtkOptionRows[] = {
    {"dir", "string", "the output directory", true},
    {"every", "integer", "steps between frames (default: only m:vtk's frame and out:write())"},
    {"name", "string", "the series' file name, without '/' (default \"talus\")"},
    {"fields", "table",
     "extra ball fields: names ({\"force\", \"mass\"}) and name = function(ball) ... end"},
    {"walls", "boolean", "write the walls (default true)"},
    {"contacts", "boolean", "write the contacts (default true)"},
    {"cracks", "boolean", "write the cracks (default false)"},
    {"append", "boolean", "continue the series' .pvd (after a restore); default false"},
};
const OptionTable kVtkOptions = {"talus.VtkOptions", "m:vtk{...}: a ParaView series",
                                 kVtkOptionRows};

struct VtkOutput : Output {
    explicit VtkOutput(vtk::SeriesState s) : series(std::move(s)) {}
    vtk::Series series;
    void write(LuaModel& lm) override;
    std::string describe() const override { return "vtk series '" + series.pvdPath() + "'"; }
    std::vector<std::string> files() const override {
        std::vector<std::string> out;
        for (const auto& f : series.state().frames)
            out.push_back(series.state().dir + "/" + f.file);
        return out;
    }
    std::string mainFile() const override { return series.pvdPath(); }
};

void VtkOutput::write(LuaModel& lm) {
    std::vector<vtk::BallArray> extra;
    if (!functions.empty()) {
        const std::vector<BallId> ids = vtk::particleIds(*lm.model);
        for (const auto& [name, ref] : functions) {
            vtk::BallArray a;
            a.name = name;
            a.components = 0;
            for (const BallId b : ids) {
                const Value v = callBallFunction(lm, ref, b, "vtk: field '" + name + "'");
                const int comps = v.vector ? 3 : 1;
                if (a.components == 0) a.components = comps;
                if (a.components != comps)
                    throw ScriptError("vtk: field '" + name +
                                      "' returned numbers for some balls and vectors for others");
                a.values.push_back(v.x);
                if (v.vector) a.values.push_back(v.y), a.values.push_back(0.0);
            }
            if (a.components == 0) a.components = 1;
            extra.push_back(std::move(a));
        }
    }
    series.writeFrame(*lm.model, extra, lm.cracks);
    ++written;
}

int w_vtk(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "vtk");
        const Options o(L, 2, "vtk", kVtkOptions);
        vtk::SeriesState st;
        st.dir = o.string("dir", "");
        if (st.dir.empty()) throw ScriptError("vtk: 'dir' is required (the output directory)");
        st.name = o.string("name", "talus");
        if (st.name.empty() || st.name.find('/') != std::string::npos)
            throw ScriptError("vtk: 'name' must be a file name without '/' (got '" + st.name +
                              "')");
        const long long every = o.integer("every", 0);
        if (o.has("every") && every < 1)
            throw ScriptError("vtk: 'every' must be >= 1 (got " + std::to_string(every) + ")");
        st.every = every;
        st.walls = o.boolean("walls", true);
        st.contacts = o.boolean("contacts", true);
        st.cracks = o.boolean("cracks", false);
        std::vector<std::pair<std::string, int>> functions;
        if (o.has("fields")) {
            readFields(L, lm, o, "vtk", vtk::optionalBallFields(), st.fields, functions);
        }
        if (o.boolean("append", false)) {
            st.frames = vtk::Series::readPvd(st.dir, st.name, lm.model->time());
            for (const auto& f : st.frames) st.next_frame = std::max(st.next_frame, f.frame + 1);
        }
        auto out = std::make_unique<VtkOutput>(st);
        out->every = static_cast<int>(every);
        out->functions = std::move(functions);
        // The first frame is the state now, as a history's first row; not again when the
        // series we go on with already ends at this time (a restored run).
        const bool have_now = !st.frames.empty() && st.frames.back().time == lm.model->time();
        return registerOutput(L, lm, std::move(out), !have_now);
    });
}

}  // namespace

std::vector<SavedVtkSeries> vtkSeriesStates(const LuaModel& lm) {
    std::vector<SavedVtkSeries> out;
    for (const auto& o : lm.outputs)
        if (const auto* v = dynamic_cast<const VtkOutput*>(o.get()); v && v->open) {
            SavedVtkSeries s;
            s.state = v->series.state();
            for (const auto& f : v->functions) s.functions.push_back(f.first);
            out.push_back(std::move(s));
        }
    return out;
}

void resumeVtkSeries(lua_State* L, LuaModel& lm, const vtk::SeriesState& state) {
    auto out = std::make_unique<VtkOutput>(state);
    out->every = static_cast<int>(state.every);
    registerOutput(L, lm, std::move(out), false);
}

// ------------------------------------------------------------------ shared with m:picture

Value callBallFunction(LuaModel& lm, int ref, BallId id, const std::string& what) {
    lua_State* L = lm.L;
    const int base = lua_gettop(L);
    pushRef(L, lm, ref);
    pushModel(L, lm);
    pushBall(L, lua_gettop(L), id);
    lua_remove(L, -2);
    if (lua_pcall(L, 1, 1, 0) != LUA_OK) {
        std::string msg = errorText(L, -1);
        lua_settop(L, base);
        throw CallbackError(msg);
    }
    Value v;
    if (lua_type(L, -1) == LUA_TNUMBER) {
        v.x = lua_tonumber(L, -1);
    } else if (lua_type(L, -1) == LUA_TTABLE) {
        try {
            const Vec2 p = toVec(L, -1, what);
            v.x = p.x(), v.y = p.y(), v.vector = true;
        } catch (...) {
            lua_settop(L, base);
            throw;
        }
    } else {
        const std::string got = typeName(L, -1);
        lua_settop(L, base);
        throw ScriptError(what + " returned a " + got + " for ball " + std::to_string(id.index) +
                          " (a number or a vector {x, y} is expected)");
    }
    lua_settop(L, base);
    return v;
}

void readFields(lua_State* L, LuaModel& lm, const Options& o, const char* what,
                const std::vector<std::string>& known, std::vector<std::string>& names,
                std::vector<std::pair<std::string, int>>& functions) {
    if (o.push("fields") != LUA_TTABLE) {
        const std::string got = typeName(L, -1);
        lua_pop(L, 1);
        throw ScriptError(std::string(what) + ": 'fields' must be a table (got " + got + ")");
    }
    const int t = lua_gettop(L);
    std::vector<std::string> fn_names;
    lua_pushnil(L);
    while (lua_next(L, t) != 0) {
        if (lua_type(L, -2) == LUA_TNUMBER) {
            const std::string name = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "";
            if (std::find(known.begin(), known.end(), name) == known.end()) {
                const std::string got = name.empty() ? "a " + typeName(L, -1) : "'" + name + "'";
                lua_settop(L, t - 1);
                throw ScriptError(std::string(what) + ": unknown ball field " + got + " (known: " +
                                  joinNames(known) + "; or name = function(ball) ... end)");
            }
            names.push_back(name);
        } else if (lua_type(L, -2) == LUA_TSTRING && lua_type(L, -1) == LUA_TFUNCTION) {
            fn_names.push_back(lua_tostring(L, -2));
        } else {
            const std::string key = lua_type(L, -2) == LUA_TSTRING ? lua_tostring(L, -2) : "?";
            const std::string got = typeName(L, -1);
            lua_settop(L, t - 1);
            throw ScriptError(std::string(what) + ": field '" + key +
                              "' must be a function(ball) returning a number or {x, y} (got " +
                              got + ")");
        }
        lua_pop(L, 1);
    }
    // Sorted: the order of the arrays in the files does not depend on table iteration.
    std::sort(fn_names.begin(), fn_names.end());
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());
    for (const std::string& n : fn_names) {
        if (std::find(names.begin(), names.end(), n) != names.end() ||
            std::find(known.begin(), known.end(), n) != known.end())
            throw ScriptError(std::string(what) + ": field '" + n +
                              "' is a built-in field name; give the function another name");
        lua_getfield(L, t, n.c_str());
        functions.emplace_back(n, storeRef(L, lm, -1));
        lua_pop(L, 1);
    }
    lua_pop(L, 1);
}

namespace {

struct OutputRef {
    LuaModel* lm;
    Output* out;
};

Output& output(void* self) { return *static_cast<OutputRef*>(self)->out; }

const Field kOutputFields[] = {
    {"file", "string", "the .pvd, or the last picture",
     [](lua_State* L, void* self) { lua_pushstring(L, output(self).mainFile().c_str()); }},
    {"files", "string[]", "every file written, in order",
     [](lua_State* L, void* self) { pushStringList(L, output(self).files()); }},
    {"frames", "integer", "the number of frames written",
     [](lua_State* L, void* self) {
         lua_pushinteger(L, static_cast<lua_Integer>(output(self).files().size()));
     }},
    {"every", "integer", "steps between frames (0: on request only)",
     [](lua_State* L, void* self) { lua_pushinteger(L, output(self).every); }},
    {"open", "boolean", "false once closed",
     [](lua_State* L, void* self) { lua_pushboolean(L, output(self).open); }},
};

int w_out_write(lua_State* L);
int w_out_close(lua_State* L);
int w_out_pixel(lua_State* L);

const Method kOutputMethods[] = {
    {"write", w_out_write, "writes a frame of the model now", "", ""},
    {"close", w_out_close, "stops the output (no more frames)", "", ""},
    {"pixel", w_out_pixel, "where the model point (x, y) is in the last picture [px]",
     "x: number, y: number", "number, number"},
};

void describe(lua_State* L, void* self) {
    const Output& out = output(self);
    lua_pushstring(L, ("talus.Output (" + out.describe() + ", " +
                       std::to_string(out.files().size()) + " frames)")
                          .c_str());
}

const ObjectType kOutputObject = {
    kOutputType,   "output",       "out",    "a ParaView series (m:vtk) or pictures (m:picture)",
    kOutputFields, kOutputMethods, describe,
};

OutputRef& checkOutput(lua_State* L, int index, const char* fn) {
    return checkObject<OutputRef>(L, index, kOutputObject, fn);
}

void closeOutput(LuaModel& lm, Output& out) {
    lm.removeHook(out.hook);
    out.hook = 0;
    out.open = false;
}

int w_out_write(lua_State* L) {
    return catchexcept(L, [&] {
        OutputRef& r = checkOutput(L, 1, "write");
        if (!r.out->open) throw ScriptError(r.out->describe() + " was closed");
        ActiveThread active(*r.lm, L);
        r.out->write(*r.lm);
        return 0;
    });
}

int w_out_close(lua_State* L) {
    return catchexcept(L, [&] {
        OutputRef& r = checkOutput(L, 1, "close");
        closeOutput(*r.lm, *r.out);
        return 0;
    });
}

int w_out_pixel(lua_State* L) {
    return catchexcept(L, [&] {
        OutputRef& r = checkOutput(L, 1, "pixel");
        const double x = toNumber(L, 2, "pixel: x"), y = toNumber(L, 3, "pixel: y");
        double px = 0, py = 0;
        if (!r.out->pixel(x, y, px, py))
            throw ScriptError("pixel: only a picture has pixels (" + r.out->describe() + ")");
        lua_pushnumber(L, px);
        lua_pushnumber(L, py);
        return 2;
    });
}

const Method kVtkMethods[] = {
    {"vtk", w_vtk, "a ParaView series: a frame now, then one every `every` steps",
     "options: talus.VtkOptions", "talus.Output"},
};

const ObjectType* const kTypes[] = {&kOutputObject};
const OptionTable* const kOptionTables[] = {&kVtkOptions};

}  // namespace

extern const Binding kVtkBinding = {"ParaView files", kVtkMethods, {}, kTypes, kOptionTables, {}};

int registerOutput(lua_State* L, LuaModel& lm, std::unique_ptr<Output> out, bool write_now) {
    Output* op = out.get();
    LuaModel* lmp = &lm;
    lm.outputs.push_back(std::move(out));
    if (write_now) {
        ActiveThread active(lm, L);
        op->write(lm);
    }
    if (op->every > 0)
        op->hook = lm.model->addCycleHook(op->every, [lmp, op](Model&) {
            if (op->open) op->write(*lmp);
        });
    pushModel(L, lm);
    const int model_index = lua_gettop(L);
    newObject<OutputRef>(L, model_index, kOutputObject)->out = op;
    lua_remove(L, model_index);
    return 1;
}

}  // namespace talus::lua
