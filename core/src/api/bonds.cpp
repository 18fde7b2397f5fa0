// SPDX-License-Identifier: MIT
//
// m:bond / m:unbond: installing bond models at contacts and near-contacts (docs/lua-api.md,
// "Bonds"; the bond contract in docs/plugin-abi.md).
//
// Installing a bond replaces the model object of a pair by a fresh clone of the bond model.
// The object comes from a rule made for this call (Rule::installed): ruleFor never matches it,
// so contacts formed later get the ordinary rules, and a bonded pair whose contact ends (its
// bond broke or was removed, and it separated) goes back to the ordinary rules (resetPair).
//
// The host then calls the new object's FDlaw once, at once, with kFdFirstCall, the pair's
// current geometry, zero increments and zero rates, and the old contact's forces on entry (zero
// with `reset`). The model adopts the entry forces as its linear part's force and reports its
// forces, stiffnesses (knest/ksest/krest, the bond included) and stored energy; the host takes
// the call as first_call.cpp says: the next step's stability limit holds the bond's stiffness,
// the ball forces the next law of motion applies are corrected by the change of the contact's
// force (zero without `reset` when the model adopts the entry forces), and with tracing on the
// change of the stored energy goes to `released` (a positive increment with `reset`: the strain
// energy the specimen lets go; in principle negative when the bond model stores more at the
// same forces, e.g. a larger kn given explicitly), so the balance stays closed.
// Nothing here runs per step: a model without bonds pays nothing (the force loop reads one
// member at a contact's first call).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "api/first_call.hpp"
#include "api/operations.hpp"
#include "force/kernels.hpp"
#include "props.hpp"
#include "step/detection.hpp"
#include "step/narrowphase.hpp"
#include "talus/errors.hpp"
#include "talus/splitmix.hpp"
#include "world/body_store.hpp"
#include "world/contact_store.hpp"
#include "world/lanes.hpp"
#include "world/messages.hpp"
#include "world/types.hpp"

namespace talus {

namespace {

std::string num(double v) { return messageNumber(v); }

/// FNV-1a of a property name: each drawn property has its own random stream, so the values do
/// not depend on the order the properties are given in.
uint64_t nameHash(const std::string& s) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
    return h;
}

/// One value of a property (BondProp::dist). Normal: mean + sd z, z standard normal by
/// Box-Muller (cosine branch), redrawn while <= 0 (truncated at zero). Uniform: mean + sd sqrt(3)
/// (2u - 1), the uniform law of that mean and standard deviation.
double drawValue(SplitMix64& rng, const BondProp& bp) {
    switch (bp.dist) {
        case BondProp::Fixed:
            return bp.mean;
        case BondProp::Uniform:
            return bp.mean + bp.sd * std::sqrt(3.0) * (2.0 * rng.uniform() - 1.0);
        case BondProp::Normal:
            // mean > 0 (checked): P(v <= 0) <= 1/2, so 200 redraws fail with p < 1e-60.
            for (int k = 0; k < 200; ++k) {
                const double u1 = 1.0 - rng.uniform();  // (0, 1]
                const double u2 = rng.uniform();
                const double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
                const double v = bp.mean + bp.sd * z;
                if (v > 0.0) return v;
            }
            return bp.mean;
    }
    return bp.mean;
}

const char* distName(BondProp::Dist d) {
    return d == BondProp::Normal ? "normal" : d == BondProp::Uniform ? "uniform" : "fixed";
}

}  // namespace

bool bondSelects(const World& world, const Pair& p, const BondSettings& s, int ga, int gb) {
    if (p.wall && !s.walls) return false;
    if (ga < 0) return true;
    const auto& b = world.bodies.balls;
    const uint64_t g1 = b.groups[p.end1];
    const uint64_t g2 =
        p.wall ? world.bodies.walls[world.bodies.segments[p.end2].wall].groups : b.groups[p.end2];
    const uint64_t a = uint64_t(1) << ga;
    if (gb < 0) return (g1 & a) && (g2 & a);  // both ends in the group
    const uint64_t c = uint64_t(1) << gb;
    return ((g1 & a) && (g2 & c)) || ((g1 & c) && (g2 & a));
}

namespace {

/// The key the bond memory uses: the contact key for two balls; for a ball and a wall, the
/// wall instead of the segment (a contact that re-forms on the next segment of the chain is the
/// same pair of bodies).
uint64_t memoryKey(const Pair& p, uint64_t key, uint32_t wall) {
    return p.wall ? ((key & 0xffffffff00000000ull) | kWallBit | 0x40000000u | wall) : key;
}

}  // namespace

