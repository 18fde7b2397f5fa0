// SPDX-License-Identifier: MIT
// m:history{file =, every =, columns =}: CSV histories written by a model cycle hook.
//
// Column order is deterministic: as given when `columns` is a list ({"time", {"y", fn}}),
// sorted by name when it is a map ({time = "time", y = fn}), whose iteration order Lua does not
// define. The first row is written at the current state when the history is created; then one
// row every `every` steps. Rows are flushed after every run call (cycle/solve), so a script that
// ends with os.exit() loses nothing; the file is closed by h:close(), m:close_history() or when
// the model is collected.
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "lua_bindings.hpp"

namespace talus::lua {

namespace {

struct HistoryRef {
    LuaModel* lm;
    History* history;
};

const char* const kBuiltins[] = {"time", "step", "dt"};

std::string knownSpecs() {
    std::vector<std::string> names(std::begin(kBuiltins), std::end(kBuiltins));
    for (const EnergyItem& e : energyItems()) names.push_back(e.name);
    names.push_back("balance_error");
    return joinNames(names) +
           ", an energy item of a group (\"kinetic@rock\" or {\"kinetic\", "
           "\"rock\"}), or a function";
}

bool isEnergyName(const std::string& name) {
    if (name == "balance_error") return true;
    for (const EnergyItem& e : energyItems())
        if (name == e.name) return true;
    return false;
}

/// The group of a group-wise energy column, checked against the model's groups.
std::string checkGroup(LuaModel& lm, const std::string& column, const std::string& item,
                       const std::string& group) {
    if (!isEnergyName(item))
        throw ScriptError(
            "history: column '" + column + "': '" + item +
            "' is not an energy item (a group goes with an energy item: " + knownSpecs() + ")");
    if (lm.model->groupIndex(group, false) < 0) {
        std::vector<std::string> names = lm.model->groupNames();
        throw ScriptError("history: column '" + column + "': unknown group '" + group +
                          "' (groups: " + (names.empty() ? "none" : joinNames(names)) + ")");
    }
    return group;
}

/// Parses one column spec (the value on top of the stack) into `col`.
void parseSpec(lua_State* L, LuaModel& lm, History::Column& col) {
    const int t = lua_type(L, -1);
    if (t == LUA_TFUNCTION) {
        col.kind = History::Column::Function;
        col.ref = storeRef(L, lm, -1);
        return;
    }
    std::string name;
    if (t == LUA_TSTRING) {
        name = lua_tostring(L, -1);
        // "kinetic@rock": an energy item of one group.
        const std::size_t at = name.find('@');
        if (at != std::string::npos) {
            col.group = checkGroup(lm, col.name, name.substr(0, at), name.substr(at + 1));
            name.resize(at);
        }
    } else if (t == LUA_TTABLE) {
        // {"kinetic"} or {"kinetic", "rock"} (an energy item of one group)
        lua_rawgeti(L, -1, 1);
        const bool ok = lua_type(L, -1) == LUA_TSTRING;
        if (ok) name = lua_tostring(L, -1);
        lua_pop(L, 1);
        if (!ok) throw ScriptError("history: column '" + col.name + "': {name} needs a string");
        if (lua_rawlen(L, -1) > 1) {
            lua_rawgeti(L, -1, 2);
            const bool ok2 = lua_type(L, -1) == LUA_TSTRING;
            const std::string group = ok2 ? lua_tostring(L, -1) : "";
            lua_pop(L, 1);
            if (!ok2 || lua_rawlen(L, -1) > 2)
                throw ScriptError("history: column '" + col.name +
                                  "': {item, group} needs two strings, e.g. {\"kinetic\", "
                                  "\"rock\"}");
            col.group = checkGroup(lm, col.name, name, group);
        }
    } else {
        throw ScriptError("history: column '" + col.name + "' must be a name (" + knownSpecs() +
                          "), got " + typeName(L, -1));
    }
    if (name == "time")
        col.kind = History::Column::Time;
    else if (name == "step")
        col.kind = History::Column::Step;
    else if (name == "dt")
        col.kind = History::Column::Dt;
    else if (name == "balance_error")
        col.kind = History::Column::BalanceError;
    else {
        for (const EnergyItem& e : energyItems())
            if (name == e.name) {
                col.kind = History::Column::Energy;
                col.energy = e.member;
                return;
            }
        throw ScriptError("history: column '" + col.name + "': unknown quantity '" + name +
                          "' (known: " + knownSpecs() + ")");
    }
}

/// In the list form, {"kinetic", "rock"} is a group-wise energy column when the first string is
/// an energy item and the second a group of the model (a pair {"name", spec} otherwise; an
/// energy item's name with a spec that is not a group would be a quantity named like an item).
bool isGroupPair(lua_State* L, LuaModel& lm, int index) {
    index = lua_absindex(L, index);
    if (lua_rawlen(L, index) != 2) return false;
    lua_rawgeti(L, index, 1);
    lua_rawgeti(L, index, 2);
    const bool strings = lua_type(L, -2) == LUA_TSTRING && lua_type(L, -1) == LUA_TSTRING;
    const bool pair = strings && isEnergyName(lua_tostring(L, -2)) &&
                      lm.model->groupIndex(lua_tostring(L, -1), false) >= 0;
    lua_pop(L, 2);
    return pair;
}

std::string formatNumber(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.12g", v);
    return buf;
}

/// Quotes a header cell if it needs it (RFC 4180).
std::string csvCell(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string out = "\"";
    for (char c : s) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

/// The data rows of an existing history file (its lines after the header; 0 if it is missing
/// or empty).
int64_t dataRows(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return 0;
    int64_t lines = 0;
    char buf[1 << 16];
    std::size_t got;
    while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) lines += std::count(buf, buf + got, '\n');
    std::fclose(f);
    return lines > 0 ? lines - 1 : 0;
}

/// Cuts a history file after its header and `rows` data rows, as the ParaView series of a
/// restore drops the frames past the save. Returns the rows the file had beyond them (0: it
/// ended there), or -1 when it has fewer (then it is left as it is).
int64_t trimRows(const std::string& path, int64_t rows, int& err) {
    err = 0;
    std::FILE* f = std::fopen(path.c_str(), "r+b");
    if (!f) {
        err = errno;
        return errno == ENOENT ? -1 : 0;
    }
    const int64_t keep = rows + 1;  // the header, then the rows
    int64_t lines = 0, cut = -1, offset = 0;
    char buf[1 << 16];
    std::size_t got;
    while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) {
        for (std::size_t i = 0; i < got; ++i)
            if (buf[i] == '\n' && ++lines == keep && cut < 0)
                cut = offset + static_cast<int64_t>(i) + 1;
        offset += static_cast<int64_t>(got);
    }
    int64_t beyond = 0;
    if (cut < 0) {
        beyond = -1;  // fewer lines than the save recorded
    } else if (cut < offset) {
        beyond = lines - keep;
        if (::ftruncate(::fileno(f), static_cast<off_t>(cut)) != 0) err = errno;
    }
    std::fclose(f);
    return beyond;
}

const Option kHistoryOptionRows[] = {
    {"file", "string", "the CSV file", true},
    {"every", "integer", "steps between rows (default 1)"},
    {"columns", "table",
     "a list {\"time\", {\"y\", fn}} (in that order) or a map {time = \"time\", y = fn} (sorted)",
     true},
    {"append", "boolean", "continue an existing file (after a restore); default false"},
};
const OptionTable kHistoryOptions = {
    "talus.HistoryOptions", "m:history{...}: a CSV row every `every` steps", kHistoryOptionRows};

/// Reads the list form of `columns` (at stack index `cols`, n > 0 entries): "time" or
/// {"name", spec} (or {"kinetic", "rock"}, an energy item of a group), in the order given.
void readColumnList(lua_State* L, LuaModel& lm, int cols, lua_Integer n, History& h) {
    for (lua_Integer i = 1; i <= n; ++i) {
        History::Column col;
        const int t = lua_rawgeti(L, cols, i);
        if (t == LUA_TSTRING) {
            col.name = lua_tostring(L, -1);
        } else if (t == LUA_TTABLE && isGroupPair(L, lm, -1)) {
            // {"kinetic", "rock"}: an energy item of a group, named "kinetic@rock".
            lua_rawgeti(L, -1, 1);
            lua_rawgeti(L, -2, 2);
            col.name = std::string(lua_tostring(L, -2)) + "@" + lua_tostring(L, -1);
            lua_pop(L, 2);
        } else if (t == LUA_TTABLE) {
            lua_rawgeti(L, -1, 1);
            const bool ok = lua_type(L, -1) == LUA_TSTRING;
            if (ok) col.name = lua_tostring(L, -1);
            lua_pop(L, 1);
            if (!ok || lua_rawlen(L, -1) != 2)
                throw ScriptError("history: column " + std::to_string(i) +
                                  " must be a name or a pair {\"name\", spec}");
            lua_rawgeti(L, -1, 2);
            lua_remove(L, -2);
        } else {
            throw ScriptError("history: column " + std::to_string(i) +
                              " must be a name or a pair {\"name\", spec} (got " + typeName(L, -1) +
                              ")");
        }
        parseSpec(L, lm, col);
        lua_pop(L, 1);
        h.columns.push_back(col);
    }
    lua_pushnil(L);
    while (lua_next(L, cols) != 0) {
        const bool in_list =
            lua_isinteger(L, -2) && lua_tointeger(L, -2) >= 1 && lua_tointeger(L, -2) <= n;
        lua_pop(L, 1);
        if (!in_list)
            throw ScriptError(
                "history: 'columns' is either a list ({\"time\", {\"y\", fn}}) or a map "
                "({time = \"time\", y = fn}), not both");
    }
}

/// Reads the map form of `columns` (at stack index `cols`): name = spec, sorted by name.
void readColumnMap(lua_State* L, LuaModel& lm, int cols, History& h) {
    std::vector<std::string> names;
    lua_pushnil(L);
    while (lua_next(L, cols) != 0) {
        lua_pop(L, 1);
        if (lua_type(L, -1) != LUA_TSTRING)
            throw ScriptError("history: column names must be strings");
        names.push_back(lua_tostring(L, -1));
    }
    std::sort(names.begin(), names.end());
    for (const std::string& name : names) {
        History::Column col;
        col.name = name;
        lua_pushstring(L, name.c_str());
        lua_rawget(L, cols);
        parseSpec(L, lm, col);
        lua_pop(L, 1);
        h.columns.push_back(col);
    }
}

/// The `columns` option, checked: not empty, energy columns only with tracing on.
void readColumns(const Options& o, LuaModel& lm, History& h) {
    lua_State* L = o.state();
    if (o.push("columns") != LUA_TTABLE) {
        const std::string got = typeName(L, -1);
        lua_pop(L, 1);
        throw ScriptError("history: 'columns' must be a table (got " + got + ")");
    }
    const int cols = lua_gettop(L);
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, cols));
    if (n > 0)
        readColumnList(L, lm, cols, n, h);
    else
        readColumnMap(L, lm, cols, h);
    lua_pop(L, 1);
    if (h.columns.empty()) throw ScriptError("history: 'columns' is empty");
    for (const History::Column& c : h.columns)
        if ((c.kind == History::Column::Energy || c.kind == History::Column::BalanceError) &&
            !lm.model->energyTracing())
            throw ScriptError("history: column '" + c.name +
                              "' needs energy tracing; call m:energy{on = true} first");
}

