// SPDX-License-Identifier: MIT
// Clumps from Lua (docs/lua-api.md, "Clumps"): m:clump{...}, m:clump_template{...},
// m:clumps{group =}, m:clump_count(), and the clump userdata (an id and its model; fields read
// and write the engine state by id, so a deleted clump gives "clump 3 was deleted (stale id)").
#include <algorithm>
#include <cmath>

#include "field_accessors.hpp"
#include "lua_bindings.hpp"
#include "talus/errors.hpp"

namespace talus::lua {

ClumpRef* testClump(lua_State* L, int index) {
    return static_cast<ClumpRef*>(testUserdata(L, index, kClumpType));
}

namespace {

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

// ------------------------------------------------------------------ the clump object

using namespace fields;
using C = ClumpRef;

const Field kClumpFields[] = {
    {"id", "integer", "the clump's handle number", getIndex<C, &Model::clumpMass>},
    {"pos", "talus.Vec", "centroid [m]; writing moves the pebbles with it",
     get<C, &Model::clumpPos>, set<C, &Model::setClumpPos>},
    {"vel", "talus.Vec", "velocity of the centroid at the half step [m/s]",
     get<C, &Model::clumpVel>, set<C, &Model::setClumpVel>},
    {"spin", "number", "angular velocity at the half step [rad/s]", get<C, &Model::clumpSpin>,
     set<C, &Model::setClumpSpin>},
    {"angle", "number", "orientation [rad]", get<C, &Model::clumpAngle>,
     set<C, &Model::setClumpAngle>},
    {"mass", "number", "[kg]", get<C, &Model::clumpMass>},
    {"inertia", "number", "inertia about the centroid [kg m^2]", get<C, &Model::clumpInertia>},
    {"density", "number", "[kg/m^3]; 0 in direct mode", get<C, &Model::clumpDensity>},
    {"force", "talus.Vec", "contact force summed to the centroid, last step [N]",
     get<C, &Model::clumpForce>},
    {"moment", "number", "contact moment about the centroid, last step [N m]",
     get<C, &Model::clumpMoment>},
    {"fapp", "talus.Vec", "applied force at the centroid [N]", get<C, &Model::clumpAppliedForce>,
     set<C, &Model::setClumpAppliedForce>},
    {"mapp", "number", "applied moment [N m]", get<C, &Model::clumpAppliedMoment>,
     set<C, &Model::setClumpAppliedMoment>},
    {"fix", "string[]|boolean", "fixed components, {\"x\", \"y\", \"spin\"}; true all",
     getFixity<C, &Model::clumpFixity>, setFixity<C, &Model::setClumpFixity>},
    {"kn", "number?", "normal stiffness of the clump and its pebbles [N/m]; nil: not set",
     getProp<C, &Model::clumpContactProp, kKn>, setProp<C, &Model::setClumpContactProp, kKn>},
    {"ks", "number?", "shear stiffness of the clump and its pebbles [N/m]; nil: not set",
     getProp<C, &Model::clumpContactProp, kKs>, setProp<C, &Model::setClumpContactProp, kKs>},
    {"fric", "number?", "friction coefficient of the clump and its pebbles; nil: not set",
     getProp<C, &Model::clumpContactProp, kFric>, setProp<C, &Model::setClumpContactProp, kFric>},
    {"groups", "string[]", "the clump's group names", get<C, &Model::clumpGroups>},
    {"alive", "boolean", "false once deleted or released", getAlive<C>},
};

int w_pebbles(lua_State* L);
int w_release(lua_State* L);

constexpr char kWhat[] = "clump";

const Method kClumpObjectMethods[] = {
    {"set", objectSet, "writes several fields at once, in sorted name order",
     "fields: talus.ClumpFields", ""},
    {"pebbles", w_pebbles, "the pebbles in world coordinates, {{pos =, radius =}, ...}", "",
     "table[]"},
    {"delete", actMethod<C, &Model::deleteClump, kDelete>,
     "removes the clump, its pebbles and their contacts", "", ""},
    {"release", w_release, "turns the pebbles into free balls (PFC clump release)", "",
     "talus.Ball[]"},
    {"add_group", addGroup<C, &Model::addClumpGroup>, "adds the clump to a group", "name: string",
     ""},
};

const ObjectType kClumpObject = {
    kClumpType,
    kWhat,
    "c",
    "a clump: a rigid body of pebbles, by id",
    kClumpFields,
    kClumpObjectMethods,
    describeBody<C, &Model::clumpPos, kWhat>,
};

ClumpRef& checkClump(lua_State* L, int index, const char* fn) {
    return checkObject<ClumpRef>(L, index, kClumpObject, fn);
}

// ------------------------------------------------------------------ m:clump{...}

const Option kClumpOptionRows[] = {
    {"pebbles", "number[][]",
     "{{x, y, r}, ...} [m]: in the clump's frame with pos, else in world coordinates"},
    {"template", "table|integer", "a template from m:clump_template{} (or pebbles, or balls)"},
    {"balls", "talus.Ball[]", "balls that become the pebbles (no pos, angle, scale)"},
    {"pos", "talus.Vec", "where the centroid goes [m]"},
    {"angle", "number", "orientation [rad] (default 0)"},
    {"scale", "number", "multiplies all lengths (default 1)"},
    {"density", "number", "[kg/m^3] for the union and sum mass modes"},
    {"mass", "number", "direct mode: mass [kg]"},
    {"inertia", "number", "direct mode: inertia about the centroid [kg m^2]"},
    {"centroid", "talus.Vec", "direct mode: centroid in the clump frame [m]"},
    {"mass_mode", "\"union\"|\"sum\"|\"direct\"", "how mass and inertia follow (default union)"},
    {"vel", "talus.Vec", "velocity of the centroid [m/s] (default {0, 0})"},
    {"spin", "number", "angular velocity [rad/s] (default 0)"},
    {"fix", "string[]|boolean", "fixed components {\"x\", \"y\", \"spin\"}; true all"},
    {"group", "string|string[]", "a group name, or a list (or groups)"},
    {"groups", "string|string[]", "a list of group names (or group)"},
    {"kn", "number", "normal stiffness [N/m], inherited by the pebbles' contacts"},
    {"ks", "number", "shear stiffness [N/m], inherited by the pebbles' contacts"},
    {"fric", "number", "friction coefficient, inherited by the pebbles' contacts"},
};
const OptionTable kClumpOptions = {"talus.ClumpDef", "m:clump{...}: a rigid body of pebbles",
                                   kClumpOptionRows};

const Option kClumpTemplateOptionRows[] = {
    {"pebbles", "number[][]", "{{x, y, r}, ...} [m] in the template's frame", true},
    {"mass_mode", "\"union\"|\"sum\"|\"direct\"", "how mass and inertia follow (default union)"},
};
const OptionTable kClumpTemplateOptions = {"talus.ClumpTemplateDef",
                                           "m:clump_template{...}: pebbles to place many times",
                                           kClumpTemplateOptionRows};

const Option kClumpsOptionRows[] = {
    {"group", "string", "only the clumps of this group"},
};
const OptionTable kClumpsOptions = {"talus.ClumpsOptions", "m:clumps{...}", kClumpsOptionRows};

/// The balls of m:clump{balls = {...}}: live balls of this model.
std::vector<BallId> readBalls(const Options& o, const LuaModel& lm) {
    lua_State* L = o.state();
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
    // Said here: the density check would otherwise answer an empty list.
    if (n == 0) {
        lua_pop(L, 1);
        throw ScriptError("clump: 'balls' is empty: a clump needs at least one ball");
    }
    std::vector<BallId> balls;
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
    return balls;
}

/// The id of m:clump{template = t}: the template table, or its id.
int readTemplate(const Options& o) {
    lua_State* L = o.state();
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
    if (id <= 0) throw ScriptError("clump: 'template' must be a template from m:clump_template{}");
    return static_cast<int>(id);
}

/// Pebbles read from the option `key` (pebbles), `what` naming one in errors.
std::vector<Pebble> pebblesOption(const Options& o, const char* key, const std::string& what) {
    lua_State* L = o.state();
    o.push(key);
    try {
        std::vector<Pebble> out = readPebbles(L, lua_gettop(L), what);
        lua_pop(L, 1);
        return out;
    } catch (...) {
        lua_pop(L, 1);
        throw;
    }
}

/// Where the clump goes and its mass: pos, angle, scale, the mass mode and its values.
void readPlacementAndMass(const Options& o, ClumpDef& d, bool from_balls) {
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
        !d.template_id && !from_balls)
        throw ScriptError("clump: 'density' (or direct 'mass' and 'inertia') is required");
}

/// Its motion, fixity, groups and contact properties.
void readMotionAndProps(const Options& o, ClumpDef& d) {
    lua_State* L = o.state();
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
}

int w_clump(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "clump");
        const Options o(L, 2, "clump", kClumpOptions);
        ClumpDef d;
        const int sources = o.has("pebbles") + o.has("template") + o.has("balls");
        if (sources != 1)
            throw ScriptError("clump: give exactly one of 'pebbles', 'template' or 'balls'");
        std::vector<BallId> balls;
        if (o.has("balls"))
            balls = readBalls(o, lm);
        else if (o.has("pebbles"))
            d.pebbles = pebblesOption(o, "pebbles", "clump: pebble");
        else
            d.template_id = readTemplate(o);
        readPlacementAndMass(o, d, !balls.empty());
        readMotionAndProps(o, d);
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
        const Options o(L, 2, "clump_template", kClumpTemplateOptions);
        if (!o.has("pebbles")) throw ScriptError("clump_template: 'pebbles' is required");
        const std::vector<Pebble> peb = pebblesOption(o, "pebbles", "clump_template: pebble");
        const int id = lm.model->defineClumpTemplate(peb, toMode(massModeOption(o)));
        const ClumpTemplate& t = lm.model->clumpTemplate(id);
        // A plain table: the id m:clump{template = t} uses, and the mass properties per unit
        // density (unit thickness) in the template's frame.
        lua_createtable(L, 0, 5);
        setInteger(L, "id", id);
        setNumber(L, "area", t.props.area);
        pushVec(L, t.props.centroid);
        lua_setfield(L, -2, "centroid");
        setNumber(L, "inertia", t.props.polar_moment);
        setInteger(L, "pebble_count", static_cast<lua_Integer>(peb.size()));
        return 1;
    });
}

