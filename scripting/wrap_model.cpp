// SPDX-License-Identifier: MIT
// talus.model{...} and the model's methods: bodies, contact models, settings, running,
// energy, callbacks and profile. Histories are in wrap_history.cpp.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <new>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"
#include "talus/plugin_registry.hpp"

namespace talus::lua {

namespace {

// Registry key of the weak table LuaModel* -> model userdata (see pushModel).
const char kModelsKey = 0;

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

void pushUserValueTable(lua_State* L, const LuaModel& lm) {
    pushModel(L, lm);
    lua_getiuservalue(L, -1, 1);
    lua_remove(L, -2);
}

// ------------------------------------------------------------------ callbacks from the engine

/// Calls the function on the stack below its `nargs` arguments; a Lua error becomes a
/// CallbackError, thrown after the stack is restored to `base`.
void callProtected(lua_State* L, int nargs, int nresults, int base) {
    if (lua_pcall(L, nargs, nresults, 0) != LUA_OK) {
        std::string msg = errorText(L, -1);
        lua_settop(L, base);
        throw CallbackError(msg);
    }
}

void runCycleCallback(LuaModel& lm, int ref) {
    lua_State* L = lm.L;
    const int base = lua_gettop(L);
    pushRef(L, lm, ref);
    pushModel(L, lm);
    lua_pushinteger(L, static_cast<lua_Integer>(lm.model->step()));
    callProtected(L, 2, 0, base);
    lua_settop(L, base);
}

const char* breakModeName(int32_t mode) {
    switch (mode) {
        case kBreakTension:
            return "tension";
        case kBreakShear:
            return "shear";
        default:
            return "none";
    }
}

void deliverEvent(LuaModel& lm, const Event& ev) {
    const int ref = ev.kind == EventKind::BondBreak ? lm.bond_break_ref : lm.contact_created_ref;
    if (ref == LUA_NOREF) return;
    lua_State* L = lm.L;
    const int base = lua_gettop(L);
    pushRef(L, lm, ref);
    pushModel(L, lm);
    const int model_index = lua_gettop(L);
    lua_createtable(L, 0, 6);
    lua_pushstring(L, ev.kind == EventKind::BondBreak ? "bond_break" : "contact_created");
    lua_setfield(L, -2, "kind");
    lua_pushnumber(L, ev.time);
    lua_setfield(L, -2, "time");
    pushVec(L, ev.pos);
    lua_setfield(L, -2, "pos");
    lua_pushstring(L, ev.model.c_str());
    lua_setfield(L, -2, "model");
    lua_pushstring(L, breakModeName(ev.mode));
    lua_setfield(L, -2, "mode");
    pushContact(L, model_index, ev.contact);
    lua_setfield(L, -2, "contact");
    lua_remove(L, model_index);
    callProtected(L, 1, 0, base);
    lua_settop(L, base);
}

void deliverWarning(LuaModel& lm, const std::string& text) {
    if (lm.warning_ref == LUA_NOREF || !lm.L) {
        // Keep the order a user sees on a terminal: what the script printed, then the warning.
        std::fflush(stdout);
        std::cerr << "warning: " << text << std::endl;
        return;
    }
    lua_State* L = lm.L;
    const int base = lua_gettop(L);
    pushRef(L, lm, lm.warning_ref);
    lua_pushstring(L, text.c_str());
    // A failing warning handler must not hide the finding (or an error being reported), so its
    // own error is printed, not raised.
    if (lua_pcall(L, 1, 0, 0) != LUA_OK) {
        std::fflush(stdout);
        std::cerr << "warning: " << text << "\nerror in on_warning handler: " << errorText(L, -1)
                  << std::endl;
    }
    lua_settop(L, base);
}

// ------------------------------------------------------------------ constructor, metamethods

int w_newModel(lua_State* L) {
    return catchexcept(L, [&] {
        const Options o(L, 1, "model", {"gravity", "mass"}, true);
        ModelDef def;
        def.gravity = o.vec("gravity", Vec2(0.0, 0.0));
        def.mass_mode =
            o.choice("mass", 0, {"disk", "sphere"}) == 0 ? MassMode::Disk : MassMode::Sphere;
        auto model = std::make_unique<Model>(def);

        void* mem = lua_newuserdatauv(L, sizeof(LuaModel), 1);
        LuaModel* lm = new (mem) LuaModel();
        lm->model = std::move(model);
        // Callbacks outside a run call use the main thread, which lives as long as the state
        // (a coroutine that created the model may be collected before the model).
        lua_rawgeti(L, LUA_REGISTRYINDEX, LUA_RIDX_MAINTHREAD);
        lm->L = lua_tothread(L, -1);
        lua_pop(L, 1);
        luaL_setmetatable(L, kModelType);
        lua_newtable(L);
        lua_setiuservalue(L, -2, 1);
        // Register in the weak table so callbacks can find the userdata from the LuaModel.
        lua_rawgetp(L, LUA_REGISTRYINDEX, &kModelsKey);
        lua_pushvalue(L, -2);
        lua_rawsetp(L, -2, lm);
        lua_pop(L, 1);

        lm->model->setWarningHandler([lm](const std::string& text) { deliverWarning(*lm, text); });
        lm->model->setEventHandler([lm](const Event& ev) { deliverEvent(*lm, ev); });
        return 1;
    });
}

int w_gc(lua_State* L) {
    auto* lm = static_cast<LuaModel*>(testUserdata(L, 1, kModelType));
    if (lm) lm->close();
    return 0;
}

int w_tostring(lua_State* L) {
    return catchexcept(L, [&] {
        auto* lm = static_cast<LuaModel*>(testUserdata(L, 1, kModelType));
        if (!lm || !lm->model) {
            lua_pushliteral(L, "talus.Model (closed)");
            return 1;
        }
        const Model& m = *lm->model;
        lua_pushfstring(L, "talus.Model (%d balls, %d walls, %d contacts, step %d, t = %f s)",
                        static_cast<int>(m.ballCount()), static_cast<int>(m.wallCount()),
                        static_cast<int>(m.contactCount()), static_cast<int>(m.step()), m.time());
        return 1;
    });
}

// ------------------------------------------------------------------ contact models

int w_contact_model(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "contact_model");
        if (lua_type(L, 2) != LUA_TSTRING)
            throw ScriptError("contact_model: argument 1 must be the model name (got " +
                              typeName(L, 2) + ")");
        const std::string name = lua_tostring(L, 2);
        std::vector<PropValue> props;
        if (!lua_isnoneornil(L, 3)) props = readProps(L, 3, name, "contact_model");
        const Options o(L, 4, "contact_model", {"groups"}, true);
        const std::vector<std::string> groups = o.strings("groups");
        if (groups.size() > 2)
            throw ScriptError("contact_model: 'groups' names one or two groups (got " +
                              std::to_string(groups.size()) + ")");
        if (groups.empty() && o.has("groups"))
            throw ScriptError(
                "contact_model: 'groups' is empty (omit it to set the default model)");
        if (groups.empty())
            lm.model->setDefaultContactModel(name, props);
        else
            lm.model->addContactModelRule(name, props, groups[0],
                                          groups.size() > 1 ? groups[1] : std::string());
        return 0;
    });
}

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

