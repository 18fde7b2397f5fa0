// SPDX-License-Identifier: MIT
// Clumps from Lua (docs/lua-api.md, "Clumps"): m:clump{...}, m:clump_template{...},
// m:clumps{group =}, m:clump_count(), and the clump userdata (an id and its model; fields read
// and write the engine state by id, so a deleted clump gives "clump 3 was deleted (stale id)").
#include <algorithm>
#include <cmath>
#include <cstring>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"

namespace talus::lua {

ClumpRef* testClump(lua_State* L, int index) {
    return static_cast<ClumpRef*>(testUserdata(L, index, kClumpType));
}

namespace {

ClumpRef& checkClump(lua_State* L, int index, const char* fn) {
    ClumpRef* c = testClump(L, index);
    if (!c)
        throw ScriptError(std::string("clump: call it as a method, c:") + fn +
                          "(...) (the first argument is a " + typeName(L, index) +
                          ", not a clump)");
    if (!c->lm->model) throw ScriptError("clump: its model was closed");
    return *c;
}

uint8_t toFixity(lua_State* L, int index, const std::string& what) {
    if (lua_type(L, index) == LUA_TBOOLEAN)
        return lua_toboolean(L, index) ? uint8_t(kFixX | kFixY | kFixSpin) : uint8_t(0);
    if (lua_isnil(L, index)) return 0;
    if (lua_type(L, index) != LUA_TTABLE)
        throw ScriptError(what + " must be a list such as {\"x\", \"spin\"}, or true/false");
    uint8_t fix = 0;
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, index));
    for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, index, i);
        int which = -1;
        try {
            which = toEnum(L, -1, what + " entry " + std::to_string(i), {"x", "y", "spin"});
        } catch (...) {
            lua_pop(L, 1);
            throw;
        }
        lua_pop(L, 1);
        fix |= which == 0 ? kFixX : which == 1 ? kFixY : kFixSpin;
    }
    return fix;
}

void pushFixity(lua_State* L, uint8_t fix) {
    std::vector<std::string> names;
    if (fix & kFixX) names.push_back("x");
    if (fix & kFixY) names.push_back("y");
    if (fix & kFixSpin) names.push_back("spin");
    pushStringList(L, names);
}

void pushOptional(lua_State* L, double v) {
    if (std::isnan(v))
        lua_pushnil(L);
    else
        lua_pushnumber(L, v);
}

/// Reads {{x, y, r}, ...} at the top of the stack (`what` names the option in errors).
std::vector<Pebble> readPebbles(lua_State* L, int index, const std::string& what) {
    if (lua_type(L, index) != LUA_TTABLE)
        throw ScriptError(what + " must be a list of pebbles {{x, y, r}, ...} (got " +
                          typeName(L, index) + ")");
    std::vector<Pebble> out;
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, index));
    if (n == 0) throw ScriptError(what + " is empty: a clump needs at least one pebble");
    for (lua_Integer i = 1; i <= n; ++i) {
        const std::string item = what + " " + std::to_string(i);
        lua_rawgeti(L, index, i);
        if (lua_type(L, -1) != LUA_TTABLE || lua_rawlen(L, -1) != 3) {
            const std::string got = typeName(L, -1);
            lua_pop(L, 1);
            throw ScriptError(item + " must be {x, y, r} (got " + got + ")");
        }
        double v[3];
        for (int k = 0; k < 3; ++k) {
            lua_rawgeti(L, -1, k + 1);
            try {
                v[k] = toNumber(L, -1, item);
            } catch (...) {
                lua_pop(L, 2);
                throw;
            }
            lua_pop(L, 1);
        }
        lua_pop(L, 1);
        out.push_back(Pebble{Vec2(v[0], v[1]), v[2]});
    }
    return out;
}

int massModeOption(const Options& o) {
    return o.choice("mass_mode", 0, {"union", "sum", "direct"});
}
ClumpMassMode toMode(int k) {
    return k == 1 ? ClumpMassMode::PlainSum : k == 2 ? ClumpMassMode::Direct : ClumpMassMode::Union;
}

std::vector<std::string> groupsOption(const Options& o) {
    if (o.has("group") && o.has("groups"))
        throw ScriptError(o.what() + ": give 'group' or 'groups', not both");
    return o.has("group") ? o.strings("group") : o.strings("groups");
}

