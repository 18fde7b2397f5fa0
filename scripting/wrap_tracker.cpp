// SPDX-License-Identifier: MIT
// Trackers from Lua (docs/lua-api.md, "Trackers"): m:track(body, {...}), m:trackers(),
// m:clear_trackers(), and the tracker userdata (an id and its model) whose methods read the
// records the engine kept. A tracker's on_event function lives in the model's user-value table
// (key "trackers", by id), so it never keeps the model alive.
#include <cmath>
#include <limits>
#include <string>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"

namespace talus::lua {

namespace {

struct TrackerRef {
    LuaModel* lm;
    int id;
};

constexpr const char* kHandlersKey = "trackers";  // in the model's user-value table

TrackerRef* testTracker(lua_State* L, int index) {
    return static_cast<TrackerRef*>(testUserdata(L, index, kTrackerType));
}

TrackerRef& checkTracker(lua_State* L, int index, const char* fn) {
    TrackerRef* t = testTracker(L, index);
    if (!t)
        throw ScriptError(std::string("tracker: call it as a method, tr:") + fn +
                          "(...) (the first argument is a " + typeName(L, index) +
                          ", not a tracker)");
    if (!t->lm->model) throw ScriptError("tracker: its model was closed");
    return *t;
}

void pushTracker(lua_State* L, int model_index, int id) {
    model_index = lua_absindex(L, model_index);
    auto* t = newRef<TrackerRef>(L, model_index, kTrackerType);
    t->lm = static_cast<LuaModel*>(lua_touserdata(L, model_index));
    t->id = id;
}

/// Pushes the model's table of on_event functions (created on first use).
void pushHandlers(lua_State* L, const LuaModel& lm) {
    pushModel(L, lm);
    lua_getiuservalue(L, -1, 1);
    lua_remove(L, -2);
    if (lua_getfield(L, -1, kHandlersKey) != LUA_TTABLE) {
        lua_pop(L, 1);
        lua_newtable(L);
        lua_pushvalue(L, -1);
        lua_setfield(L, -3, kHandlersKey);
    }
    lua_remove(L, -2);
}

// ------------------------------------------------------------------ options

TrackImpacts impactKind(lua_State* L, int index, const std::string& what) {
    static const TrackImpacts kinds[] = {TrackImpacts::Walls, TrackImpacts::Bodies,
                                         TrackImpacts::Any};
    return kinds[toEnum(L, index, what, {"walls", "bodies", "any"})];
}

void readImpacts(const Options& o, TrackerDef& d) {
    lua_State* L = o.state();
    const int t = o.push("impacts");
    const int at = lua_gettop(L);
    if (t == LUA_TBOOLEAN) {
        d.impacts = lua_toboolean(L, at) ? TrackImpacts::Any : TrackImpacts::Off;
    } else if (t == LUA_TSTRING) {
        d.impacts = impactKind(L, at, "track: 'impacts'");
    } else if (t == LUA_TTABLE) {
        const Options io(L, at, "track: impacts", {"with", "min_speed"});
        d.impacts = TrackImpacts::Any;
        if (io.has("with")) {
            io.push("with");
            d.impacts = impactKind(L, -1, "track: impacts.with");
            lua_pop(L, 1);
        }
        d.impact_min_speed = io.number("min_speed", 0.0);
    } else if (t != LUA_TNIL) {
        throw ScriptError(
            "track: 'impacts' must be true, \"walls\", \"bodies\", \"any\" or "
            "{with =, min_speed =} (got " +
            typeName(L, at) + ")");
    }
    lua_pop(L, 1);
}

void readLines(const Options& o, TrackerDef& d) {
    lua_State* L = o.state();
    if (o.push("lines") == LUA_TNIL) return lua_pop(L, 1);
    const int list = lua_gettop(L);
    requireTable(L, list, "track: 'lines'");
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, list));
    for (lua_Integer k = 1; k <= n; ++k) {
        lua_rawgeti(L, list, k);
        const std::string what = "track: lines[" + std::to_string(k) + "]";
        const Options lo(L, -1, what, {"from", "to", "event"});
        if (!lo.has("from") || !lo.has("to"))
            throw ScriptError(what + " needs from = {x, y} and to = {x, y}");
        TrackLine line;
        line.from = lo.vec("from", line.from);
        line.to = lo.vec("to", line.to);
        line.event = lo.boolean("event", false);
        d.lines.push_back(line);
        lua_pop(L, 1);
    }
    lua_pop(L, 1);
}