uint32_t autoBondFlags(const World& world, const Pair& p, const PairCold& c) {
    const auto it = world.contacts.unbonded.find(
        memoryKey(p, c.key, p.wall ? world.bodies.segments[p.end2].wall : 0));
    if (it == world.contacts.unbonded.end()) return 0u;
    const uint32_t g1 = world.bodies.generation[world.bodies.balls.handle[p.end1] - 1];
    const uint32_t g2 = p.wall ? world.bodies.walls[world.bodies.segments[p.end2].wall].generation
                               : world.bodies.generation[world.bodies.balls.handle[p.end2] - 1];
    return it->second == ((uint64_t(g1) << 32) | g2) ? uint32_t(kFdNoAutoBond) : 0u;
}

void forgetBond(World& world, std::size_t i) {
    const Pair& p = world.contacts.pairs[i];
    const uint32_t g1 = world.bodies.generation[world.bodies.balls.handle[p.end1] - 1];
    const uint32_t g2 = p.wall ? world.bodies.walls[world.bodies.segments[p.end2].wall].generation
                               : world.bodies.generation[world.bodies.balls.handle[p.end2] - 1];
    world.contacts.unbonded[memoryKey(p, world.contacts.cold[i].key,
                                      p.wall ? world.bodies.segments[p.end2].wall : 0)] =
        (uint64_t(g1) << 32) | g2;
}

namespace {

/// The group indices of a selection; throws naming an unknown group.
void selectionGroups(const std::vector<std::string>& groups, const std::string& what,
                     const std::vector<std::string>& known, int& ga, int& gb) {
    ga = gb = -1;
    if (groups.size() > 2)
        throw InputError(what + ": 'groups' names one or two groups (got " +
                         std::to_string(groups.size()) + ")");
    for (std::size_t k = 0; k < groups.size(); ++k) {
        int idx = -1;
        for (std::size_t i = 0; i < known.size(); ++i)
            if (known[i] == groups[k]) idx = static_cast<int>(i);
        if (idx < 0) {
            std::string list;
            for (const auto& n : known) list += (list.empty() ? "" : ", ") + n;
            throw InputError(what + ": unknown group '" + groups[k] +
                             "' (groups: " + (list.empty() ? "none" : list) + ")");
        }
        (k == 0 ? ga : gb) = idx;
    }
    if (ga >= 0 && gb == ga) gb = -1;  // {"a", "a"}: both ends in a
}

}  // namespace

