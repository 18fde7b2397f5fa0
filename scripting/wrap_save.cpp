// SPDX-License-Identifier: MIT
// m:save(file) and talus.restore(file): the whole model in a save file (docs/save-format.md).
// The engine saves its own state (core/src/model_save.cpp); this file adds the Lua layer's part
// in the file's host section: the histories (file, every, columns, rows), which a restore
// re-opens in append mode, and which callbacks were registered. Lua functions cannot be saved:
// a restore lists what the script must register again (on_cycle, on_event, on_warning, and the
// histories with function columns, which are not continued).
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/save_file.hpp"

namespace talus::lua {

namespace {

constexpr uint32_t kHostVersion = 1;

const char* energyName(double EnergyTotals::*member) {
    for (const EnergyItem& e : energyItems())
        if (e.member == member) return e.name;
    return "";
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
        w.i64(h->rows);
        w.u64(h->columns.size());
        for (const History::Column& c : h->columns) {
            w.str(c.name);
            w.i32(static_cast<int32_t>(c.kind));
            w.str(c.kind == History::Column::Energy ? energyName(c.energy) : "");
            w.str(c.group);
        }
    }
    w.u64(lm.cycle_refs.size());
    w.boolean(lm.bond_break_ref != LUA_NOREF);
    w.boolean(lm.contact_created_ref != LUA_NOREF);
    w.boolean(lm.warning_ref != LUA_NOREF);
    return std::move(w.data());
}

/// Re-creates the histories and collects the notes about what was not restored.
void applyHostSection(LuaModel& lm, const std::vector<uint8_t>& bytes, const std::string& file,
                      std::vector<std::string>& notes) {
    if (bytes.empty()) return;  // a file written by the engine alone (C++ tests)
    SaveReader r(bytes.data(), bytes.size(), "'" + file + "', section 'HOST'");
    const uint32_t version = r.u32();
    if (version != kHostVersion)
        r.fail("host data version " + std::to_string(version) + " (this build reads " +
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
    r.expectEnd();
    for (auto& h : restored) {
        const std::string path = h->path;
        reopenHistory(lm, std::move(h));
        notes.push_back("history '" + path + "' continues (appending)");
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

int w_save(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "save");
        if (lua_type(L, 2) != LUA_TSTRING)
            throw ScriptError("save: the file name must be a string (got " + typeName(L, 2) + ")");
        if (lm.running)
            throw ScriptError(
                "save: not from inside a cycle or solve (a callback); save "
                "between run calls");
        const std::string path = lua_tostring(L, 2);
        // Rows written so far go to the file first: the save and the CSV agree on the step.
        lm.flushHistories();
        saveModelFile(*lm.model, path, hostSection(lm));
        return 0;
    });
}

int w_restore(lua_State* L) {
    return catchexcept(L, [&] {
        if (lua_type(L, 1) != LUA_TSTRING)
            throw ScriptError("restore: the file name must be a string (got " + typeName(L, 1) +
                              ")");
        const std::string path = lua_tostring(L, 1);
        const Options o(L, 2, "restore", {"quiet"}, true);
        const bool quiet = o.boolean("quiet", false);
        RestoredModel r = restoreModelFile(path, PluginRegistry::global());
        pushNewModel(L, std::move(r.model));
        LuaModel& lm = checkModel(L, -1, "restore");
        applyHostSection(lm, r.host, path, r.notes);
        if (!quiet)
            for (const std::string& n : r.notes)
                std::fprintf(stderr, "talus: restore '%s': %s\n", path.c_str(), n.c_str());
        pushStringList(L, r.notes);
        return 2;
    });
}

}  // namespace

void addSaveMethods(lua_State* L, int methods_index) {
    lua_pushcfunction(L, w_save);
    lua_setfield(L, methods_index, "save");
}

void addSaveFunctions(lua_State* L) {
    lua_pushcfunction(L, w_restore);
    lua_setfield(L, -2, "restore");
}

}  // namespace talus::lua
