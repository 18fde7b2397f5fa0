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

const Option kBallOptionRows[] = {
    {"pos", "talus.Vec", "centre [m]", true},
    {"radius", "number", "[m], in [1e-12, 1e9]", true},
    {"density", "number", "[kg/m^3], > 0 (or mass)"},
    {"mass", "number", "[kg], > 0 (or density)"},
    {"inertia", "number", "moment of inertia [kg m^2] (default: from the mass mode)"},
    {"vel", "talus.Vec", "velocity [m/s] (default {0, 0})"},
    {"spin", "number", "angular velocity [rad/s], counter-clockwise positive (default 0)"},
    {"angle", "number", "orientation [rad] (default 0)"},
    {"group", "string|string[]", "a group name, or a list (or groups)"},
    {"groups", "string|string[]", "a list of group names (or group)"},
    {"fix", "string[]|boolean", "fixed components {\"x\", \"y\", \"spin\"}; true all"},
    {"kn", "number", "the ball's own normal stiffness [N/m], inherited by its contacts"},
    {"ks", "number", "the ball's own shear stiffness [N/m], inherited by its contacts"},
    {"fric", "number", "the ball's own friction coefficient, inherited by its contacts"},
};
const OptionTable kBallOptions = {"talus.BallDef", "m:ball{...}: a new ball", kBallOptionRows};

const Option kWallOptionRows[] = {
    {"points", "talus.Vec[]", "the chain's vertices {{x, y}, ...} [m], at least 2", true},
    {"closed", "boolean", "join the last point to the first (default false)"},
    {"vel", "talus.Vec", "translational velocity [m/s] (default {0, 0})"},
    {"spin", "number", "angular velocity about center [rad/s] (default 0)"},
    {"center", "talus.Vec", "centre of rotation [m] (default: the points' centroid)"},
    {"group", "string|string[]", "a group name, or a list (or groups)"},
    {"groups", "string|string[]", "a list of group names (or group)"},
    {"kn", "number", "the wall's own normal stiffness [N/m]"},
    {"ks", "number", "the wall's own shear stiffness [N/m]"},
    {"fric", "number", "the wall's own friction coefficient"},
};
const OptionTable kWallOptions = {"talus.WallDef", "m:wall{...}: a new wall (a chain of segments)",
                                  kWallOptionRows};

const Option kBallsOptionRows[] = {
    {"group", "string", "only the balls of this group"},
};
const OptionTable kBallsOptions = {"talus.BallsOptions", "m:balls{...}", kBallsOptionRows};

const Option kContactsOptionRows[] = {
    {"model", "string", "only the contacts of this model (any case)"},
    {"active", "boolean", "false: also the broadphase candidates not touching (default true)"},
    {"ball", "talus.Ball", "only the contacts of this ball"},
};
const OptionTable kContactsOptions = {"talus.ContactsOptions", "m:contacts{...}",
                                      kContactsOptionRows};

const Option kContactCountOptionRows[] = {
    {"active", "boolean", "false: also the broadphase candidates not touching (default true)"},
};
const OptionTable kContactCountOptions = {"talus.ContactCountOptions", "m:contact_count{...}",
                                          kContactCountOptionRows};

double optionalProp(const Options& o, const char* key) { return o.number(key, kNotSet); }

int w_ball(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "ball");
        const Options o(L, 2, "ball", kBallOptions);
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
            o.push("fix");
            try {
                d.fixity = toFixity(L, -1, o.field("fix"));
            } catch (...) {
                lua_pop(L, 1);
                throw;
            }
            lua_pop(L, 1);
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
        const Options o(L, 2, "wall", kWallOptions);
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

// Each pushes the live item of an iterator's list (false: deleted during the loop).
bool pushLiveBall(lua_State* L, LuaModel& lm, lua_Integer item) {
    const auto id = unpackId<BallId>(item);
    if (!lm.model->isAlive(id)) return false;
    pushBall(L, lua_upvalueindex(1), id);
    return true;
}

bool pushLiveWall(lua_State* L, LuaModel&, lua_Integer item) {
    pushWall(L, lua_upvalueindex(1), unpackId<WallId>(item));
    return true;
}

bool pushLiveContact(lua_State* L, LuaModel& lm, lua_Integer item) {
    const ContactKey key{static_cast<uint64_t>(item)};
    ContactInfo info;
    if (!lm.model->findContact(key, info)) return false;
    pushContact(L, lua_upvalueindex(1), key);
    return true;
}

int ballIterator(lua_State* L) { return iterateIds(L, pushLiveBall); }
int wallIterator(lua_State* L) { return iterateIds(L, pushLiveWall); }
int contactIterator(lua_State* L) { return iterateIds(L, pushLiveContact); }

/// __index and __len of an iterator: it is not a list, say what to use instead (upvalue 1:
/// the method's name, "balls").
int iteratorMisuse(lua_State* L) {
    return catchexcept(L, [&]() -> int {
        const std::string fn = lua_tostring(L, lua_upvalueindex(1));
        const std::string what = fn.substr(0, fn.size() - 1);  // "balls" -> "ball"
        std::string instead = "; their number: m:" + what + "_count()";
        if (fn == "balls") instead = "; a ball by its id: m:ball_by_id(id)" + instead;
        throw ScriptError(fn + "(): m:" + fn + "() is an iterator for a for loop (for " +
                          what.substr(0, 1) + " in m:" + fn + "() do ... end), not a list" +
                          instead);
    });
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
        const Options o(L, 2, "balls", kBallsOptions, true);
        Model& m = *lm.model;
        const auto ids =
            packIds(m.ballIds(), iteratorGroup(o, m), [&](BallId id) { return m.ballGroups(id); });
        pushIterator(L, ballIterator, ids, "balls");
        return 1;
    });
}