/// Pushes the iterator closure over `ids` (already packed) for the model at index 1.
void pushIterator(lua_State* L, lua_CFunction fn, const std::vector<lua_Integer>& ids) {
    lua_pushvalue(L, 1);
    lua_createtable(L, static_cast<int>(ids.size()), 0);
    for (std::size_t i = 0; i < ids.size(); ++i) {
        lua_pushinteger(L, ids[i]);
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_pushinteger(L, 0);
    lua_pushcclosure(L, fn, 3);
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
        pushIterator(L, ballIterator, ids);
        return 1;
    });
}

int w_walls(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "walls");
        std::vector<lua_Integer> ids;
        for (const WallId id : lm.model->wallIds())
            ids.push_back(static_cast<lua_Integer>((uint64_t(id.index) << 32) | id.generation));
        pushIterator(L, wallIterator, ids);
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
        pushIterator(L, contactIterator, keys);
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

// ------------------------------------------------------------------ settings

const char* guardName(GuardAction a) {
    switch (a) {
        case GuardAction::Off:
            return "off";
        case GuardAction::Warn:
            return "warn";
        case GuardAction::Error:
            return "error";
    }
    return "?";
}

int w_timestep(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "timestep");
        const Options o(L, 2, "timestep",
                        {"safety", "resolution", "fixed", "max", "growth", "auto"}, true);
        TimestepSettings ts = lm.model->timestep();
        readTimestepOptions(o, ts);
        lm.model->timestep() = ts;
        Model& m = *lm.model;
        lua_createtable(L, 0, 9);
        lua_pushboolean(L, ts.automatic);
        lua_setfield(L, -2, "auto");
        if (ts.automatic)
            lua_pushboolean(L, false);
        else
            lua_pushnumber(L, ts.fixed);
        lua_setfield(L, -2, "fixed");
        lua_pushnumber(L, ts.safety);
        lua_setfield(L, -2, "safety");
        lua_pushnumber(L, ts.resolution);
        lua_setfield(L, -2, "resolution");
        lua_pushnumber(L, ts.max);
        lua_setfield(L, -2, "max");
        lua_pushnumber(L, ts.growth);
        lua_setfield(L, -2, "growth");
        lua_pushnumber(L, m.lastTimestep());
        lua_setfield(L, -2, "dt");
        lua_pushstring(L, stepRuleName(m.lastStepRule()));
        lua_setfield(L, -2, "rule");
        lua_pushstring(L, m.lastStepReason().c_str());
        lua_setfield(L, -2, "reason");
        return 1;
    });
}