namespace {

/// What m:bond checked before anything changes: the bond model, its prototype with the given
/// means, the index of its `bonded` property and of each given property, the groups.
struct BondPlan {
    const ModelFactory* factory = nullptr;
    PluginRegistry::PrototypePtr proto;
    int32_t bonded_idx = -1;
    std::vector<int32_t> idx;
    int ga = -1, gb = -1;
};

/// A given property (its index `k` in the model): settable, not `bonded`, given once, a valid
/// distribution, and a value (or a uniform range's ends) the model accepts.
void checkBondProp(const BondPlan& plan, const BondProp& bp, std::size_t k) {
    ContactModel& proto = *plan.proto;
    const std::string& model = plan.factory->name;
    const std::string where = "bond: property '" + bp.name + "' of model '" + model + "'";
    const int32_t index = plan.idx[k];
    if (index < 0)
        throw InputError("bond: unknown property '" + bp.name + "' for model '" + model +
                         "' (known: " + knownProps(proto) + ")");
    const PropInfo* info = proto.PropInfoAt(index);
    if (info->flags & kPropReadOnly) throw InputError(where + " is read-only");
    if (index == plan.bonded_idx)
        throw InputError("bond: 'bonded' is set by bond itself (use m:unbond to remove bonds)");
    for (std::size_t j = 0; j < k; ++j)
        if (plan.idx[j] == index) throw InputError(where + " is given twice");
    if (bp.dist != BondProp::Fixed) {
        const std::string d = std::string(" (dist \"") + distName(bp.dist) + "\")";
        if (!std::isfinite(bp.mean) || !std::isfinite(bp.sd) || !(bp.sd >= 0.0))
            throw InputError(where + ": 'mean' and 'sd' must be finite and sd >= 0 (got mean " +
                             num(bp.mean) + ", sd " + num(bp.sd) + ")" + d);
        if (info->flags & kPropInteger)
            throw InputError(where + " is an integer mode: give a number, not a distribution");
        if (bp.dist == BondProp::Normal && !(bp.mean > 0.0))
            throw InputError(where +
                             ": the normal distribution is truncated at zero and "
                             "needs mean > 0 (got " +
                             num(bp.mean) + ")");
        if (bp.dist == BondProp::Uniform && bp.mean - bp.sd * std::sqrt(3.0) < 0.0)
            throw InputError(where + ": the uniform range mean +- sd*sqrt(3) = [" +
                             num(bp.mean - bp.sd * std::sqrt(3.0)) + ", " +
                             num(bp.mean + bp.sd * std::sqrt(3.0)) + "] goes below zero");
    }
    // The model's own range check, with the mean (and a uniform range's ends).
    std::vector<double> probes{bp.mean};
    if (bp.dist == BondProp::Uniform)
        probes = {bp.mean - bp.sd * std::sqrt(3.0), bp.mean + bp.sd * std::sqrt(3.0)};
    for (double v : probes) {
        if (const std::string why = propValueProblem(proto, index, v); !why.empty())
            throw InputError(where + " " + why);
        if (proto.AcceptProp(index, v) != 0)
            throw InputError(std::string("bond: ") + proto.LastError());
    }
}

/// Everything m:bond checks before anything changes.
BondPlan planBond(World& world, const BondSettings& s) {
    BondPlan plan;
    plan.factory = &world.registry.find(s.model);
    const std::string& model = plan.factory->name;
    plan.proto = world.registry.createPrototype(*plan.factory);
    if (!(plan.proto->Traits() & kTraitBond))
        throw InputError("bond: model '" + model +
                         "' is not a bond model (its Traits() lack kTraitBond); use a bond "
                         "model such as cbond or pbond");
    plan.bonded_idx = propIndex(*plan.proto, "bonded");
    if (plan.bonded_idx < 0 || (plan.proto->PropInfoAt(plan.bonded_idx)->flags & kPropReadOnly))
        throw InputError("bond: model '" + model +
                         "' declares kTraitBond but has no settable property 'bonded' "
                         "(docs/plugin-abi.md, bond contract)");
    if (!(s.gap >= 0.0) || !std::isfinite(s.gap))
        throw InputError("bond: 'gap' must be a finite length >= 0 m (got " + num(s.gap) + ")");
    selectionGroups(s.groups, "bond", world.bodies.group_names, plan.ga, plan.gb);
    plan.idx.resize(s.props.size());
    for (std::size_t k = 0; k < s.props.size(); ++k) {
        plan.idx[k] = propIndex(*plan.proto, s.props[k].name);
        checkBondProp(plan, s.props[k], k);
    }
    // The prototype keeps the defaults plus the given means: a pair that goes back to it (an
    // ended contact with no ordinary rule) is a plain, unbonded copy.
    if (const char* err = plan.proto->PreCycle(emptyPropBlock()))
        throw InputError("bond: model '" + model + "': " + err);
    return plan;
}

/// The pairs of near-contacts the broadphase has not made yet (a gap wider than the fat boxes'
/// margin).
void makeNearPairs(World& world, const BondSettings& s, int ga, int gb) {
    auto& b = world.bodies.balls;
    const auto ballIn = [&](uint32_t slot) {
        if (ga < 0) return true;
        const uint64_t g = b.groups[slot];
        return ((g >> ga) & 1u) || (gb >= 0 && ((g >> gb) & 1u));
    };
    for (uint32_t s1 = 0; s1 < b.size(); ++s1) {
        if (!ballIn(s1)) continue;
        const double r = b.radius[s1] + s.gap;
        const Box box{Vec2(b.pos[s1].x() - r, b.pos[s1].y() - r),
                      Vec2(b.pos[s1].x() + r, b.pos[s1].y() + r)};
        world.contacts.query.clear();
        world.contacts.broadphase->query(box, world.contacts.query);
        const std::vector<int32_t> hits = world.contacts.query;
        for (int32_t h : hits) {
            const uint32_t o = world.bodies.slot_of[world.contacts.broadphase->user(h) - 1];
            if (o == s1) continue;
            const double dist = (b.pos[o] - b.pos[s1]).norm();
            if (dist - b.radius[s1] - b.radius[o] > s.gap) continue;
            makePair(world, s1, o, false);  // no-op when it exists
        }
        if (!s.walls) continue;
        world.contacts.query.clear();
        world.contacts.wall_broadphase->query(box, world.contacts.query);
        const std::vector<int32_t> whits = world.contacts.query;
        for (int32_t h : whits) {
            const uint32_t seg = world.contacts.wall_broadphase->user(h);
            ContactGeometry g;
            if (segmentGeometry(world, seg, b.pos[s1], b.radius[s1], g) && g.overlap >= -s.gap)
                makePair(world, s1, seg, true);
        }
    }
}

/// The pairs to bond: contacts and pairs within the gap that the selection takes, in key order
/// (the ends' handles), so the drawn values do not depend on the pairs' memory order.
std::vector<uint32_t> bondCandidates(const World& world, const BondSettings& s, int ga, int gb) {
    const auto withinGap = [&](const Pair& p) {
        if (p.active) return true;
        Vec2 n, point;
        double overlap;
        return pairGeometry(world, p, n, overlap, point) && overlap >= -s.gap;
    };
    std::vector<uint32_t> cand;
    for (std::size_t i = 0; i < world.contacts.pairs.size(); ++i) {
        const Pair& p = world.contacts.pairs[i];
        if (p.model && bondSelects(world, p, s, ga, gb) && withinGap(p))
            cand.push_back(static_cast<uint32_t>(i));
    }
    std::sort(cand.begin(), cand.end(), [&](uint32_t x, uint32_t y) {
        return world.contacts.cold[x].key < world.contacts.cold[y].key;
    });
    return cand;
}

/// The rule that owns the installed objects: never matched by ruleFor (specificity 0 after the
/// first rule), so contacts formed later get the ordinary rules.
Rule& addBondRule(World& world, BondPlan& plan) {
    auto rule = std::make_unique<Rule>();
    rule->factory = plan.factory;
    rule->kernel = kernelOf(*plan.factory);
    rule->model_name = plan.factory->name;
    rule->prototype = std::move(plan.proto);
    rule->specificity = 0;
    rule->order = static_cast<int>(world.contacts.rules.size());
    rule->activity = 0.0;
    rule->pool = std::make_unique<ObjectPool>(rule->prototype->ObjectSize());
    rule->installed = true;
    world.contacts.rules.push_back(std::move(rule));
    return *world.contacts.rules.back();
}

/// The bond object being installed at one pair, until the pair owns it.
struct NewBond {
    Rule& rule;
    void* mem = nullptr;
    ContactModel* model = nullptr;
    /// Refuses the install at this pair: the new object goes, the pair keeps its old one.
    [[noreturn]] void fail(const World& world, const Pair& p, const std::string& why) {
        model->Destroy();
        rule.pool->release(mem);
        throw InputError("bond: " + describePair(world, p) + ": " + why);
    }
};

/// A fresh clone of the bond model for pair p, with the old object's same-named settable
/// properties, the given (or drawn) ones, lin_mode = 1 with `reset`, bonded = 1, PreCycle.
void cloneBond(World& world, Pair& p, const BondSettings& s, const BondPlan& plan,
               std::vector<SplitMix64>& streams, NewBond& nb) {
    const ContactModel& bproto = *nb.rule.prototype;
    const std::string& model = plan.factory->name;
    nb.mem = nb.rule.pool->allocate();
    const PropBlock pb = propBlockFor(world, p, world.contacts.coldOf(p).mass_eff);
    nb.model = bproto.Clone(pb, nb.mem);
    if (!nb.model) {
        const std::string why = bproto.LastError();
        nb.rule.pool->release(nb.mem);
        throw PluginError("bond: model '" + model + "' cannot create the model for " +
                          describePair(world, p) + ": " + why);
    }
    ContactModel& nm = *nb.model;
    leaveLane(world.contacts, p);
    const ContactModel& old = *p.model;
    for (int32_t k = 0; k < nm.PropCount(); ++k) {
        const PropInfo* info = nm.PropInfoAt(k);
        if (!info || (info->flags & (kPropReadOnly | kPropState)) || k == plan.bonded_idx) continue;
        if (std::find(plan.idx.begin(), plan.idx.end(), k) != plan.idx.end()) continue;
        const int32_t j = propIndex(old, info->name);
        if (j < 0) continue;
        const PropInfo* oi = old.PropInfoAt(j);
        if (!oi || (oi->flags & (kPropReadOnly | kPropState))) continue;
        // A value the bond model refuses (another range, another meaning of a mode) is not
        // carried: the bond model's own value stays.
        nm.AcceptProp(k, old.ReturnProp(j));
    }
    for (std::size_t k = 0; k < s.props.size(); ++k) {
        const double v = drawValue(streams[k], s.props[k]);
        if (nm.AcceptProp(plan.idx[k], v) != 0) nb.fail(world, p, nm.LastError());
    }
    const int32_t lin_mode_idx = propIndex(bproto, "lin_mode");
    const bool lin_mode_given =
        std::find(plan.idx.begin(), plan.idx.end(), lin_mode_idx) != plan.idx.end();
    if (s.reset && lin_mode_idx >= 0 && !lin_mode_given && nm.AcceptProp(lin_mode_idx, 1.0))
        nb.fail(world, p, nm.LastError());
    if (nm.AcceptProp(plan.bonded_idx, 1.0) != 0) nb.fail(world, p, nm.LastError());
    if (const char* err = nm.PreCycle(pb)) nb.fail(world, p, err);
}

/// Installs the bond at pair i: the clone, its first call now (current geometry, no increment,
/// the entry forces per the contract), the objects swapped, then what the host does with the
/// call (first_call.cpp). False when the pair has no geometry (nothing to bond).
bool installBond(World& world, uint32_t i, const BondSettings& s, const BondPlan& plan,
                 Rule& bond_rule, std::vector<SplitMix64>& streams) {
    Pair& p = world.contacts.pairs[i];
    FirstCallGeometry g;
    if (!pairGeometry(world, p, g.normal, g.overlap, g.point)) return false;
    NewBond nb{bond_rule};
    cloneBond(world, p, s, plan, streams, nb);
    FirstCallEntry before;
    before.was_active = p.active;
    if (p.active) before.n_force = p.n_force, before.s_force = p.s_force, before.moment = p.moment;
    FdBlock fd;
    const std::string why = firstCall(world, p, *nb.model, g, s.reset ? 0.0 : before.n_force,
                                      s.reset ? 0.0 : before.s_force, 0u, fd);
    if (!why.empty())
        nb.fail(world, p, "the first FDlaw of model '" + plan.factory->name + "' " + why);
    p.model->Destroy();
    world.contacts.ruleOf(p).pool->release(p.model);
    p.model = nb.model;
    p.rule = world.contacts.ruleIndex(&bond_rule);
    world.contacts.cold[i].activity =
        checkedActivity(nb.model->ActivityDistance(), plan.factory->name);
    takeFirstCall(world, i, g, fd, before);
    return true;
}

}  // namespace

