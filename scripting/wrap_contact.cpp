// SPDX-License-Identifier: MIT
// Contact userdata: the contact's key and its model. Every read looks the contact up again, so
// a contact that ended in the meantime gives a clear error instead of stale values.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "lua_bindings.hpp"
#include "talus/plugin_registry.hpp"

namespace talus::lua {

namespace {

struct ContactRef {
    LuaModel* lm;
    ContactKey key;
};

// Key layout (talus/ids.hpp; kWallBit in core/src/world/types.hpp): end 1's ball handle in the high
// word; the low word is end 2's ball handle, or a wall segment with the top bit set.
constexpr uint64_t kWallBit = 0x80000000u;

std::string describeKey(ContactKey key) {
    const auto ball1 = static_cast<unsigned>(key.value >> 32);
    const auto low = static_cast<uint32_t>(key.value & 0xffffffffu);
    if (low & kWallBit) return "contact of ball " + std::to_string(ball1) + " with a wall";
    return "contact of balls " + std::to_string(ball1) + " and " + std::to_string(low);
}

const char* const kFieldNames[] = {
    "key",          "ball1",       "ball2",  "wall",    "segment", "normal", "point",  "overlap",
    "normal_force", "shear_force", "moment", "sliding", "model",   "active", "clump1", "clump2",
};
const char* const kMethods[] = {"prop", "set_prop", "props"};

std::string knownFields() {
    std::vector<std::string> names(std::begin(kFieldNames), std::end(kFieldNames));
    for (const char* m : kMethods) names.push_back(std::string(m) + "()");
    return joinNames(names);
}

ContactRef& checkContact(lua_State* L, int index, const char* fn) {
    auto* c = static_cast<ContactRef*>(testUserdata(L, index, kContactType));
    if (!c)
        throw ScriptError(std::string("contact: call it as a method, c:") + fn +
                          "(...) (the first argument is a " + typeName(L, index) +
                          ", not a contact)");
    if (!c->lm->model) throw ScriptError("contact: its model was closed");
    return *c;
}

ContactInfo lookup(const ContactRef& c) {
    ContactInfo info;
    if (!c.lm->model->findContact(c.key, info))
        throw ScriptError(describeKey(c.key) + " no longer exists");
    return info;
}

std::string nameArg(lua_State* L, int index, const char* fn) {
    if (lua_type(L, index) != LUA_TSTRING)
        throw ScriptError(std::string("contact: ") + fn + "(name) needs a property name (got " +
                          typeName(L, index) + ")");
    return lua_tostring(L, index);
}

int w_index(lua_State* L) {
    return catchexcept(L, [&] {
        ContactRef& c = checkContact(L, 1, "index");
        if (lua_type(L, 2) != LUA_TSTRING)
            throw ScriptError("contact: field names are strings (got " + typeName(L, 2) + ")");
        const std::string key = lua_tostring(L, 2);
        for (const char* m : kMethods)
            if (key == m) {
                lua_pushstring(L, m);
                lua_rawget(L, lua_upvalueindex(1));
                return 1;
            }
        if (key == "key") {
            // The key is valid even after the contact ended (it names the pair of ends).
            lua_pushinteger(L, static_cast<lua_Integer>(c.key.value));
            return 1;
        }
        const ContactInfo info = lookup(c);
        lua_getiuservalue(L, 1, 1);  // the model userdata, for the ball/wall userdata
        const int model_index = lua_gettop(L);
        if (key == "ball1")
            pushBall(L, model_index, info.ball1);
        else if (key == "clump1" || key == "clump2") {
            const ClumpId cl = key == "clump1" ? info.clump1 : info.clump2;
            if (cl.valid())
                pushClump(L, model_index, cl);
            else
                lua_pushnil(L);
        } else if (key == "ball2") {
            if (info.ball2.valid())
                pushBall(L, model_index, info.ball2);
            else
                lua_pushnil(L);
        } else if (key == "wall") {
            if (info.wall.valid())
                pushWall(L, model_index, info.wall);
            else
                lua_pushnil(L);
        } else if (key == "segment") {
            if (info.wall.valid())
                lua_pushinteger(L, info.segment + 1);
            else
                lua_pushnil(L);
        } else if (key == "normal")
            pushVec(L, info.normal);
        else if (key == "point")
            pushVec(L, info.point);
        else if (key == "overlap")
            lua_pushnumber(L, info.overlap);
        else if (key == "normal_force")
            lua_pushnumber(L, info.normal_force);
        else if (key == "shear_force")
            lua_pushnumber(L, info.shear_force);
        else if (key == "moment")
            lua_pushnumber(L, info.moment);
        else if (key == "sliding")
            lua_pushboolean(L, info.sliding);
        else if (key == "model")
            lua_pushstring(L, info.model.c_str());
        else if (key == "active")
            lua_pushboolean(L, info.active);
        else
            throw ScriptError("contact: unknown field '" + key + "'" +
                              didYouMeanIn(key, knownFields()) + " (known: " + knownFields() + ")");
        return 1;
    });
}

int w_newindex(lua_State* L) {
    return catchexcept(L, [&] {
        ContactRef& c = checkContact(L, 1, "newindex");
        const std::string key = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : typeName(L, 2);
        if (key != "normal_force" && key != "shear_force") {
            const bool known =
                std::find_if(std::begin(kFieldNames), std::end(kFieldNames),
                             [&](const char* n) { return key == n; }) != std::end(kFieldNames);
            throw ScriptError(
                "contact: " +
                (known ? "field '" + key + "' is read-only" : "unknown field '" + key + "'") +
                " (writable: normal_force, shear_force; model properties: "
                "c:set_prop(name, value))");
        }
        const double v = toNumber(L, 3, "contact: '" + key + "'");
        const ContactInfo info = lookup(c);
        if (key == "normal_force")
            c.lm->model->setContactForce(c.key, v, info.shear_force);
        else
            c.lm->model->setContactForce(c.key, info.normal_force, v);
        return 0;
    });
}

int w_prop(lua_State* L) {
    return catchexcept(L, [&] {
        ContactRef& c = checkContact(L, 1, "prop");
        const std::string name = nameArg(L, 2, "prop");
        const ContactInfo info = lookup(c);  // a clear message if the contact ended
        checkPropertyName(c.lm->model->contactModelFactory(info.model).reference, name, "contact");
        lua_pushnumber(L, c.lm->model->contactProp(c.key, name));
        return 1;
    });
}

int w_set_prop(lua_State* L) {
    return catchexcept(L, [&] {
        ContactRef& c = checkContact(L, 1, "set_prop");
        const std::string name = nameArg(L, 2, "set_prop");
        const ContactInfo info = lookup(c);
        checkPropertyName(c.lm->model->contactModelFactory(info.model).reference, name, "contact");
        double value = 0.0;
        if (lua_type(L, 3) == LUA_TSTRING) {
            // An integer mode by name, as in contact_model{...}.
            lua_createtable(L, 0, 1);
            lua_pushvalue(L, 3);
            lua_setfield(L, -2, name.c_str());
            value = readProps(L, -1, info.model, "contact").front().value;
            lua_pop(L, 1);
        } else {
            value = toNumber(L, 3, "contact: property '" + name + "'");
        }
        c.lm->model->setContactProp(c.key, name, value);
        if (isFrictionCoefficient(name, c.lm->model->contactModelFactory(info.model).reference))
            warnImplausibleFriction(c.lm, "contact", {{name, value}});
        return 0;
    });
}

int w_props(lua_State* L) {
    return catchexcept(L, [&] {
        ContactRef& c = checkContact(L, 1, "props");
        const ContactInfo info = lookup(c);
        const ContactModel* meta = c.lm->model->contactModelFactory(info.model).reference;
        lua_newtable(L);
        for (int32_t i = 0; meta && i < meta->PropCount(); ++i) {
            const PropInfo* pi = meta->PropInfoAt(i);
            if (!pi) continue;
            lua_pushnumber(L, c.lm->model->contactProp(c.key, pi->name));
            lua_setfield(L, -2, pi->name);
        }
        return 1;
    });
}

int w_eq(lua_State* L) {
    const auto* a = static_cast<ContactRef*>(testUserdata(L, 1, kContactType));
    const auto* b = static_cast<ContactRef*>(testUserdata(L, 2, kContactType));
    lua_pushboolean(L, a && b && a->lm == b->lm && a->key == b->key);
    return 1;
}

int w_tostring(lua_State* L) {
    return catchexcept(L, [&] {
        const auto* c = static_cast<ContactRef*>(testUserdata(L, 1, kContactType));
        const std::string text = c ? describeKey(c->key) : "contact";
        lua_pushstring(L, text.c_str());
        return 1;
    });
}

const luaL_Reg kContactMethods[] = {
    {"prop", w_prop},
    {"set_prop", w_set_prop},
    {"props", w_props},
    {nullptr, nullptr},
};

}  // namespace

void pushContact(lua_State* L, int model_index, ContactKey key) {
    model_index = lua_absindex(L, model_index);
    auto* c = newRef<ContactRef>(L, model_index, kContactType);
    c->lm = static_cast<LuaModel*>(lua_touserdata(L, model_index));
    c->key = key;
}

void openContact(lua_State* L) {
    registerRefType(L, kContactType, kContactMethods, w_index, w_newindex, w_eq, w_tostring);
}

}  // namespace talus::lua