/// Opens the file and writes the header. append = true (after a restore): continue an existing
/// file; the header is written only when the file is new or empty.
void openFile(LuaModel& lm, History& h, bool append) {
    if (append) h.base_rows = dataRows(h.path);
    h.file = std::fopen(h.path.c_str(), append ? "a" : "w");
    if (!h.file)
        throw ScriptError("history: cannot write '" + h.path + "' (" + std::strerror(errno) + ")");
    std::string header;
    for (std::size_t i = 0; i < h.columns.size(); ++i)
        header += (i ? "," : "") + csvCell(h.columns[i].name);
    if ((!append || std::ftell(h.file) == 0) && std::fprintf(h.file, "%s\n", header.c_str()) < 0)
        h.fail(lm, "writing the header", errno);
}

const ObjectType& historyObject();

/// Hands the history to the model, writes its first row (the state now), installs its cycle
/// hook and pushes its userdata.
void startHistory(lua_State* L, LuaModel& lm, std::unique_ptr<History> h) {
    History* hp = h.get();
    LuaModel* lmp = &lm;
    lm.histories.push_back(std::move(h));
    try {
        ActiveThread active(lm, L);
        hp->writeRow(lm);
    } catch (...) {
        hp->closeQuietly(lm);
        throw;
    }
    hp->flush(lm);
    hp->hook = lm.model->addCycleHook(hp->every, [lmp, hp](Model&) { hp->writeRow(*lmp); });
    newObject<HistoryRef>(L, 1, historyObject())->history = hp;
}