// ------------------------------------------------------------------ model methods

int w_clump(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "clump");
        const Options o(
            L, 2, "clump",
            {"pebbles", "template", "balls", "pos", "angle", "scale", "density", "mass", "inertia",
             "centroid", "mass_mode", "vel", "spin", "fix", "group", "groups", "kn", "ks", "fric"});
        ClumpDef d;
        const int sources = o.has("pebbles") + o.has("template") + o.has("balls");
        if (sources != 1)
            throw ScriptError("clump: give exactly one of 'pebbles', 'template' or 'balls'");
        std::vector<BallId> balls;
        if (o.has("balls")) {
            for (const char* k : {"pos", "angle", "scale"})
                if (o.has(k))
                    throw ScriptError(std::string("clump: '") + k +
                                      "' does not go with 'balls' (the balls stay where they are)");
            if (o.push("balls") != LUA_TTABLE) {
                const std::string got = typeName(L, -1);
                lua_pop(L, 1);
                throw ScriptError("clump: 'balls' must be a list of balls (got " + got + ")");
            }
            const auto n = static_cast<lua_Integer>(lua_rawlen(L, -1));
            // Said here: the density check below would otherwise answer an empty list.
            if (n == 0) {
                lua_pop(L, 1);
                throw ScriptError("clump: 'balls' is empty: a clump needs at least one ball");
            }
            for (lua_Integer i = 1; i <= n; ++i) {
                lua_rawgeti(L, -1, i);
                BallRef* b = testBall(L, -1);
                lua_pop(L, 1);
                if (!b || b->lm != &lm) {
                    lua_pop(L, 1);
                    throw ScriptError("clump: 'balls' entry " + std::to_string(i) +
                                      " is not a ball of this model");
                }
                balls.push_back(b->id);
            }
            lua_pop(L, 1);
        } else if (o.has("pebbles")) {
            o.push("pebbles");
            try {
                d.pebbles = readPebbles(L, lua_gettop(L), "clump: pebble");
            } catch (...) {
                lua_pop(L, 1);
                throw;
            }
            lua_pop(L, 1);
        } else {
            const int t = o.push("template");
            lua_Integer id = 0;
            if (t == LUA_TTABLE) {
                lua_getfield(L, -1, "id");
                id = lua_tointeger(L, -1);
                lua_pop(L, 1);
            } else if (t == LUA_TNUMBER) {
                id = lua_tointeger(L, -1);
            }
            lua_pop(L, 1);
            if (id <= 0)
                throw ScriptError("clump: 'template' must be a template from m:clump_template{}");
            d.template_id = static_cast<int>(id);
        }
        if (o.has("pos")) d.pos = o.vec("pos", d.pos);
        d.angle = o.number("angle", 0.0);
        d.scale = o.number("scale", 1.0);
        d.mass_mode = toMode(massModeOption(o));
        if (o.has("mass") && o.has("density"))
            throw ScriptError("clump: give 'density' or 'mass' (direct mode), not both");
        d.density = o.number("density", kNotSet);
        d.mass = o.number("mass", kNotSet);
        d.inertia = o.number("inertia", kNotSet);
        if (o.has("centroid")) d.centroid = o.vec("centroid", d.centroid);
        if (d.mass_mode != ClumpMassMode::Direct && !o.has("density") && !o.has("mass") &&
            !d.template_id && balls.empty())
            throw ScriptError("clump: 'density' (or direct 'mass' and 'inertia') is required");
        d.vel = o.vec("vel", d.vel);
        d.spin = o.number("spin", 0.0);
        if (o.has("fix")) {
            o.push("fix");
            try {
                d.fixity = toFixity(L, -1, "clump: 'fix'");
            } catch (...) {
                lua_pop(L, 1);
                throw;
            }
            lua_pop(L, 1);
        }
        d.groups = groupsOption(o);
        d.kn = o.number("kn", kNotSet);
        d.ks = o.number("ks", kNotSet);
        d.fric = o.number("fric", kNotSet);
        pushClump(
            L, 1,
            balls.empty() ? lm.model->createClump(d) : lm.model->createClumpFromBalls(balls, d));
        warnImplausibleFriction(&lm, "clump", {{"fric", d.fric}});
        return 1;
    });
}

