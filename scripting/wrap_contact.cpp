// SPDX-License-Identifier: MIT
// Contact userdata: the contact's key and its model. Every read looks the contact up again, so
// a contact that ended in the meantime gives a clear error instead of stale values.

#include "field_accessors.hpp"
#include "lua_bindings.hpp"
#include "talus/plugin_registry.hpp"

namespace talus::lua {

namespace {

struct ContactRef {
    LuaModel* lm;
    ContactKey key;
};

// Key layout (core ids.hpp / model_internal.hpp): end 1's ball handle in the high word; the low
// word is end 2's ball handle, or a wall segment with the top bit set.
constexpr uint64_t kWallBit = 0x80000000u;

std::string describeKey(ContactKey key) {
    const auto ball1 = static_cast<unsigned>(key.value >> 32);
    const auto low = static_cast<uint32_t>(key.value & 0xffffffffu);
    if (low & kWallBit) return "contact of ball " + std::to_string(ball1) + " with a wall";
    return "contact of balls " + std::to_string(ball1) + " and " + std::to_string(low);
}

ContactInfo lookup(const ContactRef& c) {
    ContactInfo info;
    if (!c.lm->model->findContact(c.key, info))
        throw ScriptError(describeKey(c.key) + " no longer exists");
    return info;
}

int w_prop(lua_State* L);
int w_set_prop(lua_State* L);
int w_props(lua_State* L);

ContactRef& contact(void* self) { return *static_cast<ContactRef*>(self); }

/// A field read from the contact as the engine has it now (an error once it ended).
template <class Push>
void withInfo(lua_State* L, void* self, const Push& push) {
    const ContactInfo info = lookup(contact(self));
    lua_getiuservalue(L, 1, 1);  // the model userdata, for the ball/wall userdata
    const int model_index = lua_gettop(L);
    push(info, model_index);
    lua_remove(L, model_index);
}

/// A member of the contact's ContactInfo, as it is now.
template <auto Member>
void infoField(lua_State* L, void* self) {
    fields::pushValue(L, lookup(contact(self)).*Member);
}

/// Writes one of the two stored forces, keeping the other.
void setForce(lua_State* L, void* self, int value, const std::string& what, bool normal) {
    const double v = toNumber(L, value, what);
    ContactRef& c = contact(self);
    const ContactInfo info = lookup(c);
    if (normal)
        c.lm->model->setContactForce(c.key, v, info.shear_force);
    else
        c.lm->model->setContactForce(c.key, info.normal_force, v);
}

void pushBallOrNil(lua_State* L, int model_index, BallId id) {
    if (id.valid())
        pushBall(L, model_index, id);
    else
        lua_pushnil(L);
}

void pushClumpOrNil(lua_State* L, int model_index, ClumpId id) {
    if (id.valid())
        pushClump(L, model_index, id);
    else
        lua_pushnil(L);
}

const Field kContactFields[] = {
    {"key", "integer", "names the pair of ends; stays readable after the contact ended",
     [](lua_State* L, void* self) {
         lua_pushinteger(L, static_cast<lua_Integer>(contact(self).key.value));
     }},
    {"ball1", "talus.Ball", "end 1 (a ball; for two balls the lower id)",
     [](lua_State* L, void* self) {
         withInfo(L, self, [&](const ContactInfo& i, int m) { pushBall(L, m, i.ball1); });
     }},
    {"ball2", "talus.Ball?", "end 2 if it is a ball, else nil",
     [](lua_State* L, void* self) {
         withInfo(L, self, [&](const ContactInfo& i, int m) { pushBallOrNil(L, m, i.ball2); });
     }},
    {"wall", "talus.Wall?", "end 2 if it is a wall, else nil",
     [](lua_State* L, void* self) {
         withInfo(L, self, [&](const ContactInfo& i, int m) {
             if (i.wall.valid())
                 pushWall(L, m, i.wall);
             else
                 lua_pushnil(L);
         });
     }},
    {"segment", "integer?", "the wall's segment (1 = from point 1 to point 2), else nil",
     [](lua_State* L, void* self) {
         withInfo(L, self, [&](const ContactInfo& i, int) {
             if (i.wall.valid())
                 lua_pushinteger(L, i.segment + 1);
             else
                 lua_pushnil(L);
         });
     }},
    {"normal", "talus.Vec", "unit normal from end 1 to end 2", infoField<&ContactInfo::normal>},
    {"point", "talus.Vec", "contact point [m]", infoField<&ContactInfo::point>},
    {"overlap", "number", "overlap (+) or gap (-) [m]", infoField<&ContactInfo::overlap>},
    {"normal_force", "number", "normal force on end 2 [N], compression positive",
     infoField<&ContactInfo::normal_force>,
     [](lua_State* L, void* self, int v, const std::string& what) {
         setForce(L, self, v, what, true);
     }},
    {"shear_force", "number", "shear force on end 2 along t = (-n_y, n_x) [N]",
     infoField<&ContactInfo::shear_force>,
     [](lua_State* L, void* self, int v, const std::string& what) {
         setForce(L, self, v, what, false);
     }},
    {"moment", "number", "moment on end 2 [N m]", infoField<&ContactInfo::moment>},
    {"sliding", "boolean", "true while the contact slides", infoField<&ContactInfo::sliding>},
    {"model", "string", "the contact's model name", infoField<&ContactInfo::model>},
    {"active", "boolean", "true while it has a model object (touching or within reach)",
     infoField<&ContactInfo::active>},
    {"clump1", "talus.Clump?", "the clump of end 1 when it is a pebble, else nil",
     [](lua_State* L, void* self) {
         withInfo(L, self, [&](const ContactInfo& i, int m) { pushClumpOrNil(L, m, i.clump1); });
     }},
    {"clump2", "talus.Clump?", "the clump of end 2 when it is a pebble, else nil",
     [](lua_State* L, void* self) {
         withInfo(L, self, [&](const ContactInfo& i, int m) { pushClumpOrNil(L, m, i.clump2); });
     }},
};

const Method kContactMethods[] = {
    {"prop", w_prop, "a property of the contact's model object (state included: \"lin_fn\")",
     "name: string", "number"},
    {"set_prop", w_set_prop, "writes a property of the contact's model object",
     "name: string, value: number|string", ""},
    {"props", w_props, "every property of the contact's model object, by name", "",
     "table<string, number>"},
};

void describe(lua_State* L, void* self) {
    lua_pushstring(L, describeKey(contact(self).key).c_str());
}

const ObjectType kContactObject = {
    kContactType,   "contact",       "c",      "a contact: looked up again at every read",
    kContactFields, kContactMethods, describe, "model properties: c:set_prop(name, value)",
};

ContactRef& checkContact(lua_State* L, int index, const char* fn) {
    return checkObject<ContactRef>(L, index, kContactObject, fn);
}

std::string nameArg(lua_State* L, int index, const char* fn) {
    if (lua_type(L, index) != LUA_TSTRING)
        throw ScriptError(std::string("contact: ") + fn + "(name) needs a property name (got " +
                          typeName(L, index) + ")");
    return lua_tostring(L, index);
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

const ObjectType* const kTypes[] = {&kContactObject};
}  // namespace

extern const Binding kContactBinding = {"contact", {}, {}, kTypes, {}, {}};

void pushContact(lua_State* L, int model_index, ContactKey key) {
    newObject<ContactRef>(L, model_index, kContactObject)->key = key;
}

}  // namespace talus::lua