int w_history(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "history");
        const Options o(L, 2, "history", kHistoryOptions);
        auto h = std::make_unique<History>();
        h->path = o.string("file", "");
        if (h->path.empty()) throw ScriptError("history: 'file' is required (a CSV path)");
        h->every = o.integer("every", 1);
        if (h->every < 1)
            throw ScriptError("history: 'every' must be >= 1 (got " + std::to_string(h->every) +
                              ")");
        readColumns(o, lm, *h);
        openFile(lm, *h, o.boolean("append", false));
        startHistory(L, lm, std::move(h));
        return 1;
    });
}

int w_close_history(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "close_history");
        for (auto& h : lm.histories) h->close(lm);
        return 0;
    });
}

// ------------------------------------------------------------------ the history object

History& history(void* self) { return *static_cast<HistoryRef*>(self)->history; }

const Field kHistoryFields[] = {
    {"file", "string", "the CSV file",
     [](lua_State* L, void* self) { lua_pushstring(L, history(self).path.c_str()); }},
    {"rows", "integer", "the data rows written",
     [](lua_State* L, void* self) {
         lua_pushinteger(L, static_cast<lua_Integer>(history(self).rows));
     }},
    {"open", "boolean", "false once closed",
     [](lua_State* L, void* self) { lua_pushboolean(L, history(self).open()); }},
    {"columns", "string[]", "the column names, in the file's order",
     [](lua_State* L, void* self) {
         std::vector<std::string> names;
         for (const auto& c : history(self).columns) names.push_back(c.name);
         pushStringList(L, names);
     }},
};