int w_clump_template(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "clump_template");
        const Options o(L, 2, "clump_template", {"pebbles", "mass_mode"});
        if (!o.has("pebbles")) throw ScriptError("clump_template: 'pebbles' is required");
        o.push("pebbles");
        std::vector<Pebble> peb;
        try {
            peb = readPebbles(L, lua_gettop(L), "clump_template: pebble");
        } catch (...) {
            lua_pop(L, 1);
            throw;
        }
        lua_pop(L, 1);
        const int id = lm.model->defineClumpTemplate(peb, toMode(massModeOption(o)));
        const ClumpTemplate& t = lm.model->clumpTemplate(id);
        // A plain table: the id m:clump{template = t} uses, and the mass properties per unit
        // density (unit thickness) in the template's frame.
        lua_createtable(L, 0, 5);
        lua_pushinteger(L, id);
        lua_setfield(L, -2, "id");
        lua_pushnumber(L, t.props.area);
        lua_setfield(L, -2, "area");
        pushVec(L, t.props.centroid);
        lua_setfield(L, -2, "centroid");
        lua_pushnumber(L, t.props.polar_moment);
        lua_setfield(L, -2, "inertia");
        lua_pushinteger(L, static_cast<lua_Integer>(peb.size()));
        lua_setfield(L, -2, "pebble_count");
        return 1;
    });
}

int clumpIterator(lua_State* L) {
    return catchexcept(L, [&] {
        auto* lm = static_cast<LuaModel*>(lua_touserdata(L, lua_upvalueindex(1)));
        if (!lm || !lm->model) throw ScriptError("iterator: the model was closed");
        lua_Integer pos = lua_tointeger(L, lua_upvalueindex(3));
        const auto n = static_cast<lua_Integer>(lua_rawlen(L, lua_upvalueindex(2)));
        while (pos < n) {
            ++pos;
            lua_rawgeti(L, lua_upvalueindex(2), pos);
            const auto v = static_cast<uint64_t>(lua_tointeger(L, -1));
            lua_pop(L, 1);
            const ClumpId id{static_cast<uint32_t>(v >> 32), static_cast<uint32_t>(v)};
            if (!lm->model->isAlive(id)) continue;  // deleted during the loop
            lua_pushinteger(L, pos);
            lua_replace(L, lua_upvalueindex(3));
            pushClump(L, lua_upvalueindex(1), id);
            return 1;
        }
        lua_pushinteger(L, pos);
        lua_replace(L, lua_upvalueindex(3));
        return 0;
    });
}

int w_clumps(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "clumps");
        const Options o(L, 2, "clumps", {"group"}, true);
        const std::string group = o.string("group", "");
        Model& m = *lm.model;
        if (!group.empty() && m.groupIndex(group, false) < 0)
            throw ScriptError(
                "clumps: no group named '" + group + "' (groups: " +
                (m.groupNames().empty() ? std::string("none") : joinNames(m.groupNames())) + ")");
        lua_pushvalue(L, 1);
        lua_newtable(L);
        lua_Integer k = 0;
        for (const ClumpId id : m.clumpIds()) {
            if (!group.empty()) {
                const auto g = m.clumpGroups(id);
                if (std::find(g.begin(), g.end(), group) == g.end()) continue;
            }
            lua_pushinteger(L,
                            static_cast<lua_Integer>((uint64_t(id.index) << 32) | id.generation));
            lua_rawseti(L, -2, ++k);
        }
        lua_pushinteger(L, 0);
        lua_pushcclosure(L, clumpIterator, 3);
        return 1;
    });
}

int w_clump_count(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "clump_count");
        lua_pushinteger(L, static_cast<lua_Integer>(lm.model->clumpCount()));
        return 1;
    });
}

// ------------------------------------------------------------------ the clump object

struct FieldInfo {
    const char* name;
    bool writable;
};
const FieldInfo kFields[] = {
    {"id", false},   {"pos", true},      {"vel", true},      {"spin", true},   {"angle", true},
    {"mass", false}, {"inertia", false}, {"density", false}, {"force", false}, {"moment", false},
    {"fapp", true},  {"mapp", true},     {"fix", true},      {"kn", true},     {"ks", true},
    {"fric", true},  {"groups", false},  {"alive", false},
};
const char* const kMethods[] = {"set", "pebbles", "delete", "release", "add_group"};