int w_guard(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "guard");
        const Options o(L, 2, "guard", guardOptionNames(), true);
        GuardSettings g = lm.model->guard();
        readGuardOptions(o, g);
        lm.model->guard() = g;
        lua_createtable(L, 0, 8);
        lua_pushstring(L, guardName(g.energy));
        lua_setfield(L, -2, "energy");
        lua_pushnumber(L, g.energy_tolerance);
        lua_setfield(L, -2, "energy_tolerance");
        lua_pushstring(L, guardName(g.resolution));
        lua_setfield(L, -2, "resolution");
        lua_pushinteger(L, g.min_steps);
        lua_setfield(L, -2, "min_steps");
        lua_pushstring(L, guardName(g.stiffness));
        lua_setfield(L, -2, "stiffness");
        lua_pushstring(L, guardName(g.balance));
        lua_setfield(L, -2, "balance");
        lua_pushnumber(L, g.balance_tolerance);
        lua_setfield(L, -2, "balance_tolerance");
        lua_pushinteger(L, g.balance_every);
        lua_setfield(L, -2, "balance_every");
        return 1;
    });
}

int w_damping(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "damping");
        // `damp` is PFC's name for local damping; `local` (a Lua keyword, so only ['local'] =)
        // is still accepted for old scripts (issue 6, item 13).
        const Options o(L, 2, "damping", {"damp", "local", "viscous"}, true);
        DampingSettings d = lm.model->damping();
        if (o.has("damp") && o.has("local"))
            throw ScriptError("damping: give 'damp' or its old name 'local', not both");
        const char* local_key = o.has("local") ? "local" : "damp";
        d.local = o.number(local_key, d.local);
        d.viscous = o.number("viscous", d.viscous);
        if (!(d.local >= 0.0 && d.local < 1.0))
            throw ScriptError(std::string("damping: '") + local_key + "' must be in [0, 1) (got " +
                              numberText(d.local) + ")");
        if (!(d.viscous >= 0.0) || !std::isfinite(d.viscous))
            throw ScriptError("damping: 'viscous' must be >= 0 [1/s] (got " +
                              numberText(d.viscous) + ")");
        lm.model->damping() = d;
        lua_createtable(L, 0, 3);
        lua_pushnumber(L, d.local);
        lua_setfield(L, -2, "damp");
        lua_pushnumber(L, d.local);
        lua_setfield(L, -2, "local");
        lua_pushnumber(L, d.viscous);
        lua_setfield(L, -2, "viscous");
        return 1;
    });
}