void readPoints(lua_State* L, int index, const std::string& what, std::vector<Vec2>& out) {
    requireTable(L, index, what);
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, index));
    for (lua_Integer k = 1; k <= n; ++k) {
        lua_rawgeti(L, index, k);
        out.push_back(toVec(L, -1, what + " point " + std::to_string(k)));
        lua_pop(L, 1);
    }
}

TrackerDef readDef(const Options& o) {
    lua_State* L = o.state();
    TrackerDef d;
    readImpacts(o, d);
    readLines(o, d);
    if (o.has("rest")) {
        o.push("rest");
        const Options ro(L, -1, "track: rest", {"energy", "speed", "time"});
        d.rest_energy = ro.number("energy", kNotSet);
        d.rest_speed = ro.number("speed", kNotSet);
        if (!ro.has("energy") && !ro.has("speed"))
            throw ScriptError("track: rest needs energy = J or speed = m/s (and time = s)");
        d.rest_time = ro.number("time", 0.0);
        lua_pop(L, 1);
    }
    if (o.has("region")) {
        o.push("region");
        const Options ro(L, -1, "track: region", {"lo", "hi"});
        if (!ro.has("lo") || !ro.has("hi"))
            throw ScriptError("track: region needs lo = {x, y} and hi = {x, y}");
        d.region = true;
        d.region_lo = ro.vec("lo", d.region_lo);
        d.region_hi = ro.vec("hi", d.region_hi);
        lua_pop(L, 1);
    }
    d.end_time = o.number("end_time", d.end_time);
    if (o.has("envelope")) {
        o.push("envelope");
        const Options eo(L, -1, "track: envelope", {"ground", "x0", "dx", "bins"});
        for (const char* k : {"ground", "x0", "dx", "bins"})
            if (!eo.has(k))
                throw ScriptError(std::string("track: envelope needs ground, x0, dx and bins (") +
                                  k + " is missing)");
        eo.push("ground");
        readPoints(L, lua_gettop(L), "track: envelope.ground", d.ground);
        lua_pop(L, 1);
        d.envelope_x0 = eo.number("x0", 0.0);
        d.envelope_dx = eo.number("dx", 0.0);
        const long long bins = eo.integer("bins", 0);
        if (bins < 1 || bins > 10000000)
            throw ScriptError("track: envelope.bins must be from 1 to 1e7 (got " +
                              std::to_string(bins) + ")");
        d.envelope_bins = static_cast<int32_t>(bins);
        lua_pop(L, 1);
    }
    if (o.has("path")) {
        const long long every = o.integer("path", 0);
        if (every < 1)
            throw ScriptError("track: 'path' must be a number of samples >= 1 (got " +
                              std::to_string(every) + ")");
        d.path_every = every;
    }
    return d;
}

// ------------------------------------------------------------------ results

void pushState(lua_State* L, const TrackedState& s, const char* suffix) {
    const std::string sx = suffix;
    lua_pushnumber(L, s.time);
    lua_setfield(L, -2, ("t" + sx).c_str());
    pushVec(L, s.pos);
    lua_setfield(L, -2, ("pos" + sx).c_str());
    pushVec(L, s.vel);
    lua_setfield(L, -2, ("vel" + sx).c_str());
    lua_pushnumber(L, s.spin);
    lua_setfield(L, -2, ("spin" + sx).c_str());
}

std::vector<std::string> groupList(const Model& m, uint64_t bits) {
    std::vector<std::string> out;
    const auto& names = m.groupNames();
    for (std::size_t k = 0; k < names.size() && k < 64; ++k)
        if (bits & (uint64_t(1) << k)) out.push_back(names[k]);
    return out;
}