std::string knownFields(bool writable_only) {
    std::vector<std::string> names;
    for (const FieldInfo& f : kFields)
        if (f.writable || !writable_only) names.push_back(f.name);
    if (!writable_only)
        for (const char* m : kMethods) names.push_back(std::string(m) + "()");
    return joinNames(names);
}
const FieldInfo* findField(const std::string& name) {
    for (const FieldInfo& f : kFields)
        if (name == f.name) return &f;
    return nullptr;
}

std::string fieldKey(lua_State* L, int index) {
    if (lua_type(L, index) != LUA_TSTRING)
        throw ScriptError("clump: field names are strings (got " + typeName(L, index) + ")");
    return lua_tostring(L, index);
}

void pushField(lua_State* L, const ClumpRef& c, const std::string& f) {
    Model& m = *c.lm->model;
    const ClumpId id = c.id;
    if (f == "alive") return lua_pushboolean(L, m.isAlive(id));
    if (f == "id") {
        (void)m.clumpMass(id);  // a deleted clump's id is an error like any other field
        return lua_pushinteger(L, id.index);
    }
    if (f == "pos") return pushVec(L, m.clumpPos(id));
    if (f == "vel") return pushVec(L, m.clumpVel(id));
    if (f == "spin") return lua_pushnumber(L, m.clumpSpin(id));
    if (f == "angle") return lua_pushnumber(L, m.clumpAngle(id));
    if (f == "mass") return lua_pushnumber(L, m.clumpMass(id));
    if (f == "inertia") return lua_pushnumber(L, m.clumpInertia(id));
    if (f == "density") return lua_pushnumber(L, m.clumpDensity(id));
    if (f == "force") return pushVec(L, m.clumpForce(id));
    if (f == "moment") return lua_pushnumber(L, m.clumpMoment(id));
    if (f == "fapp") return pushVec(L, m.clumpAppliedForce(id));
    if (f == "mapp") return lua_pushnumber(L, m.clumpAppliedMoment(id));
    if (f == "fix") return pushFixity(L, m.clumpFixity(id));
    if (f == "groups") return pushStringList(L, m.clumpGroups(id));
    if (f == "kn" || f == "ks" || f == "fric") return pushOptional(L, m.clumpContactProp(id, f));
}

void setField(lua_State* L, const ClumpRef& c, const std::string& name, int index) {
    const FieldInfo* info = findField(name);
    if (!info)
        throw ScriptError("clump: unknown field '" + name + "'" +
                          didYouMeanIn(name, knownFields(true)) +
                          " (writable: " + knownFields(true) + ")");
    if (!info->writable)
        throw ScriptError("clump: field '" + name +
                          "' is read-only (writable: " + knownFields(true) + ")");
    Model& m = *c.lm->model;
    const ClumpId id = c.id;
    const std::string what = "clump: '" + name + "'";
    if (name == "pos") return m.setClumpPos(id, toVec(L, index, what));
    if (name == "vel") return m.setClumpVel(id, toVec(L, index, what));
    if (name == "spin") return m.setClumpSpin(id, toNumber(L, index, what));
    if (name == "angle") return m.setClumpAngle(id, toNumber(L, index, what));
    if (name == "fapp") return m.setClumpAppliedForce(id, toVec(L, index, what));
    if (name == "mapp") return m.setClumpAppliedMoment(id, toNumber(L, index, what));
    if (name == "fix") return m.setClumpFixity(id, toFixity(L, index, what));
    // kn, ks, fric; nil removes the clump's own value (and its pebbles').
    const double v = lua_isnil(L, index) ? kNotSet : toNumber(L, index, what);
    m.setClumpContactProp(id, name, v);
    if (name == "fric") warnImplausibleFriction(c.lm, "clump", {{name, v}});
}

int w_index(lua_State* L) {
    return catchexcept(L, [&] {
        ClumpRef& c = checkClump(L, 1, "index");
        const std::string key = fieldKey(L, 2);
        for (const char* m : kMethods)
            if (key == m) {
                lua_getfield(L, lua_upvalueindex(1), m);
                return 1;
            }
        if (!findField(key))
            throw ScriptError("clump: unknown field '" + key + "'" +
                              didYouMeanIn(key, knownFields(false)) +
                              " (known: " + knownFields(false) + ")");
        pushField(L, c, key);
        return 1;
    });
}