bool pushLiveClump(lua_State* L, LuaModel& lm, lua_Integer item) {
    const auto id = unpackId<ClumpId>(item);
    if (!lm.model->isAlive(id)) return false;  // deleted during the loop
    pushClump(L, lua_upvalueindex(1), id);
    return true;
}

int clumpIterator(lua_State* L) { return iterateIds(L, pushLiveClump); }

int w_clumps(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "clumps");
        const Options o(L, 2, "clumps", kClumpsOptions, true);
        Model& m = *lm.model;
        const auto ids = packIds(m.clumpIds(), iteratorGroup(o, m),
                                 [&](ClumpId id) { return m.clumpGroups(id); });
        pushIterator(L, clumpIterator, ids, "clumps");
        return 1;
    });
}

constexpr char kClumpCount[] = "clump_count";

int w_pebbles(lua_State* L) {
    return catchexcept(L, [&] {
        ClumpRef& c = checkClump(L, 1, "pebbles");
        const auto peb = c.lm->model->clumpPebbles(c.id);
        lua_createtable(L, static_cast<int>(peb.size()), 0);
        for (std::size_t i = 0; i < peb.size(); ++i) {
            lua_createtable(L, 0, 2);
            pushVec(L, peb[i].pos);
            lua_setfield(L, -2, "pos");
            setNumber(L, "radius", peb[i].radius);
            lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
        }
        return 1;
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

const Method kClumpMethods[] = {
    {"clump", w_clump, "a new clump, from pebbles, a template or existing balls",
     "def: talus.ClumpDef", "talus.Clump"},
    {"clump_template", w_clump_template,
     "a template of pebbles with its mass properties per unit density",
     "def: talus.ClumpTemplateDef", "table"},
    {"clumps", w_clumps, "iterates over the live clumps, optionally of one group",
     "options?: talus.ClumpsOptions", "fun(): talus.Clump"},
    {"clump_count", countMethod<&Model::clumpCount, kClumpCount>, "the number of clumps", "",
     "integer"},
};

const ObjectType* const kTypes[] = {&kClumpObject};
const OptionTable* const kOptionTables[] = {&kClumpOptions, &kClumpTemplateOptions,
                                            &kClumpsOptions};

}  // namespace

extern const Binding kClumpBinding = {"clumps", kClumpMethods, {}, kTypes, kOptionTables, {}};

void pushClump(lua_State* L, int model_index, ClumpId id) {
    newObject<ClumpRef>(L, model_index, kClumpObject)->id = id;
}

}  // namespace talus::lua