std::size_t Model::bond(const BondSettings& s) {
    World& world = *m_world;
    BondPlan plan = planBond(world, s);
    if (!world.contacts.broadphase_ready) initBroadphase(world);
    makeNearPairs(world, s, plan.ga, plan.gb);
    const std::vector<uint32_t> cand = bondCandidates(world, s, plan.ga, plan.gb);
    Rule& bond_rule = addBondRule(world, plan);
    std::vector<SplitMix64> streams;
    for (const BondProp& bp : s.props)
        streams.emplace_back((s.seed * 0x9E3779B97F4A7C15ull) ^ nameHash(bp.name));
    std::size_t count = 0;
    for (uint32_t i : cand) count += installBond(world, i, s, plan, bond_rule, streams);
    world.stepping.limits_stale = true;
    return count;
}

std::size_t Model::unbond(const BondSettings& s) {
    World& world = *m_world;
    int ga, gb;
    selectionGroups(s.groups, "unbond", world.bodies.group_names, ga, gb);
    if (!s.model.empty()) world.registry.find(s.model);  // an unknown model name is an error
    std::size_t count = 0;
    for (std::size_t i = 0; i < world.contacts.pairs.size(); ++i) {
        Pair& p = world.contacts.pairs[i];
        if (!p.model || !p.active || !(p.model->Traits() & kTraitBond)) continue;
        if (!s.model.empty() && s.model != p.model->Name()) continue;
        if (!bondSelects(world, p, s, ga, gb)) continue;
        const int32_t k = propIndex(*p.model, "bonded");
        syncLane(world.contacts, p);
        if (k < 0 || p.model->ReturnProp(k) != 1.0) continue;
        // No event, and nothing booked here: the forces the last force loop summed, the
        // bond's included, still act over the half step after this one, so what the bond lets
        // go is known at the model's next FDlaw, which books it as released (pbond, cbond:
        // docs/models/pbond.md, cbond.md, Energies). Booking the stored energy now would miss
        // that half step's work (first order in the step) and, for cbond, would book what its
        // unbonded law keeps (a contact in compression).
        leaveLane(world.contacts, p);
        if (p.model->AcceptProp(k, 0.0) != 0)
            throw InputError(std::string("unbond: ") + describePair(world, p) + ": " +
                             p.model->LastError());
        p.bonded = false;
        forgetBond(world, i);
        ++count;
    }
    world.stepping.limits_stale = true;
    return count;
}

}  // namespace talus