int w_broadphase(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "broadphase");
        const Options o(L, 2, "broadphase", {"margin"}, true);
        if (o.has("margin")) lm.model->setBroadphaseMargin(o.number("margin", 0.0));
        lua_createtable(L, 0, 1);
        lua_pushnumber(L, lm.model->broadphaseMargin());
        lua_setfield(L, -2, "margin");
        return 1;
    });
}

int w_gravity(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "gravity");
        if (!lua_isnoneornil(L, 2)) {
            const Vec2 g = toVec(L, 2, "gravity");
            if (!std::isfinite(g.x()) || !std::isfinite(g.y()))
                throw ScriptError("gravity: must be finite");
            lm.model->gravity() = g;
        }
        pushVec(L, lm.model->gravity());
        return 1;
    });
}

// ------------------------------------------------------------------ running

/// Runs `step` with this Lua thread as the callback thread; flushes histories either way.
template <class Run>
void runModel(lua_State* L, LuaModel& lm, const Run& step) {
    ActiveThread active(lm, L);
    ++lm.running;
    try {
        step(*lm.model);
    } catch (...) {
        --lm.running;
        lm.finishRun();
        try {
            lm.flushHistories();
        } catch (const std::exception&) {  // the run's own error comes first
        }
        throw;
    }
    --lm.running;
    lm.finishRun();
    lm.flushHistories();
}

int w_cycle(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "cycle");
        if (lua_isnoneornil(L, 2)) throw ScriptError("cycle: give the number of steps, m:cycle(n)");
        const long long n = toInteger(L, 2, "cycle: number of steps");
        if (n < 0)
            throw ScriptError("cycle: number of steps must be >= 0 (got " + std::to_string(n) +
                              ")");
        runModel(L, lm, [&](Model& m) { m.cycle(static_cast<int64_t>(n)); });
        return 0;
    });
}

int w_solve(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "solve");
        const Options o(L, 2, "solve", {"time"});
        if (!o.has("time")) throw ScriptError("solve: 'time' is required (simulated seconds)");
        const double t = o.number("time", 0.0);
        runModel(L, lm, [&](Model& m) { m.solveTime(t); });
        return 0;
    });
}

int w_time(lua_State* L) {
    return catchexcept(L, [&] {
        lua_pushnumber(L, checkModel(L, 1, "time").model->time());
        return 1;
    });
}

int w_step(lua_State* L) {
    return catchexcept(L, [&] {
        lua_pushinteger(L, static_cast<lua_Integer>(checkModel(L, 1, "step").model->step()));
        return 1;
    });
}

int w_dt(lua_State* L) {
    return catchexcept(L, [&] {
        const Model& m = *checkModel(L, 1, "dt").model;
        lua_pushnumber(L, m.lastTimestep());
        lua_pushstring(L, stepRuleName(m.lastStepRule()));
        return 2;
    });
}

// ------------------------------------------------------------------ energy

int w_energy(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "energy");
        const Options o(L, 2, "energy", {"on"}, true);
        if (o.has("on")) lm.model->setEnergyTracing(o.boolean("on", false));
        lua_pushboolean(L, lm.model->energyTracing());
        return 1;
    });
}

int w_energies(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "energies");
        if (!lua_isnoneornil(L, 2))
            throw ScriptError(
                "energies: group-wise energies are not available yet (the engine "
                "traces whole-model energies only); call m:energies()");
        pushEnergies(L, lm.model->energies());
        return 1;
    });
}

// ------------------------------------------------------------------ callbacks

