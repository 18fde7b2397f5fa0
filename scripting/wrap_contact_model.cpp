// SPDX-License-Identifier: MIT
// m:contact_model(name, props, groups) and the property-table reader shared with contacts
// and impact.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"
#include "talus/plugin_registry.hpp"

namespace talus::lua {

namespace {

const Option kContactModelOptionRows[] = {
    {"groups", "string|string[]",
     "a rule for contacts between a body of group a and one of b (either order); {a}: a with "
     "anything"},
};
const OptionTable kContactModelOptions = {
    "talus.ContactModelOptions", "m:contact_model(name, props, {...})", kContactModelOptionRows};

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
        const Options o(L, 4, "contact_model", kContactModelOptions, true);
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
        const ContactModel* meta = PluginRegistry::global().find(name).reference;
        std::vector<std::pair<std::string, double>> fric;
        for (const PropValue& p : props)
            if (isFrictionCoefficient(p.name, meta)) fric.emplace_back(p.name, p.value);
        warnImplausibleFriction(&lm, "contact_model '" + name + "'", fric);
        return 0;
    });
}

const Method kContactModelMethods[] = {
    {"contact_model", w_contact_model,
     "sets the default contact model, or with groups a rule for a pair of groups",
     "name: string, props?: table<string, number|string>, options?: talus.ContactModelOptions", ""},
};

const OptionTable* const kOptionTables[] = {&kContactModelOptions};

}  // namespace

extern const Binding kContactModelBinding = {
    "contact models", kContactModelMethods, {}, {}, kOptionTables, {}};

bool isFrictionCoefficient(const std::string& name, const ContactModel* meta) {
    const std::string key = lower(name);
    const bool named =
        key == "fric" || (key.size() > 5 && key.compare(key.size() - 5, 5, "_fric") == 0);
    if (!named) return false;
    // A model may call an angle *_fric: only dimensionless properties are coefficients.
    for (int32_t i = 0; meta && i < meta->PropCount(); ++i) {
        const PropInfo* pi = meta->PropInfoAt(i);
        if (pi && lower(pi->name) == key)
            return !pi->units || std::string(pi->units) == "-" || std::string(pi->units).empty();
    }
    return true;
}

void warnImplausibleFriction(LuaModel* lm, const std::string& what,
                             const std::vector<std::pair<std::string, double>>& values) {
    std::string text;
    for (const auto& [name, v] : values) {
        if (!(v > kPlausibleFrictionMax) || !std::isfinite(v)) continue;
        text += text.empty() ? what + ": " : "; ";
        text +=
            name + " = " + numberText(v) + " is a friction coefficient (tan of the friction angle)";
        if (v < 90.0) {
            char buf[160];
            std::snprintf(
                buf, sizeof buf,
                ", not an angle: for a friction angle of %s\u00b0 use %s = tan(%s\u00b0) = "
                "%.3g (math.tan(math.rad(%s)))",
                numberText(v).c_str(), name.c_str(), numberText(v).c_str(),
                std::tan(v * 3.14159265358979323846 / 180.0), numberText(v).c_str());
            text += buf;
        } else {
            text += "; above " + numberText(kPlausibleFrictionMax) + " it is not plausible";
        }
    }
    if (text.empty()) return;
    text += " (a coefficient above " + numberText(kPlausibleFrictionMax) +
            " makes contacts that almost never slip)";
    if (lm && lm->model) {
        lm->model->warn(text);
    } else {
        clearProgressLine();
        std::fflush(stdout);
        std::fprintf(stderr, "warning: %s\n", text.c_str());
    }
}

void checkPropertyName(const ContactModel* meta, const std::string& name, const std::string& what) {
    if (!meta) return;
    const std::string key = lower(name);
    for (int32_t i = 0; i < meta->PropCount(); ++i) {
        const PropInfo* pi = meta->PropInfoAt(i);
        if (pi && lower(pi->name) == key) return;
    }
    std::string known;
    for (const char* c = meta->PropNames(); c && *c; ++c)
        known += (*c == ',') ? std::string(", ") : std::string(1, *c);
    throw ScriptError(what + ": unknown property '" + name + "' for model '" + meta->Name() + "'" +
                      didYouMeanIn(name, known) + " (known: " + known + ")");
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
        try {
            checkPropertyName(meta, pv.name, what);
        } catch (...) {
            lua_pop(L, 2);
            throw;
        }
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
