// SPDX-License-Identifier: MIT
// m:bond{...} and m:unbond{...} (docs/lua-api.md, "Bonds"; core/src/model_bonds.cpp).
#include <string>
#include <vector>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"
#include "talus/plugin_registry.hpp"

namespace talus::lua {

namespace {

const Option kBondOptionRows[] = {
    {"model", "string", "the bond model (cbond, pbond, or a plugin with kTraitBond)", true},
    {"props", "table<string, number|string|talus.Distribution>",
     "its properties: a number, a mode's name, or a distribution drawn per contact"},
    {"group", "string", "contacts whose two ends are in this group (default: all bodies)"},
    {"groups", "string|string[]", "{a}: as group; {a, b}: between a body of a and one of b"},
    {"gap", "number", "near-contacts too, up to this gap [m] (default 0)"},
    {"seed", "integer", "seed of the drawn properties (default 1)"},
    {"reset", "boolean", "start stress-free: the bonded contacts' forces go to zero"},
    {"walls", "boolean", "ball-wall contacts too (default false)"},
};
const OptionTable kBondOptions = {"talus.BondOptions",
                                  "m:bond{...}: installs a bond model at the selected contacts",
                                  kBondOptionRows};

const Option kDistributionRows[] = {
    {"mean", "number", "the mean value", true},
    {"sd", "number", "the standard deviation (default 0)"},
    {"dist", "\"normal\"|\"uniform\"", "normal (truncated at zero, the default) or uniform"},
};
const OptionTable kDistribution = {"talus.Distribution", "a property drawn per contact",
                                   kDistributionRows};

const Option kUnbondOptionRows[] = {
    {"group", "string", "contacts whose two ends are in this group (default: all bodies)"},
    {"groups", "string|string[]", "{a}: as group; {a, b}: between a body of a and one of b"},
    {"model", "string", "only the bonds of this model"},
    {"walls", "boolean", "ball-wall contacts too (default true)"},
};
const OptionTable kUnbondOptions = {"talus.UnbondOptions",
                                    "m:unbond{...}: removes the selected contacts' bonds",
                                    kUnbondOptionRows};

/// The selection options shared by bond and unbond: group = "a" or groups = {"a"[, "b"]}.
std::vector<std::string> readSelection(const Options& o) {
    if (o.has("group") && o.has("groups"))
        throw ScriptError(o.what() + ": give 'group' or 'groups', not both");
    std::vector<std::string> g = o.strings(o.has("group") ? "group" : "groups");
    if (g.size() > 2)
        throw ScriptError(o.what() + ": 'groups' names one or two groups (got " +
                          std::to_string(g.size()) + ")");
    if (g.empty() && o.has("groups"))
        throw ScriptError(o.what() + ": 'groups' is empty (omit it to select all bodies)");
    return g;
}

/// props = {name = number | enum name | {mean =, sd =, dist = "normal" | "uniform"}}.
std::vector<BondProp> readBondProps(lua_State* L, int index, const std::string& model) {
    std::vector<BondProp> out;
    if (lua_isnoneornil(L, index)) return out;
    requireTable(L, index, "bond: 'props'");
    const ContactModel* meta = PluginRegistry::global().find(model).reference;
    for (const std::string& key :
         sortedKeys(L, index, "bond: 'props' must be named (pb_ten = 1e7, ...)")) {
        checkPropertyName(meta, key, "bond");
        BondProp bp;
        bp.name = key;
        const std::string what = "bond: property '" + key + "'";
        lua_pushstring(L, key.c_str());
        const int t = lua_rawget(L, index);
        const int v = lua_gettop(L);
        try {
            if (t == LUA_TNUMBER) {
                bp.mean = lua_tonumber(L, v);
            } else if (t == LUA_TBOOLEAN) {
                bp.mean = lua_toboolean(L, v) ? 1.0 : 0.0;
            } else if (t == LUA_TSTRING) {
                // Integer modes by name, as in contact_model.
                const std::string text = lua_tostring(L, v);
                const PropInfo* info = nullptr;
                for (int32_t i = 0; meta && i < meta->PropCount(); ++i) {
                    const PropInfo* pi = meta->PropInfoAt(i);
                    if (pi && lower(pi->name) == lower(key)) info = pi;
                }
                if (!info || !info->enum_names)
                    throw ScriptError(what + " must be a number or {mean =, sd =, dist =} (got \"" +
                                      text + "\")");
                bool found = false;
                std::vector<std::string> names;
                for (int i = 0; info->enum_names[i]; ++i) {
                    names.push_back(std::string("\"") + info->enum_names[i] + "\"");
                    if (text == info->enum_names[i]) bp.mean = i, found = true;
                }
                if (!found)
                    throw ScriptError(what + " must be one of " + joinNames(names) + " (got \"" +
                                      text + "\")");
            } else if (t == LUA_TTABLE) {
                const Options d(L, v, what, kDistribution);
                if (!d.has("mean")) throw ScriptError(what + ": the distribution needs 'mean'");
                bp.mean = d.number("mean", 0.0);
                bp.sd = d.number("sd", 0.0);
                bp.dist = d.choice("dist", 0, {"normal", "uniform"}) == 0 ? BondProp::Normal
                                                                          : BondProp::Uniform;
            } else {
                throw ScriptError(what + " must be a number or {mean =, sd =, dist =} (got " +
                                  typeName(L, v) + ")");
            }
        } catch (...) {
            lua_pop(L, 1);
            throw;
        }
        lua_pop(L, 1);
        out.push_back(bp);
    }
    return out;
}

int w_bond(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "bond");
        const Options o(L, 2, "bond", kBondOptions);
        BondSettings s;
        if (!o.has("model"))
            throw ScriptError("bond: 'model' is required (a bond model: cbond, pbond)");
        s.model = o.string("model", "");
        PluginRegistry::global().find(s.model);  // an unknown model: the registry's error
        o.push("props");
        try {
            s.props = readBondProps(L, lua_gettop(L), s.model);
        } catch (...) {
            lua_pop(L, 1);
            throw;
        }
        lua_pop(L, 1);
        s.groups = readSelection(o);
        s.gap = o.number("gap", 0.0);
        const long long seed = o.integer("seed", 1);
        if (seed < 0)
            throw ScriptError("bond: 'seed' must be >= 0 (got " + std::to_string(seed) + ")");
        s.seed = static_cast<uint64_t>(seed);
        s.reset = o.boolean("reset", false);
        s.walls = o.boolean("walls", false);
        lua_pushinteger(L, static_cast<lua_Integer>(lm.model->bond(s)));
        const ContactModel* meta = PluginRegistry::global().find(s.model).reference;
        std::vector<std::pair<std::string, double>> fric;
        for (const BondProp& p : s.props)
            if (isFrictionCoefficient(p.name, meta)) fric.emplace_back(p.name, p.mean);
        warnImplausibleFriction(&lm, "bond", fric);
        return 1;
    });
}

int w_unbond(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "unbond");
        const Options o(L, 2, "unbond", kUnbondOptions, true);
        BondSettings s;
        s.groups = readSelection(o);
        s.model = o.string("model", "");
        s.walls = o.boolean("walls", true);
        lua_pushinteger(L, static_cast<lua_Integer>(lm.model->unbond(s)));
        return 1;
    });
}

const Method kBondMethods[] = {
    {"bond", w_bond, "installs a bond model at the selected contacts; returns how many",
     "options: talus.BondOptions", "integer"},
    {"unbond", w_unbond, "removes the bonds of the selected contacts; returns how many",
     "options?: talus.UnbondOptions", "integer"},
};

const OptionTable* const kOptionTables[] = {&kBondOptions, &kDistribution, &kUnbondOptions};

}  // namespace

extern const Binding kBondBinding = {"bonds", kBondMethods, {}, {}, kOptionTables, {}};

}  // namespace talus::lua