int w_on_cycle(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "on_cycle");
        if (lua_type(L, 2) != LUA_TFUNCTION)
            throw ScriptError("on_cycle: argument 1 must be a function (got " + typeName(L, 2) +
                              ")");
        long long every = 1;
        if (!lua_isnoneornil(L, 3)) every = toInteger(L, 3, "on_cycle: 'every'");
        if (every < 1)
            throw ScriptError("on_cycle: 'every' must be >= 1 (got " + std::to_string(every) + ")");
        const int ref = storeRef(L, lm, 2);
        LuaModel* lmp = &lm;
        auto handle_cell = std::make_shared<int>(0);  // the hook learns its handle after adding
        const int handle = lm.model->addCycleHook(every, [lmp, ref, handle_cell](Model&) {
            if (!lmp->hookRemoved(*handle_cell)) runCycleCallback(*lmp, ref);
        });
        *handle_cell = handle;
        lm.cycle_refs.emplace_back(handle, ref);
        lua_pushinteger(L, handle);
        return 1;
    });
}

int w_remove_on_cycle(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "remove_on_cycle");
        const long long handle = toInteger(L, 2, "remove_on_cycle: handle");
        for (auto it = lm.cycle_refs.begin(); it != lm.cycle_refs.end(); ++it)
            if (it->first == handle) {
                lm.removeHook(it->first);
                releaseRef(L, lm, it->second);
                lm.cycle_refs.erase(it);
                break;
            }
        return 0;
    });
}

int w_on_event(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "on_event");
        const int kind = toEnum(L, 2, "on_event: event", {"bond_break", "contact_created"});
        if (!lua_isnil(L, 3) && lua_type(L, 3) != LUA_TFUNCTION)
            throw ScriptError("on_event: argument 2 must be a function or nil (got " +
                              typeName(L, 3) + ")");
        int& slot = kind == 0 ? lm.bond_break_ref : lm.contact_created_ref;
        if (slot != LUA_NOREF) releaseRef(L, lm, slot);
        slot = lua_isfunction(L, 3) ? storeRef(L, lm, 3) : LUA_NOREF;
        return 0;
    });
}

int w_on_warning(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "on_warning");
        if (!lua_isnoneornil(L, 2) && lua_type(L, 2) != LUA_TFUNCTION)
            throw ScriptError("on_warning: argument 1 must be a function or nil (got " +
                              typeName(L, 2) + ")");
        if (lm.warning_ref != LUA_NOREF) releaseRef(L, lm, lm.warning_ref);
        lm.warning_ref = lua_isfunction(L, 2) ? storeRef(L, lm, 2) : LUA_NOREF;
        return 0;
    });
}

int w_profile(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "profile");
        const Options o(L, 2, "profile", {"reset", "enabled"}, true);
        Profile& p = lm.model->profile();
        lua_pushstring(L, p.report(lm.model->ballCount()).c_str());
        if (o.has("enabled")) p.enabled = o.boolean("enabled", true);
        if (o.boolean("reset", false)) p.reset();
        return 1;
    });
}

const luaL_Reg kModelMethods[] = {
    {"contact_model", w_contact_model},
    {"ball", w_ball},
    {"wall", w_wall},
    {"balls", w_balls},
    {"walls", w_walls},
    {"contacts", w_contacts},
    {"ball_count", w_ball_count},
    {"wall_count", w_wall_count},
    {"contact_count", w_contact_count},
    {"timestep", w_timestep},
    {"guard", w_guard},
    {"damping", w_damping},
    {"broadphase", w_broadphase},
    {"gravity", w_gravity},
    {"cycle", w_cycle},
    {"solve", w_solve},
    {"time", w_time},
    {"step", w_step},
    {"dt", w_dt},
    {"energy", w_energy},
    {"energies", w_energies},
    {"on_cycle", w_on_cycle},
    {"remove_on_cycle", w_remove_on_cycle},
    {"on_event", w_on_event},
    {"on_warning", w_on_warning},
    {"profile", w_profile},
    {nullptr, nullptr},
};