void pushImpact(lua_State* L, int model_index, const Model& m, const TrackedImpact& imp) {
    lua_createtable(L, 0, 16);
    pushState(L, imp.start, "");
    pushVec(L, imp.normal);
    lua_setfield(L, -2, "normal");
    lua_pushnumber(L, imp.approach);
    lua_setfield(L, -2, "approach");
    pushVec(L, imp.point);
    lua_setfield(L, -2, "point");
    if (imp.wall.valid()) {
        pushWall(L, model_index, imp.wall);
        lua_setfield(L, -2, "wall");
        lua_pushinteger(L, imp.segment + 1);
        lua_setfield(L, -2, "segment");
    } else {
        pushBall(L, model_index, imp.ball);
        lua_setfield(L, -2, "ball");
        if (imp.clump.valid()) {
            pushClump(L, model_index, imp.clump);
            lua_setfield(L, -2, "clump");
        }
    }
    pushStringList(L, groupList(m, imp.groups));
    lua_setfield(L, -2, "groups");
    lua_pushboolean(L, imp.ended);
    lua_setfield(L, -2, "ended");
    if (imp.closed) pushState(L, imp.end, "_end");
}

void pushCrossing(lua_State* L, const TrackedCrossing& c) {
    lua_createtable(L, 0, 7);
    lua_pushinteger(L, c.line + 1);
    lua_setfield(L, -2, "line");
    lua_pushnumber(L, c.time);
    lua_setfield(L, -2, "t");
    pushVec(L, c.pos);
    lua_setfield(L, -2, "pos");
    pushVec(L, c.vel);
    lua_setfield(L, -2, "vel");
    lua_pushnumber(L, c.spin);
    lua_setfield(L, -2, "spin");
    lua_pushnumber(L, c.ke_trans);
    lua_setfield(L, -2, "ke_trans");
    lua_pushnumber(L, c.ke_rot);
    lua_setfield(L, -2, "ke_rot");
}

// ------------------------------------------------------------------ events

void deliverTrackerEvent(LuaModel& lm, const TrackerEvent& ev) {
    lua_State* L = lm.L;
    const int base = lua_gettop(L);
    pushHandlers(L, lm);
    if (lua_rawgeti(L, -1, ev.tracker) != LUA_TFUNCTION) {
        lua_settop(L, base);
        return;
    }
    pushModel(L, lm);
    const int model_index = lua_gettop(L);
    pushTracker(L, model_index, ev.tracker);
    lua_createtable(L, 0, 3);
    if (ev.kind == TrackerEvent::Crossing) {
        lua_pushliteral(L, "crossing");
        lua_setfield(L, -2, "kind");
        lua_pushinteger(L, ev.line + 1);
        lua_setfield(L, -2, "line");
        // The crossing's record: the last one (it was just added).
        const auto& cs = lm.model->trackerCrossings(ev.tracker);
        if (!cs.empty()) {
            pushCrossing(L, cs.back());
            lua_setfield(L, -2, "crossing");
        }
    } else {
        lua_pushliteral(L, "end");
        lua_setfield(L, -2, "kind");
        lua_pushstring(L, trackerStateName(ev.state));
        lua_setfield(L, -2, "state");
    }
    lua_remove(L, model_index);
    if (lua_pcall(L, 2, 0, 0) != LUA_OK) {
        std::string msg = errorText(L, -1);
        lua_settop(L, base);
        throw CallbackError(msg);
    }
    lua_settop(L, base);
}

// ------------------------------------------------------------------ model methods

int w_track(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "track");
        const Options o(
            L, 3, "track",
            {"impacts", "lines", "rest", "region", "end_time", "envelope", "path", "on_event"},
            true);
        if (o.has("on_event")) {
            o.push("on_event");
            const std::string type = typeName(L, -1);
            const bool fn = lua_isfunction(L, -1);
            lua_pop(L, 1);
            if (!fn) throw ScriptError("track: 'on_event' must be a function (got " + type + ")");
        }
        const TrackerDef def = readDef(o);
        int id = 0;
        if (BallRef* b = testBall(L, 2)) {
            if (b->lm != &lm) throw ScriptError("track: the ball belongs to another model");
            id = lm.model->createTracker(b->id, def);
        } else if (ClumpRef* c = testClump(L, 2)) {
            if (c->lm != &lm) throw ScriptError("track: the clump belongs to another model");
            id = lm.model->createTracker(c->id, def);
        } else {
            throw ScriptError("track: argument 1 must be a ball or a clump (got " + typeName(L, 2) +
                              ")");
        }
        if (o.has("on_event")) {
            pushHandlers(L, lm);
            o.push("on_event");
            lua_rawseti(L, -2, id);
            lua_pop(L, 1);
            LuaModel* lmp = &lm;
            lm.model->setTrackerHandler(
                [lmp](const TrackerEvent& ev) { deliverTrackerEvent(*lmp, ev); });
        }
        pushTracker(L, 1, id);
        return 1;
    });
}

