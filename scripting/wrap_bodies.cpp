// SPDX-License-Identifier: MIT
// The model's body methods: m:ball{...}, m:wall{...}, the iterators m:balls(), m:walls(),
// m:contacts() and the counts. The ball, wall and contact objects are in wrap_ball.cpp,
// wrap_wall.cpp, wrap_contact.cpp.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"
#include "talus/plugin_registry.hpp"

namespace talus::lua {

namespace {

// ------------------------------------------------------------------ bodies

std::vector<std::string> groupsOption(const Options& o) {
    if (o.has("group") && o.has("groups"))
        throw ScriptError(o.what() + ": give 'group' or 'groups', not both");
    return o.has("group") ? o.strings("group") : o.strings("groups");
}

double optionalProp(const Options& o, const char* key) { return o.number(key, kNotSet); }

int w_ball(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "ball");
        const Options o(L, 2, "ball",
                        {"pos", "radius", "density", "mass", "inertia", "vel", "spin", "angle",
                         "group", "groups", "fix", "kn", "ks", "fric"});
        BallDef d;
        if (!o.has("pos")) throw ScriptError("ball: 'pos' is required");
        if (!o.has("radius")) throw ScriptError("ball: 'radius' is required");
        d.pos = o.vec("pos", d.pos);
        d.radius = o.number("radius", 0.0);
        if (o.has("density") && o.has("mass"))
            throw ScriptError("ball: give 'density' or 'mass', not both");
        if (!o.has("density") && !o.has("mass"))
            throw ScriptError("ball: 'density' or 'mass' is required");
        d.density = o.number("density", 0.0);
        d.mass = o.number("mass", kNotSet);
        d.inertia = o.number("inertia", kNotSet);
        d.vel = o.vec("vel", d.vel);
        d.spin = o.number("spin", 0.0);
        d.angle = o.number("angle", 0.0);
        d.groups = groupsOption(o);
        if (o.has("fix")) {
            if (o.push("fix") == LUA_TBOOLEAN) {
                d.fixity = lua_toboolean(L, -1) ? (kFixX | kFixY | kFixSpin) : 0;
                lua_pop(L, 1);
            } else {
                lua_pop(L, 1);
                for (const std::string& f : o.strings("fix")) {
                    if (f == "x")
                        d.fixity |= kFixX;
                    else if (f == "y")
                        d.fixity |= kFixY;
                    else if (f == "spin")
                        d.fixity |= kFixSpin;
                    else
                        throw ScriptError(
                            "ball: 'fix' entries must be one of \"x\", \"y\", "
                            "\"spin\" (got \"" +
                            f + "\")");
                }
            }
        }
        d.kn = optionalProp(o, "kn");
        d.ks = optionalProp(o, "ks");
        d.fric = optionalProp(o, "fric");
        const BallId id = lm.model->createBall(d);
        warnImplausibleFriction(&lm, "ball", {{"fric", d.fric}});
        pushBall(L, 1, id);
        return 1;
    });
}

int w_wall(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "wall");
        const Options o(
            L, 2, "wall",
            {"points", "closed", "vel", "spin", "center", "group", "groups", "kn", "ks", "fric"});
        WallDef d;
        if (o.push("points") != LUA_TTABLE) {
            const std::string got = typeName(L, -1);
            lua_pop(L, 1);
            throw ScriptError("wall: 'points' must be a list of vectors {{x, y}, ...} (got " + got +
                              ")");
        }
        const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, -1));
        for (lua_Integer i = 1; i <= n; ++i) {
            lua_rawgeti(L, -1, i);
            try {
                d.points.push_back(toVec(L, -1, "wall: point " + std::to_string(i)));
            } catch (...) {
                lua_pop(L, 2);
                throw;
            }
            lua_pop(L, 1);
        }
        lua_pop(L, 1);
        d.closed = o.boolean("closed", false);
        d.vel = o.vec("vel", d.vel);
        d.spin = o.number("spin", 0.0);
        d.center = o.vec("center", d.center);
        d.groups = groupsOption(o);
        d.kn = optionalProp(o, "kn");
        d.ks = optionalProp(o, "ks");
        d.fric = optionalProp(o, "fric");
        const WallId id = lm.model->createWall(d);
        warnImplausibleFriction(&lm, "wall", {{"fric", d.fric}});
        pushWall(L, 1, id);
        return 1;
    });
}

