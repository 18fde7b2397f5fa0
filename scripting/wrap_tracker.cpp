// SPDX-License-Identifier: MIT
// Trackers from Lua (docs/lua-api.md, "Trackers"): m:track(body, {...}), m:trackers(),
// m:clear_trackers(), and the tracker userdata (an id and its model) whose methods read the
// records the engine kept. A tracker's on_event function lives in the model's user-value table
// (key "trackers", by id), so it never keeps the model alive.
#include <cmath>
#include <limits>
#include <string>

#include "field_accessors.hpp"
#include "lua_bindings.hpp"
#include "talus/errors.hpp"

namespace talus::lua {

namespace {

struct TrackerRef {
    LuaModel* lm;
    int id;
};

constexpr const char* kHandlersKey = "trackers";  // in the model's user-value table

const Option kTrackOptionRows[] = {
    {"impacts", "boolean|\"walls\"|\"bodies\"|\"any\"|talus.TrackImpacts",
     "record the body's impacts (true: with anything)"},
    {"lines", "talus.TrackLine[]", "lines whose crossings are recorded"},
    {"rest", "talus.TrackRest", "the tracker ends (\"rest\") once the body is slow for a time"},
    {"region", "talus.TrackRegion", "the tracker ends (\"exit\") once the centre is outside"},
    {"end_time", "number", "the tracker ends (\"time\") at this time [s]"},
    {"envelope", "talus.TrackEnvelope", "the greatest height and energy per bin of x"},
    {"path", "integer", "keep the centre every `path` samples"},
    {"on_event", "fun(tr: talus.Tracker, ev: table)",
     "called at a crossing (event = true) and at the end"},
};
const OptionTable kTrackOptions = {"talus.TrackOptions", "m:track(body, {...})", kTrackOptionRows};

const Option kTrackImpactRows[] = {
    {"with", "\"walls\"|\"bodies\"|\"any\"", "what the impacts are with (default any)"},
    {"min_speed", "number", "smallest approach speed recorded [m/s] (default 0)"},
};
const OptionTable kTrackImpacts = {"talus.TrackImpacts", "m:track{impacts = {...}}",
                                   kTrackImpactRows};

const Option kTrackLineRows[] = {
    {"from", "talus.Vec", "the line's start [m]", true},
    {"to", "talus.Vec", "the line's end [m]; crossings from its left to its right count", true},
    {"event", "boolean", "deliver each crossing to on_event during the step"},
};
const OptionTable kTrackLine = {"talus.TrackLine", "one line of m:track{lines = {...}}",
                                kTrackLineRows};

const Option kTrackRestRows[] = {
    {"energy", "number", "kinetic energy below this [J] (or speed)"},
    {"speed", "number", "centre speed below this [m/s] (or energy)"},
    {"time", "number", "for this long [s] (default 0)"},
};
const OptionTable kTrackRest = {"talus.TrackRest", "m:track{rest = {...}}", kTrackRestRows};

const Option kTrackRegionRows[] = {
    {"lo", "talus.Vec", "the lower left corner [m] (math.huge allowed)", true},
    {"hi", "talus.Vec", "the upper right corner [m] (math.huge allowed)", true},
};
const OptionTable kTrackRegion = {"talus.TrackRegion", "m:track{region = {...}}", kTrackRegionRows};

const Option kTrackEnvelopeRows[] = {
    {"ground", "talus.Vec[]", "the ground polyline {{x, y}, ...}, x not decreasing", true},
    {"x0", "number", "the first bin's left edge [m]", true},
    {"dx", "number", "the bins' width [m]", true},
    {"bins", "integer", "the number of bins, 1..1e7", true},
};
const OptionTable kTrackEnvelope = {"talus.TrackEnvelope", "m:track{envelope = {...}}",
                                    kTrackEnvelopeRows};

void pushTracker(lua_State* L, int model_index, int id);  // with the tracker object, below

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
        const Options io(L, at, "track: impacts", kTrackImpacts);
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
        const Options lo(L, -1, what, kTrackLine);
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
        const Options ro(L, -1, "track: rest", kTrackRest);
        d.rest_energy = ro.number("energy", kNotSet);
        d.rest_speed = ro.number("speed", kNotSet);
        if (!ro.has("energy") && !ro.has("speed"))
            throw ScriptError("track: rest needs energy = J or speed = m/s (and time = s)");
        d.rest_time = ro.number("time", 0.0);
        lua_pop(L, 1);
    }
    if (o.has("region")) {
        o.push("region");
        const Options ro(L, -1, "track: region", kTrackRegion);
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
        const Options eo(L, -1, "track: envelope", kTrackEnvelope);
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
    setNumber(L, "approach", imp.approach);
    pushVec(L, imp.point);
    lua_setfield(L, -2, "point");
    if (imp.wall.valid()) {
        pushWall(L, model_index, imp.wall);
        lua_setfield(L, -2, "wall");
        setInteger(L, "segment", imp.segment + 1);
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
    setBoolean(L, "ended", imp.ended);
    if (imp.closed) pushState(L, imp.end, "_end");
}

void pushCrossing(lua_State* L, const TrackedCrossing& c) {
    lua_createtable(L, 0, 7);
    setInteger(L, "line", c.line + 1);
    setNumber(L, "t", c.time);
    pushVec(L, c.pos);
    lua_setfield(L, -2, "pos");
    pushVec(L, c.vel);
    lua_setfield(L, -2, "vel");
    setNumber(L, "spin", c.spin);
    setNumber(L, "ke_trans", c.ke_trans);
    setNumber(L, "ke_rot", c.ke_rot);
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
        setInteger(L, "line", ev.line + 1);
        // The crossing's record: the last one (it was just added).
        const auto& cs = lm.model->trackerCrossings(ev.tracker);
        if (!cs.empty()) {
            pushCrossing(L, cs.back());
            lua_setfield(L, -2, "crossing");
        }
    } else {
        lua_pushliteral(L, "end");
        lua_setfield(L, -2, "kind");
        setString(L, "state", trackerStateName(ev.state));
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
        const Options o(L, 3, "track", kTrackOptions, true);
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

TrackerRef& tracker(void* self) { return *static_cast<TrackerRef*>(self); }
TrackerStatus status(void* self) {
    return tracker(self).lm->model->trackerStatus(tracker(self).id);
}

const Field kTrackerFields[] = {
    {"id", "integer", "the tracker's number",
     [](lua_State* L, void* self) { lua_pushinteger(L, tracker(self).id); }},
    {"state", "string", "\"tracking\", \"rest\", \"exit\", \"time\", \"deleted\" or \"stopped\"",
     [](lua_State* L, void* self) { lua_pushstring(L, trackerStateName(status(self).state)); }},
    {"body", "talus.Ball|talus.Clump", "the ball or clump it follows",
     [](lua_State* L, void* self) {
         const TrackerStatus s = status(self);
         lua_getiuservalue(L, 1, 1);
         if (s.clump.valid())
             pushClump(L, -1, s.clump);
         else
             pushBall(L, -1, s.ball);
         lua_remove(L, -2);
     }},
    {"samples", "integer", "the samples taken",
     [](lua_State* L, void* self) {
         lua_pushinteger(L, static_cast<lua_Integer>(status(self).samples));
     }},
};

int w_status(lua_State* L);
int w_impacts(lua_State* L);
int w_crossings(lua_State* L);
int w_envelope(lua_State* L);
int w_path(lua_State* L);
constexpr char kStop[] = "stop";

const Method kTrackerObjectMethods[] = {
    {"status", w_status, "the last sample: {state, samples, t, pos, vel, spin, rest_since}", "",
     "table"},
    {"impacts", w_impacts, "the impacts recorded, each the body at its start and end", "",
     "table[]"},
    {"crossings", w_crossings, "the line crossings, {line, t, pos, vel, spin, ke_trans, ke_rot}",
     "", "table[]"},
    {"envelope", w_envelope, "{height = {[k] = m}, energy = {[k] = J}}: the bins the centre was in",
     "", "table"},
    {"path", w_path, "the centre's path, {{t, x, y}, ...}", "", "number[][]"},
    {"stop", fields::actMethod<TrackerRef, &Model::stopTracker, kStop>,
     "ends the tracker (\"stopped\")", "", ""},
};

void describe(lua_State* L, void* self) {
    const TrackerRef& t = tracker(self);
    if (!t.lm->model || t.id > static_cast<int>(t.lm->model->trackerCount())) {
        lua_pushfstring(L, "tracker %d (cleared)", t.id);
        return;
    }
    const TrackerStatus s = t.lm->model->trackerStatus(t.id);
    lua_pushfstring(L, "tracker %d (%s, %d samples)", t.id, trackerStateName(s.state),
                    static_cast<int>(s.samples));
}

const ObjectType kTrackerObject = {
    kTrackerType,   "tracker",
    "tr",           "follows one body for the engine (m:track)",
    kTrackerFields, kTrackerObjectMethods,
    describe,       "it is set by m:track{...}",
};

TrackerRef& checkTracker(lua_State* L, int index, const char* fn) {
    return checkObject<TrackerRef>(L, index, kTrackerObject, fn);
}

void pushTracker(lua_State* L, int model_index, int id) {
    newObject<TrackerRef>(L, model_index, kTrackerObject)->id = id;
}

int w_status(lua_State* L) {
    return catchexcept(L, [&] {
        TrackerRef& t = checkTracker(L, 1, "status");
        const TrackerStatus s = t.lm->model->trackerStatus(t.id);
        lua_createtable(L, 0, 7);
        setString(L, "state", trackerStateName(s.state));
        setInteger(L, "samples", static_cast<lua_Integer>(s.samples));
        pushState(L, s.last, "");
        if (!std::isnan(s.rest_since)) {
            setNumber(L, "rest_since", s.rest_since);
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

const Method kTrackerMethods[] = {
    {"track", w_track, "a tracker that follows a ball or a clump for the engine",
     "body: talus.Ball|talus.Clump, options?: talus.TrackOptions", "talus.Tracker"},
    {"trackers", w_trackers, "every tracker of the model", "", "talus.Tracker[]"},
    {"clear_trackers", w_clear_trackers, "forgets every tracker (not from inside on_event)", "",
     ""},
};

const ObjectType* const kTypes[] = {&kTrackerObject};
const OptionTable* const kOptionTables[] = {&kTrackOptions, &kTrackImpacts, &kTrackLine,
                                            &kTrackRest,    &kTrackRegion,  &kTrackEnvelope};

}  // namespace

extern const Binding kTrackerBinding = {"trackers", kTrackerMethods, {}, kTypes, kOptionTables, {}};

}  // namespace talus::lua
