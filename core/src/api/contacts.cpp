// SPDX-License-Identifier: MIT
//
// The facade, contact models and contacts: contact-model rules (default model, group rules, rule
// lookup) and the contact queries (list, find, read and set a contact's properties and forces).
// The data is in the contact store (world/contact_store.hpp).
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "api/operations.hpp"
#include "force/kernels.hpp"
#include "props.hpp"
#include "step/detection.hpp"
#include "step/narrowphase.hpp"
#include "talus/errors.hpp"
#include "talus/model.hpp"
#include "world/body_store.hpp"
#include "world/broadphase.hpp"
#include "world/contact_store.hpp"
#include "world/lanes.hpp"
#include "world/messages.hpp"
#include "world/types.hpp"

namespace talus {

// ------------------------------------------------------------------------ contact-model rules

const ModelFactory& Model::contactModelFactory(const std::string& name) {
    World& world = *m_world;
    return world.registry.find(name);
}

void Model::setDefaultContactModel(const std::string& name, const std::vector<PropValue>& props) {
    addContactModelRule(name, props, "", "");
}

void Model::addContactModelRule(const std::string& name, const std::vector<PropValue>& props,
                                const std::string& group_a, const std::string& group_b) {
    World& world = *m_world;
    requireRuleRoom(world, "contact_model");
    auto rule = std::make_unique<Rule>();
    rule->factory = &world.registry.find(name);
    rule->kernel = kernelOf(*rule->factory);
    rule->model_name = rule->factory->name;
    rule->prototype = world.registry.createPrototype(*rule->factory);
    applyProps(*rule->prototype, props, "contact_model");
    PropBlock pb = emptyPropBlock();
    if (const char* err = rule->prototype->PreCycle(pb))
        throw InputError(std::string("contact_model '") + rule->model_name + "': " + err);
    rule->group_a = group_a.empty() ? -1 : talus::groupIndex(world, group_a, true);
    rule->group_b = group_b.empty() ? -1 : talus::groupIndex(world, group_b, true);
    rule->specificity = (rule->group_a >= 0) + (rule->group_b >= 0);
    rule->order = static_cast<int>(world.contacts.rules.size());
    rule->activity = checkedActivity(rule->prototype->ActivityDistance(), rule->model_name);
    rule->pool = std::make_unique<ObjectPool>(rule->prototype->ObjectSize());
    if (rule->specificity == 0) {
        // A new default replaces the old one for future contacts; the old rule stays alive
        // (existing contacts hold objects from its pool) but is no longer matched.
        world.contacts.rules.push_back(std::move(world.contacts.rules[0]));
        world.contacts.rules[0] = std::move(rule);
        const auto moved = static_cast<uint16_t>(world.contacts.rules.size() - 1);
        for (Pair& p : world.contacts.pairs)
            if (p.rule == 0) p.rule = moved;
    } else {
        world.contacts.rules.push_back(std::move(rule));
    }
    // Pairs that are not in contact pick the new rules up when they touch.
    ++world.contacts.rules_version;
    world.stepping.limits_stale = true;
    world.contacts.max_activity = 0.0;
    for (const auto& r : world.contacts.rules)
        if (r->prototype)
            world.contacts.max_activity = std::max(world.contacts.max_activity, r->activity);
}

double checkedActivity(double activity, const std::string& model) {
    if (!(activity >= 0.0) || !std::isfinite(activity))
        throw PluginError("contact model '" + model + "': ActivityDistance() returned " +
                          messageNumber(activity) + " m (must be finite and >= 0)");
    return activity;
}

void requireRuleRoom(const World& world, const char* what) {
    // Pair::rule is 16 bits wide (the pair's hot record is 48 bytes, world/types.hpp).
    if (world.contacts.rules.size() >= 65535)
        throw InputError(std::string(what) +
                         ": a model holds at most 65 535 contact_model rules and m:bond calls");
}

// ------------------------------------------------------------------------ contacts (queries)

ContactInfo infoOf(const World& world, std::size_t index) {
    const Pair& p = world.contacts.pairs[index];
    ContactInfo c;
    c.key = ContactKey{world.contacts.cold[index].key};
    const uint32_t h1 = world.bodies.balls.handle[p.end1];
    c.ball1 = BallId{h1, world.bodies.generation[h1 - 1]};
    const auto clumpAt = [&](uint32_t slot) {
        const uint32_t k = world.bodies.balls.clump[slot];
        return k == kNoClump ? ClumpId{} : world.bodies.clumpId(k);
    };
    c.clump1 = clumpAt(p.end1);
    if (p.wall) {
        const Segment& s = world.bodies.segments[p.end2];
        c.wall = WallId{s.wall + 1, world.bodies.walls[s.wall].generation};
        c.segment = static_cast<int32_t>(p.end2 - world.bodies.walls[s.wall].first_segment);
    } else {
        const uint32_t h2 = world.bodies.balls.handle[p.end2];
        c.ball2 = BallId{h2, world.bodies.generation[h2 - 1]};
        c.clump2 = clumpAt(p.end2);
    }
    c.active = p.active;
    pairGeometry(world, p, c.normal, c.overlap, c.point);
    c.normal_force = p.n_force;
    c.shear_force = p.s_force;
    c.moment = p.moment;
    c.sliding = p.sliding;
    c.bonded = p.bonded;
    c.model = world.contacts.ruleOf(p).model_name;
    return c;
}

std::size_t Model::contactCount(bool active_only) const {
    const World& world = *m_world;
    if (!active_only) return world.contacts.pairs.size();
    std::size_t n = 0;
    for (const auto& p : world.contacts.pairs) n += p.active;
    return n;
}

std::vector<ContactInfo> Model::contacts(bool active_only) const {
    const World& world = *m_world;
    std::vector<ContactInfo> out;
    // Counted first: a list of a packing's contacts is large, and growing it by doubling would
    // hold one and a half copies at the last growth.
    std::size_t count = world.contacts.pairs.size();
    if (active_only)
        count = static_cast<std::size_t>(std::count_if(world.contacts.pairs.begin(),
                                                       world.contacts.pairs.end(),
                                                       [](const Pair& p) { return p.active; }));
    out.reserve(count);
    for (std::size_t i = 0; i < world.contacts.pairs.size(); ++i)
        if (world.contacts.pairs[i].active || !active_only) out.push_back(infoOf(world, i));
    return out;
}

bool Model::findContact(ContactKey key, ContactInfo& out) const {
    const World& world = *m_world;
    const Pair* p = world.contacts.pairByKey(key);
    if (!p) return false;
    out = infoOf(world, world.contacts.pairIndex(*p));
    return true;
}

double Model::contactProp(ContactKey key, const std::string& name) const {
    const World& world = *m_world;
    const Pair* p = world.contacts.pairByKey(key);
    ContactModel* model = p ? p->model : nullptr;
    if (!model) throw InputError("contact no longer exists");
    const int32_t idx = propIndex(*model, name);
    if (idx < 0)
        throw InputError("contact: unknown property '" + name + "' for model '" + model->Name() +
                         "' (known: " + knownProps(*model) + ")");
    syncLane(world.contacts, *p);
    return model->ReturnProp(idx);
}

void Model::setContactProp(ContactKey key, const std::string& name, double value) {
    World& world = *m_world;
    world.stepping.limits_stale = true;
    Pair* p = world.contacts.pairByKey(key);
    ContactModel* model = p ? p->model : nullptr;
    if (!model) throw InputError("contact no longer exists");
    const int32_t idx = propIndex(*model, name);
    if (idx < 0)
        throw InputError("contact: unknown property '" + name + "' for model '" + model->Name() +
                         "' (known: " + knownProps(*model) + ")");
    if (const std::string why = propValueProblem(*model, idx, value); !why.empty())
        throw InputError(std::string("contact: ") + model->Name() + ": '" + name + "' " + why);
    leaveLane(world.contacts, *p);  // (it comes back after its next FDlaw, with the new value)
    if (model->AcceptProp(idx, value) != 0)
        throw InputError(std::string("contact: ") + model->LastError());
    // A stiffness set to zero on a live contact: the bodies may pass through each other.
    const PropInfo* info = model->PropInfoAt(idx);
    const std::string units = info && info->units ? info->units : "";
    if (value == 0.0 && (units == "N/m" || units == "Pa"))
        talus::warn(world, "contact " + describePair(world, *p) + ": property '" + name +
                               "' of model '" + model->Name() +
                               "' set to 0: the contact may let the bodies pass through");
}

void Model::setContactForce(ContactKey key, double normal_force, double shear_force) {
    World& world = *m_world;
    Pair* p = world.contacts.pairByKey(key);
    if (!p) throw InputError("contact no longer exists");
    if (!std::isfinite(normal_force) || !std::isfinite(shear_force))
        throw InputError("contact: normal_force and shear_force must be finite (got " +
                         messageNumber(normal_force) + ", " + messageNumber(shear_force) + ")");
    p->n_force = normal_force;
    p->s_force = shear_force;
}

void Model::setBroadphaseMargin(double margin) {
    World& world = *m_world;
    // The float broadphase tree works in units of margin / 0.1: a subnormal margin (1e-320)
    // made them infinite and no contact was ever found. Below 1e-9 m the
    // margin is under a double's resolution of coordinates of 1e7 m, and the kinematic rule
    // (no body leaves its fat box in a step) stalls the step. 0 = automatic.
    if (!(margin >= 0.0) || !std::isfinite(margin) || (margin > 0.0 && margin < 1e-9) ||
        margin > 1e9) {
        char got[32];
        std::snprintf(got, sizeof got, "%g", margin);
        throw InputError(
            std::string("broadphase: margin must be 0 (automatic) or in [1e-9, 1e9] m (got ") +
            got + ")");
    }
    world.contacts.margin = margin;
    if (world.contacts.broadphase_ready) {
        // Rebuild with the new margin; existing pairs are kept (makePair finds them), and pairs
        // whose fat boxes no longer overlap are dropped at the next step.
        world.contacts.broadphase_ready = false;
        initBroadphase(world);
        std::fill(world.contacts.ball_moved.begin(), world.contacts.ball_moved.end(), 1);
        std::fill(world.contacts.segment_moved.begin(), world.contacts.segment_moved.end(), 1);
        for (uint32_t s = 0; s < world.contacts.ball_moved.size(); ++s)
            world.contacts.moved_balls.push_back(s);
        for (uint32_t g = 0; g < world.contacts.segment_moved.size(); ++g)
            world.contacts.moved_segments.push_back(g);
    }
}

}  // namespace talus