int w_newindex(lua_State* L) {
    return catchexcept(L, [&] {
        ClumpRef& c = checkClump(L, 1, "newindex");
        setField(L, c, fieldKey(L, 2), 3);
        return 0;
    });
}

int w_set(lua_State* L) {
    return catchexcept(L, [&] {
        ClumpRef& c = checkClump(L, 1, "set");
        applyFields(L, 2, "clump: set{...}",
                    "clump: set{...} takes named fields (vel = {1, 0}, ...)",
                    [&](const std::string& key, int value) { setField(L, c, key, value); });
        return 0;
    });
}

int w_pebbles(lua_State* L) {
    return catchexcept(L, [&] {
        ClumpRef& c = checkClump(L, 1, "pebbles");
        const auto peb = c.lm->model->clumpPebbles(c.id);
        lua_createtable(L, static_cast<int>(peb.size()), 0);
        for (std::size_t i = 0; i < peb.size(); ++i) {
            lua_createtable(L, 0, 2);
            pushVec(L, peb[i].pos);
            lua_setfield(L, -2, "pos");
            lua_pushnumber(L, peb[i].radius);
            lua_setfield(L, -2, "radius");
            lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
        }
        return 1;
    });
}

int w_delete(lua_State* L) {
    return catchexcept(L, [&] {
        ClumpRef& c = checkClump(L, 1, "delete");
        c.lm->model->deleteClump(c.id);
        return 0;
    });
}

int w_release(lua_State* L) {
    return catchexcept(L, [&] {
        ClumpRef& c = checkClump(L, 1, "release");
        const auto balls = c.lm->model->releaseClump(c.id);
        lua_getiuservalue(L, 1, 1);  // the model userdata, for the ball userdata
        const int model_index = lua_gettop(L);
        lua_createtable(L, static_cast<int>(balls.size()), 0);
        for (std::size_t i = 0; i < balls.size(); ++i) {
            pushBall(L, model_index, balls[i]);
            lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
        }
        return 1;
    });
}

int w_add_group(lua_State* L) {
    return catchexcept(L, [&] {
        ClumpRef& c = checkClump(L, 1, "add_group");
        if (lua_type(L, 2) != LUA_TSTRING)
            throw ScriptError("clump: add_group(name) needs a group name (got " + typeName(L, 2) +
                              ")");
        c.lm->model->addClumpGroup(c.id, lua_tostring(L, 2));
        return 0;
    });
}

int w_eq(lua_State* L) {
    const ClumpRef* a = testClump(L, 1);
    const ClumpRef* b = testClump(L, 2);
    lua_pushboolean(L, a && b && a->lm == b->lm && a->id == b->id);
    return 1;
}

int w_tostring(lua_State* L) {
    return catchexcept(L, [&] {
        const ClumpRef* c = testClump(L, 1);
        if (!c || !c->lm->model || !c->lm->model->isAlive(c->id)) {
            lua_pushfstring(L, "clump %d (deleted)", c ? static_cast<int>(c->id.index) : 0);
            return 1;
        }
        const Vec2 p = c->lm->model->clumpPos(c->id);
        lua_pushfstring(L, "clump %d at (%f, %f)", static_cast<int>(c->id.index), p.x(), p.y());
        return 1;
    });
}

const luaL_Reg kClumpObjectMethods[] = {
    {"set", w_set},         {"pebbles", w_pebbles},     {"delete", w_delete},
    {"release", w_release}, {"add_group", w_add_group}, {nullptr, nullptr},
};

}  // namespace

extern const luaL_Reg kClumpMethods[] = {
    {"clump", w_clump},   {"clump_template", w_clump_template},
    {"clumps", w_clumps}, {"clump_count", w_clump_count},
    {nullptr, nullptr},
};

void pushClump(lua_State* L, int model_index, ClumpId id) {
    model_index = lua_absindex(L, model_index);
    auto* c = newRef<ClumpRef>(L, model_index, kClumpType);
    c->lm = static_cast<LuaModel*>(lua_touserdata(L, model_index));
    c->id = id;
}

void openClump(lua_State* L) {
    registerRefType(L, kClumpType, kClumpObjectMethods, w_index, w_newindex, w_eq, w_tostring);
}

}  // namespace talus::lua
