// SPDX-License-Identifier: MIT
// The `talus` module table: talus.model, talus.load_plugin, talus.contact_model_info,
// talus.models, talus.mkdir, talus.version, talus.impact/drive (wrap_impact.cpp) and
// talus.map/rank/ranks (wrap_map.cpp).
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
        lua_pushstring(L, f.name.c_str());
        lua_setfield(L, -2, "name");
        lua_pushstring(L, f.library.c_str());
        lua_setfield(L, -2, "library");
        lua_pushstring(L, f.plugin_version.c_str());
        lua_setfield(L, -2, "plugin_version");
        lua_newtable(L);
        for (int32_t i = 0; m && i < m->PropCount(); ++i) {
            const PropInfo* p = m->PropInfoAt(i);
            if (!p) continue;
            lua_createtable(L, 0, 9);
            lua_pushstring(L, p->name);
            lua_setfield(L, -2, "name");
            lua_pushstring(L, p->units ? p->units : "");
            lua_setfield(L, -2, "units");
            lua_pushnumber(L, p->default_value);
            lua_setfield(L, -2, "default");
            lua_pushstring(L, p->description ? p->description : "");
            lua_setfield(L, -2, "description");
            lua_pushboolean(L, (p->flags & kPropReadOnly) != 0);
            lua_setfield(L, -2, "read_only");
            lua_pushboolean(L, (p->flags & kPropState) != 0);
            lua_setfield(L, -2, "state");
            lua_pushboolean(L, (p->flags & kPropInheritable) != 0);
            lua_setfield(L, -2, "inheritable");
            lua_pushboolean(L, (p->flags & kPropInteger) != 0);
            lua_setfield(L, -2, "integer");
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

const luaL_Reg kModuleFunctions[] = {
    {"model", newModel},  {"load_plugin", w_load_plugin},
    {"models", w_models}, {"contact_model_info", w_contact_model_info},
    {"mkdir", w_mkdir},   {"did_you_mean", w_did_you_mean},
    {nullptr, nullptr},
};

/// Every function table of the module, one per thing (lua_bindings.hpp): a new thing's table
/// is one row here.
const luaL_Reg* const kModuleFunctionTables[] = {
    kModuleFunctions,  // this file
    kImpactFunctions,  // wrap_impact.cpp
    kMapFunctions,     // wrap_map.cpp
    kSaveFunctions,    // wrap_save.cpp
};

}  // namespace

}  // namespace talus::lua

extern "C" int luaopen_talus(lua_State* L) {
    using namespace talus::lua;
    openModel(L);
    openBall(L);
    openWall(L);
    openContact(L);
    openClump(L);
    openHistory(L);
    openTracker(L);
    openOutputs(L);
    lua_newtable(L);
    for (const luaL_Reg* table : kModuleFunctionTables) luaL_setfuncs(L, table, 0);
    lua_pushliteral(L, TALUS_VERSION);
    lua_setfield(L, -2, "version");
    // Whether m:threads(n) can run the force loop on n threads (built with OpenMP).
    lua_pushboolean(L, talus::Model::threadingAvailable());
    lua_setfield(L, -2, "openmp");
    return 1;
}
