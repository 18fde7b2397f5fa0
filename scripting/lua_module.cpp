// SPDX-License-Identifier: MIT
// The `talus` module: luaopen_talus walks the Binding of every wrap_<thing>.cpp (binding.hpp)
// and registers their types, functions and values; this file's own are talus.load_plugin,
// talus.models, talus.contact_model_info, talus.mkdir, talus.did_you_mean, talus.version and
// talus.openmp.
#include <filesystem>
#include <system_error>

#include "lua_bindings.hpp"
#include "talus/model.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/suggest.hpp"

#ifndef TALUS_VERSION
#error "TALUS_VERSION must be defined by the build (project version)"
#endif

namespace talus::lua {

namespace {

std::string stringArg(lua_State* L, int index, const char* what) {
    if (lua_type(L, index) != LUA_TSTRING)
        throw ScriptError(std::string(what) + " (got " + typeName(L, index) + ")");
    return lua_tostring(L, index);
}

int w_load_plugin(lua_State* L) {
    return catchexcept(L, [&] {
        const std::string path = stringArg(L, 1, "load_plugin: argument must be a library path");
        pushStringList(L, PluginRegistry::global().load(path));
        return 1;
    });
}

int w_models(lua_State* L) {
    return catchexcept(L, [&] {
        pushStringList(L, PluginRegistry::global().modelNames());
        return 1;
    });
}

int w_contact_model_info(lua_State* L) {
    return catchexcept(L, [&] {
        const std::string name =
            stringArg(L, 1, "contact_model_info: argument must be a model name");
        const ModelFactory& f = PluginRegistry::global().find(name);
        const ContactModel* m = f.reference;
        lua_createtable(L, 0, 4);
        setString(L, "name", f.name);
        setString(L, "library", f.library);
        setString(L, "plugin_version", f.plugin_version);
        lua_newtable(L);
        for (int32_t i = 0; m && i < m->PropCount(); ++i) {
            const PropInfo* p = m->PropInfoAt(i);
            if (!p) continue;
            lua_createtable(L, 0, 9);
            setString(L, "name", p->name);
            setString(L, "units", p->units ? p->units : "");
            setNumber(L, "default", p->default_value);
            setString(L, "description", p->description ? p->description : "");
            setBoolean(L, "read_only", (p->flags & kPropReadOnly) != 0);
            setBoolean(L, "state", (p->flags & kPropState) != 0);
            setBoolean(L, "inheritable", (p->flags & kPropInheritable) != 0);
            setBoolean(L, "integer", (p->flags & kPropInteger) != 0);
            if (p->enum_names) {
                std::vector<std::string> names;
                for (int k = 0; p->enum_names[k]; ++k) names.push_back(p->enum_names[k]);
                pushStringList(L, names);
                lua_setfield(L, -2, "values");
            }
            lua_rawseti(L, -2, i + 1);
        }
        lua_setfield(L, -2, "properties");
        return 1;
    });
}

int w_mkdir(lua_State* L) {
    return catchexcept(L, [&] {
        const std::string path = stringArg(L, 1, "mkdir: argument must be a directory path");
        std::error_code ec;
        std::filesystem::create_directories(path, ec);
        if (ec) throw ScriptError("mkdir: cannot create '" + path + "' (" + ec.message() + ")");
        return 0;
    });
}

/// talus.did_you_mean(name, {candidates}): "; did you mean 'x'?" or "" (talus/suggest.hpp), for
/// the "unknown name" errors of Lua libraries (rockfall.lua), worded as the engine's.
int w_did_you_mean(lua_State* L) {
    return catchexcept(L, [&] {
        const std::string name = stringArg(L, 1, "did_you_mean: argument 1 must be the name");
        requireTable(L, 2, "did_you_mean: argument 2 (the known names)");
        std::vector<std::string> names;
        const auto n = static_cast<lua_Integer>(lua_rawlen(L, 2));
        for (lua_Integer i = 1; i <= n; ++i) {
            if (lua_rawgeti(L, 2, i) == LUA_TSTRING) names.push_back(lua_tostring(L, -1));
            lua_pop(L, 1);
        }
        const std::string hint = didYouMean(name, names);
        lua_pushlstring(L, hint.data(), hint.size());
        return 1;
    });
}

const Method kModuleFunctions[] = {
    {"load_plugin", w_load_plugin,
     "loads a contact-model library; returns the model names it added", "path: string", "string[]"},
    {"models", w_models, "the contact models loaded so far", "", "string[]"},
    {"contact_model_info", w_contact_model_info,
     "a model's metadata: name, library, plugin_version, properties", "name: string", "table"},
    {"mkdir", w_mkdir, "creates a directory and its parents (no error if it exists)",
     "path: string", ""},
    {"did_you_mean", w_did_you_mean, "\"; did you mean 'x'?\" for the names close to name, or \"\"",
     "name: string, names: string[]", "string"},
};

const Constant kModuleConstants[] = {
    {"version", "string", "the project version, e.g. \"0.1.0\"",
     [](lua_State* L) { lua_pushliteral(L, TALUS_VERSION); }},
    {"openmp", "boolean", "true when m:threads(n) can run the force loop on n threads",
     [](lua_State* L) { lua_pushboolean(L, talus::Model::threadingAvailable()); }},
};

/// Every Binding of the module: adding a thing is its Binding (lua_bindings.hpp) and a row here.
const Binding* const kBindings[] = {
    &kModuleBinding,       &kModelBinding,    &kBodiesBinding,  &kBallBinding,
    &kWallBinding,         &kServoBinding,    &kServosBinding,  &kContactBinding,
    &kContactModelBinding, &kTimestepBinding, &kGuardBinding,   &kEnergyBinding,
    &kClumpBinding,        &kBondBinding,     &kMeasureBinding, &kForceLoopBinding,
    &kHistoryBinding,      &kVtkBinding,      &kPictureBinding, &kSaveBinding,
    &kCrackBinding,        &kTrackerBinding,  &kBarrierBinding, &kImpactBinding,
    &kMapBinding,
};

}  // namespace

extern const Binding kModuleBinding = {"talus", {}, kModuleFunctions, {}, {}, kModuleConstants};

Rows<const Binding*> bindings() { return kBindings; }

}  // namespace talus::lua

extern "C" int luaopen_talus(lua_State* L) {
    using namespace talus::lua;
    openModel(L);
    lua_newtable(L);
    for (const Binding* b : bindings()) {
        for (const ObjectType* t : b->types) registerObjectType(L, *t);
        for (const Method& f : b->functions) {
            lua_pushcfunction(L, f.fn);
            lua_setfield(L, -2, f.name);
        }
        for (const Constant& c : b->constants) {
            c.push(L);
            lua_setfield(L, -2, c.name);
        }
    }
    return 1;
}
