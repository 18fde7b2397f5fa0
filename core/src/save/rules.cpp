// SPDX-License-Identifier: MIT
//
// Section RULE: the contact-model rules in order (the default rule, group rules, retired
// defaults, the rules m:bond made). Per rule its model's name, the plugin version and the
// model's Version() its data was saved with, then the prototype's state through the plugin's
// SaveRestore (its properties and any state), the groups, specificity, order, activity distance
// and warn-once flags. A restore finds the plugin by name, notes another plugin version, and
// refuses data a newer model version wrote.
#include <cctype>
#include <cmath>
#include <memory>
#include <string>

#include "force/kernels.hpp"
#include "save/sections.hpp"

namespace talus {

void writeRules(const World& world, SaveWriter& w) {
    const auto& rules = world.contacts.rules;
    w.u64(rules.size());
    for (const auto& rp : rules) {
        const Rule& r = *rp;
        w.boolean(r.prototype != nullptr);
        w.str(r.model_name);
        if (r.prototype) {
            // The plugin version as the registry has it now, looked up by name as the restore
            // does.
            const ModelFactory* f = world.registry.tryFind(r.model_name);
            w.str(f ? f->plugin_version : std::string());
            w.i32(r.prototype->Version());
            writeModelState(w, *r.prototype);
        }
        w.i32(r.group_a), w.i32(r.group_b), w.i32(r.specificity), w.i32(r.order);
        w.f64(r.activity);
        w.boolean(r.warned_no_stiffness), w.boolean(r.warned_negative_dissipation);
        w.boolean(r.installed);
    }
    w.u32(world.contacts.rules_version);
    w.f64(world.contacts.max_activity);
}

namespace {

/// The rule's model from the registry, its prototype restored from the file; returns the model
/// Version() the data was saved with.
int32_t readRuleModel(RestoreContext& ctx, SaveReader& r, Rule& rule, std::size_t i) {
    const std::string plugin_version = r.str();
    const int32_t version = r.i32();
    std::vector<uint8_t> state = readModelState(r);
    try {
        rule.factory = &ctx.registry.find(rule.model_name);
        rule.kernel = kernelOf(*rule.factory);
    } catch (const std::exception& e) {
        r.fail("contact model '" + rule.model_name + "' (plugin version " + plugin_version +
               ") is not available: " + e.what());
    }
    if (rule.factory->plugin_version != plugin_version)
        ctx.notes.push_back("contact model '" + rule.model_name + "' was saved by plugin version " +
                            plugin_version + "; the loaded plugin is version " +
                            rule.factory->plugin_version);
    rule.prototype = ctx.registry.createPrototype(*rule.factory);
    if (version > rule.prototype->Version())
        r.fail("contact model '" + rule.model_name + "': its data was saved by " +
               "model version " + std::to_string(version) + " (plugin " + plugin_version +
               "), newer than the loaded plugin's version " +
               std::to_string(rule.prototype->Version()) + " can read");
    applyModelState(r, *rule.prototype, state, version,
                    "rule " + std::to_string(i) + " ('" + rule.model_name + "')");
    rule.pool = std::make_unique<ObjectPool>(rule.prototype->ObjectSize());
    return version;
}

}  // namespace

void readRules(RestoreContext& ctx, SaveReader& r) {
    World& world = ctx.world;
    ContactStore& cs = world.contacts;
    const std::size_t nr = r.count(40, "rules");
    if (nr == 0) r.fail("no rule (the default rule is always saved)");
    cs.rules.clear();
    const auto group_ok = [&](int g) {
        return g >= -1 && g < static_cast<int>(world.bodies.group_names.size());
    };
    for (std::size_t i = 0; i < nr; ++i) {
        auto rule = std::make_unique<Rule>();
        const bool has = r.boolean();
        rule->model_name = r.str();
        // A model name becomes a library name (libtalus_<name>.so) in the plugin search: only
        // names a plugin can have, never a path.
        for (char ch : rule->model_name)
            if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '-')
                r.fail("rule " + std::to_string(i) + ": invalid contact model name");
        ctx.rule_versions.push_back(has ? readRuleModel(ctx, r, *rule, i) : 0);
        rule->group_a = r.i32(), rule->group_b = r.i32();
        rule->specificity = r.i32(), rule->order = r.i32();
        rule->activity = r.f64();
        rule->warned_no_stiffness = r.boolean();
        rule->warned_negative_dissipation = r.boolean();
        rule->installed = r.boolean();
        if (!group_ok(rule->group_a) || !group_ok(rule->group_b))
            r.fail("rule " + std::to_string(i) + " names an unknown group");
        cs.rules.push_back(std::move(rule));
    }
    cs.rules_version = r.u32();
    cs.max_activity = r.f64();
    if (!(cs.max_activity >= 0.0) || !std::isfinite(cs.max_activity))
        r.fail("invalid activity distance");
    r.expectEnd();
}

}  // namespace talus