int w_trackers(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "trackers");
        const auto n = static_cast<int>(lm.model->trackerCount());
        lua_createtable(L, n, 0);
        for (int id = 1; id <= n; ++id) {
            pushTracker(L, 1, id);
            lua_rawseti(L, -2, id);
        }
        return 1;
    });
}

int w_clear_trackers(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "clear_trackers");
        lm.model->clearTrackers();
        pushModel(L, lm);
        lua_getiuservalue(L, -1, 1);
        lua_pushnil(L);
        lua_setfield(L, -2, kHandlersKey);
        lm.model->setTrackerHandler(nullptr);
        return 0;
    });
}

// ------------------------------------------------------------------ the tracker object

const char* const kFields[] = {"id", "state", "body", "samples"};
const char* const kMethods[] = {"status", "impacts", "crossings", "envelope", "path", "stop"};

std::string knownNames() {
    std::vector<std::string> names(std::begin(kFields), std::end(kFields));
    for (const char* m : kMethods) names.push_back(std::string(m) + "()");
    return joinNames(names);
}

int w_index(lua_State* L) {
    return catchexcept(L, [&] {
        TrackerRef& t = checkTracker(L, 1, "index");
        if (lua_type(L, 2) != LUA_TSTRING)
            throw ScriptError("tracker: field names are strings (got " + typeName(L, 2) + ")");
        const std::string key = lua_tostring(L, 2);
        for (const char* m : kMethods)
            if (key == m) {
                lua_getfield(L, lua_upvalueindex(1), m);
                return 1;
            }
        const TrackerStatus s = t.lm->model->trackerStatus(t.id);
        if (key == "id") {
            lua_pushinteger(L, t.id);
        } else if (key == "state") {
            lua_pushstring(L, trackerStateName(s.state));
        } else if (key == "samples") {
            lua_pushinteger(L, static_cast<lua_Integer>(s.samples));
        } else if (key == "body") {
            lua_getiuservalue(L, 1, 1);
            if (s.clump.valid())
                pushClump(L, -1, s.clump);
            else
                pushBall(L, -1, s.ball);
        } else {
            throw ScriptError("tracker: unknown field '" + key + "' (known: " + knownNames() + ")");
        }
        return 1;
    });
}

int w_newindex(lua_State* L) {
    return catchexcept(L, [&]() -> int {
        checkTracker(L, 1, "newindex");
        throw ScriptError("tracker: its fields are read-only (it is set by m:track{...})");
    });
}

int w_status(lua_State* L) {
    return catchexcept(L, [&] {
        TrackerRef& t = checkTracker(L, 1, "status");
        const TrackerStatus s = t.lm->model->trackerStatus(t.id);
        lua_createtable(L, 0, 7);
        lua_pushstring(L, trackerStateName(s.state));
        lua_setfield(L, -2, "state");
        lua_pushinteger(L, static_cast<lua_Integer>(s.samples));
        lua_setfield(L, -2, "samples");
        pushState(L, s.last, "");
        if (!std::isnan(s.rest_since)) {
            lua_pushnumber(L, s.rest_since);
            lua_setfield(L, -2, "rest_since");
        }
        return 1;
    });
}