int w_index_unknown(lua_State* L) {
    // __index of the method table's metatable: an unknown method name is an error that lists
    // the known ones (m:cylce(10) would otherwise say "attempt to call a nil value").
    return catchexcept(L, [&]() -> int {
        std::vector<std::string> names;
        for (const luaL_Reg* r = kModelMethods; r->name; ++r) names.push_back(r->name);
        names.push_back("history");
        names.push_back("close_history");
        std::sort(names.begin(), names.end());
        const std::string key = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : typeName(L, 2);
        throw ScriptError("model: unknown method or field '" + key +
                          "' (known: " + joinNames(names) + ")");
    });
}

}  // namespace

// ------------------------------------------------------------------ shared with other files

LuaModel::~LuaModel() { close(); }

void LuaModel::close() {
    closeHistories();
    // Free every container's storage: __gc calls close(), never the destructor.
    std::vector<std::unique_ptr<History>>().swap(histories);
    std::vector<std::pair<int, int>>().swap(cycle_refs);
    std::vector<int>().swap(removed_hooks);
    model.reset();
}

void LuaModel::closeHistories() {
    for (auto& h : histories)
        if (h->open()) {
            if (model && h->hook) model->removeCycleHook(h->hook);
            h->hook = 0;
            h->closeQuietly(*this);  // no throwing here (__gc); a failed close goes to stderr
        }
}

void LuaModel::removeHook(int handle) {
    if (!model || handle == 0) return;
    if (running > 0)
        removed_hooks.push_back(handle);
    else
        model->removeCycleHook(handle);
}

bool LuaModel::hookRemoved(int handle) const {
    return std::find(removed_hooks.begin(), removed_hooks.end(), handle) != removed_hooks.end();
}

void LuaModel::finishRun() {
    if (running > 0 || !model) return;
    for (int handle : removed_hooks) model->removeCycleHook(handle);
    removed_hooks.clear();
}

void LuaModel::flushHistories() {
    for (auto& h : histories)
        if (h->open()) h->flush(*this);  // a failed write stops with the file's name
}

LuaModel& checkModel(lua_State* L, int index, const char* fn) {
    auto* lm = static_cast<LuaModel*>(testUserdata(L, index, kModelType));
    if (!lm)
        throw ScriptError(std::string(fn) + ": call it as a method, m:" + fn + "(...) (" +
                          (lua_isnone(L, index) ? std::string("no model was given")
                                                : "the first argument is a " + typeName(L, index) +
                                                      ", not a model") +
                          ")");
    if (!lm->model) throw ScriptError(std::string(fn) + ": the model was closed");
    return *lm;
}

void pushModel(lua_State* L, const LuaModel& lm) {
    lua_rawgetp(L, LUA_REGISTRYINDEX, &kModelsKey);
    lua_rawgetp(L, -1, &lm);
    lua_remove(L, -2);
}

int storeRef(lua_State* L, const LuaModel& lm, int value_index) {
    value_index = lua_absindex(L, value_index);
    pushUserValueTable(L, lm);
    lua_pushvalue(L, value_index);
    const int ref = luaL_ref(L, -2);
    lua_pop(L, 1);
    return ref;
}

void pushRef(lua_State* L, const LuaModel& lm, int ref) {
    pushUserValueTable(L, lm);
    lua_rawgeti(L, -1, ref);
    lua_remove(L, -2);
}

void releaseRef(lua_State* L, const LuaModel& lm, int ref) {
    pushUserValueTable(L, lm);
    luaL_unref(L, -1, ref);
    lua_pop(L, 1);
}