// ------------------------------------------------------------------ iterators

lua_Integer packBall(BallId id) {
    return static_cast<lua_Integer>((uint64_t(id.index) << 32) | id.generation);
}
BallId unpackBall(lua_Integer v) {
    const auto u = static_cast<uint64_t>(v);
    return BallId{static_cast<uint32_t>(u >> 32), static_cast<uint32_t>(u & 0xffffffffu)};
}

/// Iterator state in upvalues: 1 = model userdata, 2 = list of packed ids, 3 = position.
template <class Push>
int iterate(lua_State* L, const Push& pushItem) {
    return catchexcept(L, [&] {
        auto* lm = static_cast<LuaModel*>(lua_touserdata(L, lua_upvalueindex(1)));
        if (!lm || !lm->model) throw ScriptError("iterator: the model was closed");
        lua_Integer pos = lua_tointeger(L, lua_upvalueindex(3));
        const auto n = static_cast<lua_Integer>(lua_rawlen(L, lua_upvalueindex(2)));
        while (pos < n) {
            ++pos;
            lua_rawgeti(L, lua_upvalueindex(2), pos);
            const lua_Integer v = lua_tointeger(L, -1);
            lua_pop(L, 1);
            if (pushItem(*lm, v)) {
                lua_pushinteger(L, pos);
                lua_replace(L, lua_upvalueindex(3));
                return 1;
            }
        }
        lua_pushinteger(L, pos);
        lua_replace(L, lua_upvalueindex(3));
        return 0;
    });
}

int ballIterator(lua_State* L) {
    return iterate(L, [&](LuaModel& lm, lua_Integer v) {
        const BallId id = unpackBall(v);
        if (!lm.model->isAlive(id)) return false;  // deleted during the loop
        pushBall(L, lua_upvalueindex(1), id);
        return true;
    });
}

int wallIterator(lua_State* L) {
    return iterate(L, [&](LuaModel&, lua_Integer v) {
        pushWall(L, lua_upvalueindex(1),
                 WallId{static_cast<uint32_t>(static_cast<uint64_t>(v) >> 32),
                        static_cast<uint32_t>(static_cast<uint64_t>(v) & 0xffffffffu)});
        return true;
    });
}

int contactIterator(lua_State* L) {
    return iterate(L, [&](LuaModel& lm, lua_Integer v) {
        ContactInfo info;
        if (!lm.model->findContact(ContactKey{static_cast<uint64_t>(v)}, info)) return false;
        pushContact(L, lua_upvalueindex(1), ContactKey{static_cast<uint64_t>(v)});
        return true;
    });
}

/// __index and __len of an iterator: it is not a list, say what to use instead (upvalue 1:
/// the method's name, "balls").
int iteratorMisuse(lua_State* L) {
    return catchexcept(L, [&]() -> int {
        const std::string fn = lua_tostring(L, lua_upvalueindex(1));
        const std::string what = fn == "balls" ? "ball" : fn == "walls" ? "wall" : "contact";
        std::string instead;
        if (fn == "balls")
            instead = "; a ball by its id: m:ball_by_id(id); their number: m:ball_count()";
        else if (fn == "walls")
            instead = "; their number: m:wall_count()";
        else
            instead = "; their number: m:contact_count()";
        throw ScriptError(fn + "(): m:" + fn + "() is an iterator for a for loop (for " +
                          what.substr(0, 1) + " in m:" + fn + "() do ... end), not a list" +
                          instead);
    });
}

