// SPDX-License-Identifier: MIT
// m:contact_model(name, props, groups) and the property-table reader shared with contacts
// and impact.
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

}  // namespace

extern const luaL_Reg kContactModelMethods[] = {
    {"contact_model", w_contact_model},
    {nullptr, nullptr},
};

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

}  // namespace talus::lua