int w_walls(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "walls");
        std::vector<lua_Integer> ids;
        for (const WallId id : lm.model->wallIds()) ids.push_back(packId(id));
        pushIterator(L, wallIterator, ids, "walls");
        return 1;
    });
}

int w_contacts(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "contacts");
        const Options o(L, 2, "contacts", kContactsOptions, true);
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

constexpr char kBallCount[] = "ball_count";
constexpr char kWallCount[] = "wall_count";

int w_contact_count(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "contact_count");
        const Options o(L, 2, "contact_count", kContactCountOptions, true);
        lua_pushinteger(
            L, static_cast<lua_Integer>(lm.model->contactCount(o.boolean("active", true))));
        return 1;
    });
}

const Method kBodyMethods[] = {
    {"ball", w_ball, "a new ball", "def: talus.BallDef", "talus.Ball"},
    {"wall", w_wall, "a new wall: a chain of segments moved by prescribed velocity",
     "def: talus.WallDef", "talus.Wall"},
    {"balls", w_balls, "iterates over the live balls (in handle order), optionally of one group",
     "options?: talus.BallsOptions", "fun(): talus.Ball"},
    {"ball_by_id", w_ball_by_id, "the live ball whose b.id is id, or nil (PFC's ball.find)",
     "id: integer", "talus.Ball?"},
    {"walls", w_walls, "iterates over every wall", "", "fun(): talus.Wall"},
    {"contacts", w_contacts, "iterates over the contacts, optionally of one model or ball",
     "options?: talus.ContactsOptions", "fun(): talus.Contact"},
    {"ball_count", countMethod<&Model::ballCount, kBallCount>,
     "the number of balls (pebbles not counted)", "", "integer"},
    {"wall_count", countMethod<&Model::wallCount, kWallCount>, "the number of walls", "",
     "integer"},
    {"contact_count", w_contact_count, "the number of contacts (active ones by default)",
     "options?: talus.ContactCountOptions", "integer"},
};

const OptionTable* const kOptionTables[] = {&kBallOptions, &kWallOptions, &kBallsOptions,
                                            &kContactsOptions, &kContactCountOptions};

}  // namespace

extern const Binding kBodiesBinding = {"bodies", kBodyMethods, {}, {}, kOptionTables, {}};

// ------------------------------------------------------------------ shared body values

void pushFixity(lua_State* L, uint8_t fix) {
    std::vector<std::string> names;
    if (fix & kFixX) names.push_back("x");
    if (fix & kFixY) names.push_back("y");
    if (fix & kFixSpin) names.push_back("spin");
    pushStringList(L, names);
}

uint8_t toFixity(lua_State* L, int index, const std::string& what) {
    index = lua_absindex(L, index);
    const int t = lua_type(L, index);
    if (t == LUA_TBOOLEAN)
        return lua_toboolean(L, index) ? uint8_t(kFixX | kFixY | kFixSpin) : uint8_t(0);
    if (t == LUA_TNIL) return 0;
    const auto component = [&](int at, const std::string& entry) -> uint8_t {
        const int which = toEnum(L, at, entry, {"x", "y", "spin"});
        return which == 0 ? kFixX : which == 1 ? kFixY : kFixSpin;
    };
    if (t == LUA_TSTRING) return component(index, what);
    if (t != LUA_TTABLE)
        throw ScriptError(what + " must be a list such as {\"x\", \"spin\"}, or true/false");
    uint8_t fix = 0;
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, index));
    for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, index, i);
        try {
            fix |= component(-1, what + " entry " + std::to_string(i));
        } catch (...) {
            lua_pop(L, 1);
            throw;
        }
        lua_pop(L, 1);
    }
    return fix;
}

void pushOptional(lua_State* L, double v) {
    if (std::isnan(v))
        lua_pushnil(L);
    else
        lua_pushnumber(L, v);
}

std::vector<std::string> groupsOption(const Options& o) {
    if (o.has("group") && o.has("groups"))
        throw ScriptError(o.what() + ": give 'group' or 'groups', not both");
    return o.has("group") ? o.strings("group") : o.strings("groups");
}

// ------------------------------------------------------------------ iterators

std::string iteratorGroup(const Options& o, Model& m) {
    const std::string group = o.string("group", "");
    if (!group.empty() && m.groupIndex(group, false) < 0)
        throw ScriptError(
            o.what() + ": no group named '" + group + "' (groups: " +
            (m.groupNames().empty() ? std::string("none") : joinNames(m.groupNames())) + ")");
    return group;
}

// An iterator's state is in the upvalues of its function: 1 = the model userdata, 2 = the list
// of packed ids, 3 = the position in the list.
int iterateIds(lua_State* L, bool (*push)(lua_State* L, LuaModel& lm, lua_Integer item)) {
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
            if (push(L, *lm, v)) {
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

void pushIterator(lua_State* L, lua_CFunction next, const std::vector<lua_Integer>& items,
                  const char* name) {
    lua_createtable(L, 0, 0);
    lua_createtable(L, 0, 4);
    lua_pushvalue(L, 1);
    lua_createtable(L, static_cast<int>(items.size()), 0);
    for (std::size_t i = 0; i < items.size(); ++i) {
        lua_pushinteger(L, items[i]);
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_pushinteger(L, 0);
    lua_pushcclosure(L, next, 3);
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

}  // namespace talus::lua