/// Pushes the iterator over `ids` (already packed) for the model at index 1: a table callable
/// as the iterator function (a C closure over the model, the ids and the position), whose
/// indexing is an error that names what to use instead (m:balls()[3] would otherwise say
/// "attempt to index a function value").
void pushIterator(lua_State* L, lua_CFunction fn, const std::vector<lua_Integer>& ids,
                  const char* name) {
    lua_createtable(L, 0, 0);
    lua_createtable(L, 0, 4);
    lua_pushvalue(L, 1);
    lua_createtable(L, static_cast<int>(ids.size()), 0);
    for (std::size_t i = 0; i < ids.size(); ++i) {
        lua_pushinteger(L, ids[i]);
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_pushinteger(L, 0);
    lua_pushcclosure(L, fn, 3);
    lua_setfield(L, -2, "__call");
    lua_pushstring(L, name);
    lua_pushcclosure(L, iteratorMisuse, 1);
    lua_pushvalue(L, -1);
    lua_setfield(L, -3, "__index");
    lua_setfield(L, -2, "__len");
    lua_pushfstring(L, "talus.%s iterator", name);
    lua_setfield(L, -2, "__name");
    lua_setmetatable(L, -2);
}

int w_ball_by_id(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "ball_by_id");
        const long long id = toInteger(L, 2, "ball_by_id: id");
        Model& m = *lm.model;
        const auto find = [&](bool refresh) -> BallId {
            if (refresh) {
                lm.ball_slots.clear();
                for (const BallId b : m.ballIds()) {
                    if (b.index >= lm.ball_slots.size()) lm.ball_slots.resize(b.index + 1);
                    lm.ball_slots[b.index] = b;
                }
            }
            if (id < 1 || static_cast<unsigned long long>(id) >= lm.ball_slots.size()) return {};
            const BallId b = lm.ball_slots[static_cast<std::size_t>(id)];
            return b.valid() && m.isAlive(b) ? b : BallId{};
        };
        // The cached handle of a live ball is that ball (a deleted ball's handle is dead even
        // when its id went to a new ball); a miss refreshes the cache once.
        BallId b = find(false);
        if (!b.valid()) b = find(true);
        if (b.valid())
            pushBall(L, 1, b);
        else
            lua_pushnil(L);
        return 1;
    });
}

int w_balls(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "balls");
        const Options o(L, 2, "balls", {"group"}, true);
        const std::string group = o.string("group", "");
        Model& m = *lm.model;
        if (!group.empty() && m.groupIndex(group, false) < 0)
            throw ScriptError(
                "balls: no group named '" + group + "' (groups: " +
                (m.groupNames().empty() ? std::string("none") : joinNames(m.groupNames())) + ")");
        std::vector<lua_Integer> ids;
        for (const BallId id : m.ballIds()) {
            if (!group.empty()) {
                const auto g = m.ballGroups(id);
                if (std::find(g.begin(), g.end(), group) == g.end()) continue;
            }
            ids.push_back(packBall(id));
        }
        pushIterator(L, ballIterator, ids, "balls");
        return 1;
    });
}

int w_walls(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "walls");
        std::vector<lua_Integer> ids;
        for (const WallId id : lm.model->wallIds())
            ids.push_back(static_cast<lua_Integer>((uint64_t(id.index) << 32) | id.generation));
        pushIterator(L, wallIterator, ids, "walls");
        return 1;
    });
}

int w_contacts(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "contacts");
        const Options o(L, 2, "contacts", {"model", "active", "ball"}, true);
        const std::string model = lower(o.string("model", ""));
        const bool active = o.boolean("active", true);
        BallId ball;
        if (o.has("ball")) {
            o.push("ball");
            BallRef* b = testBall(L, -1);
            lua_pop(L, 1);
            if (!b) throw ScriptError("contacts: 'ball' must be a ball");
            ball = b->id;
        }
        std::vector<lua_Integer> keys;
        for (const ContactInfo& c : lm.model->contacts(active)) {
            if (!model.empty() && lower(c.model) != model) continue;
            if (ball.valid() && c.ball1 != ball && c.ball2 != ball) continue;
            keys.push_back(static_cast<lua_Integer>(c.key.value));
        }
        pushIterator(L, contactIterator, keys, "contacts");
        return 1;
    });
}

int w_ball_count(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "ball_count");
        lua_pushinteger(L, static_cast<lua_Integer>(lm.model->ballCount()));
        return 1;
    });
}

int w_wall_count(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "wall_count");
        lua_pushinteger(L, static_cast<lua_Integer>(lm.model->wallCount()));
        return 1;
    });
}

int w_contact_count(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "contact_count");
        const Options o(L, 2, "contact_count", {"active"}, true);
        lua_pushinteger(
            L, static_cast<lua_Integer>(lm.model->contactCount(o.boolean("active", true))));
        return 1;
    });
}

}  // namespace

extern const luaL_Reg kModelBodyMethods[] = {
    {"ball", w_ball},
    {"wall", w_wall},
    {"balls", w_balls},
    {"ball_by_id", w_ball_by_id},
    {"walls", w_walls},
    {"contacts", w_contacts},
    {"ball_count", w_ball_count},
    {"wall_count", w_wall_count},
    {"contact_count", w_contact_count},
    {nullptr, nullptr},
};

}  // namespace talus::lua