int w_h_close(lua_State* L) {
    return catchexcept(L, [&] {
        HistoryRef& h = checkObject<HistoryRef>(L, 1, historyObject(), "close");
        h.history->close(*h.lm);
        return 0;
    });
}

int w_h_flush(lua_State* L) {
    return catchexcept(L, [&] {
        HistoryRef& h = checkObject<HistoryRef>(L, 1, historyObject(), "flush");
        if (h.history->open()) h.history->flush(*h.lm);
        return 0;
    });
}

const Method kHistoryObjectMethods[] = {
    {"close", w_h_close, "writes what is buffered and closes the file", "", ""},
    {"flush", w_h_flush, "hands the buffered rows to the system", "", ""},
};

void describe(lua_State* L, void* self) {
    lua_pushfstring(L, "history '%s' (%d rows)", history(self).path.c_str(),
                    static_cast<int>(history(self).rows));
}

const ObjectType kHistoryObject = {
    kHistoryType,
    "history",
    "h",
    "a CSV history written by a cycle hook (m:history)",
    kHistoryFields,
    kHistoryObjectMethods,
    describe,
};

const ObjectType& historyObject() { return kHistoryObject; }

}  // namespace

void History::writeRow(LuaModel& lm) {
    if (!open()) return;
    Model& m = *lm.model;
    writing = true;
    std::string row;
    try {
        EnergyTotals e;
        bool have_energy = false;
        for (std::size_t i = 0; i < columns.size(); ++i) {
            const Column& c = columns[i];
            if (i) row += ',';
            switch (c.kind) {
                case Column::Time:
                    row += formatNumber(m.time());
                    break;
                case Column::Step:
                    row += std::to_string(m.step());
                    break;
                case Column::Dt:
                    row += formatNumber(m.lastTimestep());
                    break;
                case Column::Energy:
                case Column::BalanceError: {
                    if (!have_energy) e = m.energies(), have_energy = true;
                    const EnergyTotals eg = c.group.empty() ? e : m.energies(c.group);
                    row +=
                        formatNumber(c.kind == Column::Energy ? eg.*(c.energy) : eg.balanceError());
                    break;
                }
                case Column::Function: {
                    lua_State* L = lm.L;
                    const int base = lua_gettop(L);
                    pushRef(L, lm, c.ref);
                    pushModel(L, lm);
                    if (lua_pcall(L, 1, 1, 0) != LUA_OK) {
                        std::string msg = errorText(L, -1);
                        lua_settop(L, base);
                        throw CallbackError(msg);
                    }
                    const int t = lua_type(L, -1);
                    if (t == LUA_TNUMBER)
                        row += formatNumber(lua_tonumber(L, -1));
                    else if (t == LUA_TBOOLEAN)
                        row += lua_toboolean(L, -1) ? "1" : "0";
                    else if (t != LUA_TNIL) {
                        const std::string got = typeName(L, -1);
                        lua_settop(L, base);
                        throw ScriptError("history '" + path + "': column '" + c.name +
                                          "' returned a " + got +
                                          " (a number, boolean or nil "
                                          "is expected)");
                    }
                    lua_settop(L, base);
                    break;
                }
            }
        }
    } catch (...) {
        writing = false;
        if (close_pending) closeQuietly(lm);
        throw;
    }
    writing = false;
    if (open()) {
        // A full disk or a closed pipe shows here (or at the next flush, for buffered rows):
        // stop the run rather than report rows that never reach the file.
        if (std::fprintf(file, "%s\n", row.c_str()) < 0 || std::ferror(file))
            fail(lm, "writing a row", errno);
        ++rows;
    }
    if (close_pending) close(lm);
}