void readTimestepOptions(const Options& o, TimestepSettings& ts) {
    lua_State* L = o.state();
    if (o.has("fixed")) {
        const int t = o.push("fixed");
        const bool is_false = t == LUA_TBOOLEAN && !lua_toboolean(L, -1);
        lua_pop(L, 1);
        if (is_false) {
            ts.automatic = true;
        } else {
            const double dt = o.number("fixed", 0.0);
            if (!(dt > 0.0) || !std::isfinite(dt))
                throw ScriptError("timestep: 'fixed' must be > 0 [s] (got " + numberText(dt) + ")");
            ts.fixed = dt;
            ts.automatic = false;
        }
    }
    if (o.has("auto")) {
        ts.automatic = o.boolean("auto", true);
        if (!ts.automatic && !(ts.fixed > 0.0))
            throw ScriptError("timestep: auto = false needs a 'fixed' step");
    }
    ts.safety = o.number("safety", ts.safety);
    ts.resolution = o.number("resolution", ts.resolution);
    ts.max = o.number("max", ts.max);
    ts.growth = o.number("growth", ts.growth);
    if (!(ts.safety > 0.0) || !std::isfinite(ts.safety))
        throw ScriptError("timestep: 'safety' must be > 0 (got " + numberText(ts.safety) + ")");
    if (!(ts.resolution >= 0.0) || !std::isfinite(ts.resolution))
        throw ScriptError("timestep: 'resolution' must be >= 0 steps per contact (got " +
                          numberText(ts.resolution) + ")");
    if (!(ts.max > 0.0))
        throw ScriptError("timestep: 'max' must be > 0 [s] (got " + numberText(ts.max) + ")");
    if (!(ts.growth > 1.0))
        throw ScriptError("timestep: 'growth' must be > 1 (got " + numberText(ts.growth) + ")");
}

const std::vector<std::string>& guardOptionNames() {
    static const std::vector<std::string> names = {
        "energy",    "energy_tolerance", "resolution",        "min_steps",
        "stiffness", "balance",          "balance_tolerance", "balance_every"};
    return names;
}

void readGuardOptions(const Options& o, GuardSettings& g) {
    const GuardAction actions[] = {GuardAction::Warn, GuardAction::Error, GuardAction::Off};
    if (o.has("energy")) g.energy = actions[o.choice("energy", 0, {"warn", "error", "off"})];
    if (o.has("resolution"))
        g.resolution = actions[o.choice("resolution", 0, {"warn", "error", "off"})];
    if (o.has("stiffness"))
        g.stiffness = actions[o.choice("stiffness", 0, {"warn", "error", "off"})];
    g.energy_tolerance = o.number("energy_tolerance", g.energy_tolerance);
    if (!(g.energy_tolerance >= 0.0))
        throw ScriptError("guard: 'energy_tolerance' must be >= 0 (got " +
                          numberText(g.energy_tolerance) + ")");
    if (o.has("balance")) g.balance = actions[o.choice("balance", 0, {"warn", "error", "off"})];
    g.balance_tolerance = o.number("balance_tolerance", g.balance_tolerance);
    if (!(g.balance_tolerance >= 0.0) || !std::isfinite(g.balance_tolerance))
        throw ScriptError("guard: 'balance_tolerance' must be a finite number >= 0 (got " +
                          numberText(g.balance_tolerance) + ")");
    const long long window = o.integer("balance_every", g.balance_every);
    if (window < 1)
        throw ScriptError("guard: 'balance_every' must be >= 1 step (got " +
                          std::to_string(window) + ")");
    g.balance_every = window;
    const long long steps = o.integer("min_steps", g.min_steps);
    if (steps < 0 || steps > std::numeric_limits<int>::max())
        throw ScriptError("guard: 'min_steps' must be >= 0 (got " + std::to_string(steps) + ")");
    g.min_steps = static_cast<int>(steps);
}