int w_impacts(lua_State* L) {
    return catchexcept(L, [&] {
        TrackerRef& t = checkTracker(L, 1, "impacts");
        const Model& m = *t.lm->model;
        const auto& list = m.trackerImpacts(t.id);
        lua_getiuservalue(L, 1, 1);
        const int model_index = lua_gettop(L);
        lua_createtable(L, static_cast<int>(list.size()), 0);
        for (std::size_t i = 0; i < list.size(); ++i) {
            pushImpact(L, model_index, m, list[i]);
            lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
        }
        return 1;
    });
}

int w_crossings(lua_State* L) {
    return catchexcept(L, [&] {
        TrackerRef& t = checkTracker(L, 1, "crossings");
        const auto& list = t.lm->model->trackerCrossings(t.id);
        lua_createtable(L, static_cast<int>(list.size()), 0);
        for (std::size_t i = 0; i < list.size(); ++i) {
            pushCrossing(L, list[i]);
            lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
        }
        return 1;
    });
}

int w_envelope(lua_State* L) {
    return catchexcept(L, [&] {
        TrackerRef& t = checkTracker(L, 1, "envelope");
        const Model& m = *t.lm->model;
        lua_createtable(L, 0, 2);
        const char* names[] = {"height", "energy"};
        const std::vector<double>* lists[] = {&m.trackerEnvelopeHeight(t.id),
                                              &m.trackerEnvelopeEnergy(t.id)};
        for (int k = 0; k < 2; ++k) {
            lua_newtable(L);  // sparse: only the bins the centre was in
            for (std::size_t b = 0; b < lists[k]->size(); ++b)
                if (!std::isnan((*lists[k])[b])) {
                    lua_pushnumber(L, (*lists[k])[b]);
                    lua_rawseti(L, -2, static_cast<lua_Integer>(b + 1));
                }
            lua_setfield(L, -2, names[k]);
        }
        return 1;
    });
}

int w_path(lua_State* L) {
    return catchexcept(L, [&] {
        TrackerRef& t = checkTracker(L, 1, "path");
        const auto& list = t.lm->model->trackerPath(t.id);
        lua_createtable(L, static_cast<int>(list.size()), 0);
        for (std::size_t i = 0; i < list.size(); ++i) {
            lua_createtable(L, 3, 0);
            lua_pushnumber(L, list[i].time);
            lua_rawseti(L, -2, 1);
            lua_pushnumber(L, list[i].pos.x());
            lua_rawseti(L, -2, 2);
            lua_pushnumber(L, list[i].pos.y());
            lua_rawseti(L, -2, 3);
            lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
        }
        return 1;
    });
}

int w_stop(lua_State* L) {
    return catchexcept(L, [&] {
        TrackerRef& t = checkTracker(L, 1, "stop");
        t.lm->model->stopTracker(t.id);
        return 0;
    });
}

int w_eq(lua_State* L) {
    const TrackerRef* a = testTracker(L, 1);
    const TrackerRef* b = testTracker(L, 2);
    lua_pushboolean(L, a && b && a->lm == b->lm && a->id == b->id);
    return 1;
}

int w_tostring(lua_State* L) {
    return catchexcept(L, [&] {
        const TrackerRef* t = testTracker(L, 1);
        if (!t || !t->lm->model || t->id > static_cast<int>(t->lm->model->trackerCount())) {
            lua_pushfstring(L, "tracker %d (cleared)", t ? t->id : 0);
            return 1;
        }
        const TrackerStatus s = t->lm->model->trackerStatus(t->id);
        lua_pushfstring(L, "tracker %d (%s, %d samples)", t->id, trackerStateName(s.state),
                        static_cast<int>(s.samples));
        return 1;
    });
}

const luaL_Reg kTrackerObjectMethods[] = {
    {"status", w_status},     {"impacts", w_impacts}, {"crossings", w_crossings},
    {"envelope", w_envelope}, {"path", w_path},       {"stop", w_stop},
    {nullptr, nullptr},
};

}  // namespace

extern const luaL_Reg kTrackerMethods[] = {
    {"track", w_track},
    {"trackers", w_trackers},
    {"clear_trackers", w_clear_trackers},
    {nullptr, nullptr},
};

void openTracker(lua_State* L) {
    registerRefType(L, kTrackerType, kTrackerObjectMethods, w_index, w_newindex, w_eq, w_tostring);
}

}  // namespace talus::lua