void History::flush(LuaModel& lm) {
    if (!open()) return;
    if (std::fflush(file) != 0 || std::ferror(file)) fail(lm, "flushing", errno);
}

void History::fail(LuaModel& lm, const char* what, int err) {
    const std::string msg = "history '" + path + "': " + what + " failed (" +
                            std::strerror(err != 0 ? err : EIO) + "); " + std::to_string(rows) +
                            " rows were given to it and the file is incomplete";
    // Close without further reports: this error is the one that counts.
    writing = false;
    close_pending = false;
    lm.removeHook(hook);
    hook = 0;
    if (file) std::fclose(file);
    file = nullptr;
    throw ScriptError(msg);
}

void History::close(LuaModel& lm) {
    if (writing) {
        close_pending = true;
        return;
    }
    close_pending = false;
    lm.removeHook(hook);
    hook = 0;
    if (!file) return;
    // fclose writes what is still buffered: its failure loses rows too.
    const bool bad = std::ferror(file) != 0;
    errno = 0;
    const int rc = std::fclose(file);
    file = nullptr;
    if (rc != 0 || bad) {
        const int err = errno;
        throw ScriptError("history '" + path + "': closing failed (" +
                          std::strerror(err != 0 ? err : EIO) + "); " + std::to_string(rows) +
                          " rows were given to it and the file is incomplete");
    }
}

void History::closeQuietly(LuaModel& lm) {
    try {
        close(lm);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "talus: error: %s\n", e.what());
    }
}

std::string reopenHistory(LuaModel& lm, std::unique_ptr<History> h) {
    // A restored history continues its file: no header, no first row (the saving run wrote the
    // row of the saved step if it was due), then a row every `every` steps as before. Rows the
    // saving run wrote after the save are cut first, so that no time appears twice.
    std::string note;
    int err = 0;
    const int64_t beyond = trimRows(h->path, h->rows, err);
    if (err != 0 && err != ENOENT)
        throw ScriptError("restore: history '" + h->path + "': cannot cut it back to the " +
                          std::to_string(h->rows) + " rows of the save (" + std::strerror(err) +
                          ")");
    if (beyond > 0)
        note = "history '" + h->path + "' continues (appending) after its row " +
               std::to_string(h->rows) + ", the saved step; the " + std::to_string(beyond) +
               " row(s) written after the save were dropped";
    else if (beyond < 0)
        note = "history '" + h->path + "' continues (appending), but it has fewer than the " +
               std::to_string(h->rows) + " rows of the save (missing, edited or replaced?)";
    h->file = std::fopen(h->path.c_str(), "a");
    if (!h->file)
        throw ScriptError("restore: history '" + h->path + "': cannot append (" +
                          std::strerror(errno) + ")");
    History* hp = h.get();
    LuaModel* lmp = &lm;
    lm.histories.push_back(std::move(h));
    hp->hook = lm.model->addCycleHook(hp->every, [lmp, hp](Model&) { hp->writeRow(*lmp); });
    return note;
}

namespace {

const Method kHistoryMethods[] = {
    {"history", w_history, "a CSV history: one row now, then one every `every` steps",
     "options: talus.HistoryOptions", "talus.History"},
    {"close_history", w_close_history, "closes every history of the model", "", ""},
};

const ObjectType* const kTypes[] = {&kHistoryObject};
const OptionTable* const kOptionTables[] = {&kHistoryOptions};

}  // namespace

extern const Binding kHistoryBinding = {"histories", kHistoryMethods, {},
                                        kTypes,      kOptionTables,   {}};

}  // namespace talus::lua