std::vector<PropValue> readProps(lua_State* L, int index, const std::string& model_name,
                                 const std::string& what) {
    index = lua_absindex(L, index);
    requireTable(L, index, what + ": properties");
    const ContactModel* meta = PluginRegistry::global().find(model_name).reference;
    std::vector<PropValue> props;
    lua_pushnil(L);
    while (lua_next(L, index) != 0) {
        if (lua_type(L, -2) != LUA_TSTRING) {
            lua_pop(L, 2);
            throw ScriptError(what + ": properties must be named (kn = 1e8, ...)");
        }
        PropValue pv;
        pv.name = lua_tostring(L, -2);
        const int t = lua_type(L, -1);
        std::string text;
        if (t == LUA_TNUMBER)
            pv.value = lua_tonumber(L, -1);
        else if (t == LUA_TBOOLEAN)
            pv.value = lua_toboolean(L, -1) ? 1.0 : 0.0;
        else if (t == LUA_TSTRING)
            text = lua_tostring(L, -1);
        const std::string got = typeName(L, -1);
        lua_pop(L, 1);
        if (t != LUA_TNUMBER && t != LUA_TBOOLEAN && t != LUA_TSTRING) {
            lua_pop(L, 1);
            throw ScriptError(what + ": property '" + pv.name + "' must be a number (got " + got +
                              ")");
        }
        if (t == LUA_TSTRING) {
            // Integer modes may be given by name: dp_mode = "no_tension".
            const PropInfo* info = nullptr;
            for (int32_t i = 0; meta && i < meta->PropCount(); ++i) {
                const PropInfo* pi = meta->PropInfoAt(i);
                if (pi && lower(pi->name) == lower(pv.name)) info = pi;
            }
            if (!info || !info->enum_names) {
                lua_pop(L, 1);
                throw ScriptError(what + ": property '" + pv.name + "' must be a number (got \"" +
                                  text + "\")");
            }
            std::vector<std::string> names;
            bool found = false;
            for (int i = 0; info->enum_names[i]; ++i) {
                names.push_back(std::string("\"") + info->enum_names[i] + "\"");
                if (text == info->enum_names[i]) pv.value = i, found = true;
            }
            if (!found) {
                lua_pop(L, 1);
                throw ScriptError(what + ": property '" + pv.name + "' must be one of " +
                                  joinNames(names) + " (got \"" + text + "\")");
            }
        }
        props.push_back(pv);
    }
    std::sort(props.begin(), props.end(),
              [](const PropValue& a, const PropValue& b) { return a.name < b.name; });
    return props;
}

const std::vector<EnergyItem>& energyItems() {
    static const std::vector<EnergyItem> items = {
        {"body", &EnergyTotals::body},
        {"boundary", &EnergyTotals::boundary},
        {"kinetic", &EnergyTotals::kinetic},
        {"strain", &EnergyTotals::strain},
        {"bond", &EnergyTotals::bond},
        {"slip", &EnergyTotals::slip},
        {"dashpot", &EnergyTotals::dashpot},
        {"plastic", &EnergyTotals::plastic},
        {"damping", &EnergyTotals::damping},
        {"released", &EnergyTotals::released},
        {"deleted", &EnergyTotals::deleted},
        {"initial_kinetic", &EnergyTotals::initial_kinetic},
        {"initial_strain", &EnergyTotals::initial_strain},
        {"placement", &EnergyTotals::placement},
    };
    return items;
}

void pushEnergies(lua_State* L, const EnergyTotals& e) {
    lua_createtable(L, 0, 14);
    for (const EnergyItem& item : energyItems()) {
        lua_pushnumber(L, e.*(item.member));
        lua_setfield(L, -2, item.name);
    }
    lua_pushnumber(L, e.balanceError());
    lua_setfield(L, -2, "balance_error");
    lua_pushnumber(L, e.input());
    lua_setfield(L, -2, "input");
}

void openModel(lua_State* L) {
    // Weak-valued table LuaModel* -> userdata: callbacks find their model without keeping it alive.
    lua_newtable(L);
    lua_createtable(L, 0, 1);
    lua_pushliteral(L, "v");
    lua_setfield(L, -2, "__mode");
    lua_setmetatable(L, -2);
    lua_rawsetp(L, LUA_REGISTRYINDEX, &kModelsKey);

    luaL_newmetatable(L, kModelType);
    lua_pushcfunction(L, w_gc);
    lua_setfield(L, -2, "__gc");
    lua_pushcfunction(L, w_tostring);
    lua_setfield(L, -2, "__tostring");
    luaL_newlib(L, kModelMethods);
    addHistoryMethods(L, lua_gettop(L));
    lua_createtable(L, 0, 1);
    lua_pushcfunction(L, w_index_unknown);
    lua_setfield(L, -2, "__index");
    lua_setmetatable(L, -2);
    lua_setfield(L, -2, "__index");
    lua_pop(L, 1);
}

int newModel(lua_State* L) { return w_newModel(L); }

}  // namespace talus::lua
