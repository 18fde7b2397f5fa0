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
// forces, stiffnesses (knest/ksest/krest, the bond included) and stored energy. So:
//  - the next step's stability limit already holds the bond's stiffness (the limits are surveyed
//    again before it, from the stiffnesses stored here);
//  - the ball forces the next law of motion applies are corrected by the change of the
//    contact's force (zero without `reset` when the model adopts the entry forces);
//  - with tracing on, the change of the stored energy (old model's last report against the new
//    model's) is booked to `released` (a positive increment with `reset`: the strain energy
//    the specimen lets go; in principle negative when the bond model stores more at the same
//    forces, e.g. a larger kn given explicitly), so the balance stays closed.
// Nothing here runs per step: a model without bonds pays nothing (the force loop reads one
// member at a contact's first call).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "api/operations.hpp"
#include "force/force.hpp"
#include "force/kernels.hpp"
#include "props.hpp"
#include "step/detection.hpp"
#include "step/group_energy.hpp"
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

std::size_t Model::bond(const BondSettings& s) {
    World& world = *m_world;
    // ---- validation: everything before anything changes
    const ModelFactory& factory = world.registry.find(s.model);
    PluginRegistry::PrototypePtr proto = world.registry.createPrototype(factory);
    if (!(proto->Traits() & kTraitBond))
        throw InputError("bond: model '" + factory.name +
                         "' is not a bond model (its Traits() lack kTraitBond); use a bond "
                         "model such as cbond or pbond");
    const int32_t bonded_idx = propIndex(*proto, "bonded");
    if (bonded_idx < 0 || (proto->PropInfoAt(bonded_idx)->flags & kPropReadOnly))
        throw InputError("bond: model '" + factory.name +
                         "' declares kTraitBond but has no settable property 'bonded' "
                         "(docs/plugin-abi.md, bond contract)");
    if (!(s.gap >= 0.0) || !std::isfinite(s.gap))
        throw InputError("bond: 'gap' must be a finite length >= 0 m (got " + num(s.gap) + ")");
    int ga, gb;
    selectionGroups(s.groups, "bond", world.bodies.group_names, ga, gb);
    std::vector<int32_t> idx(s.props.size());
    std::vector<PropValue> fixed;
    for (std::size_t k = 0; k < s.props.size(); ++k) {
        const BondProp& bp = s.props[k];
        const std::string where =
            "bond: property '" + bp.name + "' of model '" + factory.name + "'";
        idx[k] = propIndex(*proto, bp.name);
        if (idx[k] < 0)
            throw InputError("bond: unknown property '" + bp.name + "' for model '" + factory.name +
                             "' (known: " + knownProps(*proto) + ")");
        const PropInfo* info = proto->PropInfoAt(idx[k]);
        if (info->flags & kPropReadOnly) throw InputError(where + " is read-only");
        if (idx[k] == bonded_idx)
            throw InputError("bond: 'bonded' is set by bond itself (use m:unbond to remove bonds)");
        for (std::size_t j = 0; j < k; ++j)
            if (idx[j] == idx[k]) throw InputError(where + " is given twice");
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
            if (const std::string why = propValueProblem(*proto, idx[k], v); !why.empty())
                throw InputError(where + " " + why);
            if (proto->AcceptProp(idx[k], v) != 0)
                throw InputError(std::string("bond: ") + proto->LastError());
        }
    }
    // The prototype keeps the defaults plus the given means: a pair that goes back to it (an
    // ended contact with no ordinary rule) is a plain, unbonded copy.
    if (const char* err = proto->PreCycle(emptyPropBlock()))
        throw InputError("bond: model '" + factory.name + "': " + err);

    if (!world.contacts.broadphase_ready) initBroadphase(world);
    auto& b = world.bodies.balls;

    // ---- candidates: existing pairs that are contacts or within the gap, and near pairs the
    // broadphase has not made yet (gap wider than the fat boxes' margin)
    const auto withinGap = [&](const Pair& p) {
        if (p.active) return true;
        Vec2 n, point;
        double overlap;
        return pairGeometry(world, p, n, overlap, point) && overlap >= -s.gap;
    };
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
    std::vector<uint32_t> cand;
    for (std::size_t i = 0; i < world.contacts.pairs.size(); ++i) {
        const Pair& p = world.contacts.pairs[i];
        if (p.model && bondSelects(world, p, s, ga, gb) && withinGap(p))
            cand.push_back(static_cast<uint32_t>(i));
    }
    // Contact order: by key (the ends' handles), so the drawn values do not depend on the pairs'
    // memory order.
    std::sort(cand.begin(), cand.end(), [&](uint32_t x, uint32_t y) {
        return world.contacts.cold[x].key < world.contacts.cold[y].key;
    });

    // ---- the rule that owns the installed objects
    auto rule = std::make_unique<Rule>();
    rule->factory = &factory;
    rule->kernel = kernelOf(factory);
    rule->model_name = factory.name;
    rule->prototype = std::move(proto);
    rule->specificity = 0;  // never matched (ruleFor skips specificity-0 rules after the first)
    rule->order = static_cast<int>(world.contacts.rules.size());
    rule->activity = 0.0;
    rule->pool = std::make_unique<ObjectPool>(rule->prototype->ObjectSize());
    rule->installed = true;
    Rule* bond_rule = rule.get();
    world.contacts.rules.push_back(std::move(rule));
    const ContactModel& bproto = *bond_rule->prototype;
    const int32_t lin_mode_idx = propIndex(bproto, "lin_mode");
    bool lin_mode_given = false;
    for (int32_t k : idx) lin_mode_given |= k == lin_mode_idx;

    std::vector<SplitMix64> streams;
    for (const BondProp& bp : s.props)
        streams.emplace_back((s.seed * 0x9E3779B97F4A7C15ull) ^ nameHash(bp.name));

    const double tdel = world.clock.dt > 0.0                  ? world.clock.dt
                        : world.settings.timestep.fixed > 0.0 ? world.settings.timestep.fixed
                        : world.settings.timestep.max < 1e300 ? world.settings.timestep.max
                                                              : 1e-6;
    const bool energy = world.books.on;
    std::size_t count = 0;
    for (uint32_t i : cand) {
        Pair& p = world.contacts.pairs[i];
        PairCold& c = world.contacts.cold[i];
        PairStored& stored = world.contacts.stored[i];
        Vec2 normal, point;
        double overlap;
        if (!pairGeometry(world, p, normal, overlap, point)) continue;
        // The new object, with the old one's same-named settable properties, then the given ones.
        void* mem = bond_rule->pool->allocate();
        const PropBlock pb = propBlockFor(world, p, c.mass_eff);
        ContactModel* nm = bproto.Clone(pb, mem);
        if (!nm) {
            const std::string why = bproto.LastError();
            bond_rule->pool->release(mem);
            throw PluginError("bond: model '" + factory.name + "' cannot create the model for " +
                              describePair(world, p) + ": " + why);
        }
        const auto fail = [&](const std::string& why) {
            nm->Destroy();
            bond_rule->pool->release(mem);
            throw InputError("bond: " + describePair(world, p) + ": " + why);
        };
        leaveLane(world.contacts, p);
        const ContactModel& old = *p.model;
        for (int32_t k = 0; k < nm->PropCount(); ++k) {
            const PropInfo* info = nm->PropInfoAt(k);
            if (!info || (info->flags & (kPropReadOnly | kPropState)) || k == bonded_idx) continue;
            if (std::find(idx.begin(), idx.end(), k) != idx.end()) continue;
            const int32_t j = propIndex(old, info->name);
            if (j < 0) continue;
            const PropInfo* oi = old.PropInfoAt(j);
            if (!oi || (oi->flags & (kPropReadOnly | kPropState))) continue;
            // A value the bond model refuses (another range, another meaning of a mode) is not
            // carried: the bond model's own value stays.
            nm->AcceptProp(k, old.ReturnProp(j));
        }
        for (std::size_t k = 0; k < s.props.size(); ++k) {
            const double v = drawValue(streams[k], s.props[k]);
            if (nm->AcceptProp(idx[k], v) != 0) fail(nm->LastError());
        }
        if (s.reset && lin_mode_idx >= 0 && !lin_mode_given && nm->AcceptProp(lin_mode_idx, 1.0))
            fail(nm->LastError());
        if (nm->AcceptProp(bonded_idx, 1.0) != 0) fail(nm->LastError());
        if (const char* err = nm->PreCycle(pb)) fail(err);

        // The first call, now: current geometry, no increment, entry forces per the contract.
        FdBlock fd = world.contacts.fd_template;
        fd.flags = kFdFirstCall | (energy ? kFdEnergyOn : 0u);
        fd.status = 0;
        fd.u_n = overlap;
        fd.u_dot_n = fd.u_dot_s = fd.t_dot_rel = 0.0;
        fd.du_n = fd.du_s = fd.dtheta = 0.0;
        fd.tdel = tdel;
        fd.mass_eff = world.contacts.coldOf(p).mass_eff;
        fd.inv_mass_eff_s = world.contacts.coldOf(p).inv_mass_eff_s;
        fd.time = world.clock.time;
        const bool was_active = p.active;
        const double fn_old = was_active ? p.n_force : 0.0;
        const double fs_old = was_active ? p.s_force : 0.0;
        const double m_old = was_active ? p.moment : 0.0;
        fd.n_force = s.reset ? 0.0 : fn_old;
        fd.s_force = s.reset ? 0.0 : fs_old;
        fd.moment = 0.0;
        fd.knest = fd.ksest = fd.krest = 0.0;
        for (double& e : fd.energy) e = 0.0;
        try {
            nm->FDlaw(fd);
        } catch (...) {
            fd.status = 1;
            fd.error = "exception in FDlaw";
        }
        if (fd.status != 0) {
            const std::string why = fd.error ? fd.error : "(no message)";
            fail("the first FDlaw of model '" + factory.name + "' failed: " + why);
        }
        if (!std::isfinite(fd.n_force + fd.s_force + fd.moment + fd.knest + fd.ksest + fd.krest))
            fail("the first FDlaw of model '" + factory.name + "' returned a non-finite value");

        // Swap the objects.
        p.model->Destroy();
        world.contacts.ruleOf(p).pool->release(p.model);
        p.model = nm;
        p.rule = world.contacts.ruleIndex(bond_rule);
        c.activity = checkedActivity(nm->ActivityDistance(), factory.name);
        if (!was_active) ++world.profile.contacts_created;
        p.active = true;
        if (!was_active) world.contacts.startWatch(p, c);  // (an active one keeps its watch)

        // The force the next law of motion applies: the last force loop's, corrected by the
        // change of this contact's force (same geometry: nothing moved since).
        const Vec2 t = perp(normal);
        const Vec2 df = (fd.n_force - fn_old) * normal + (fd.s_force - fs_old) * t;
        const double dm = fd.moment - m_old;
        const Vec2& x1 = b.pos[p.end1];
        b.force[p.end1] -= df;
        b.moment[p.end1] -= cross(point - x1, df) + dm;
        if (!p.wall) {
            b.force[p.end2] += df;
            b.moment[p.end2] += cross(point - b.pos[p.end2], df) + dm;
        } else {
            WallData& w = world.bodies.walls[world.bodies.segments[p.end2].wall];
            w.force += df;
            w.moment += cross(point - w.center, df) + dm;
        }

        // Per-group books: the exchange record the last force loop left for this contact (ends
        // in different groups) carries its force to the next law of motion; correct it too.
        if (world.books.groups.on && (df.squaredNorm() > 0.0 || dm != 0.0)) {
            const uint32_t e2 = p.wall ? world.bodies.segments[p.end2].wall : p.end2;
            for (auto& x : world.books.groups.exchange) {
                if (x.end1 != p.end1 || x.end2 != e2 || x.wall != p.wall) continue;
                x.f1 -= df;
                x.m1 -= cross(point - endCentre(world, p.end1), df) + dm;
                x.m2 += cross(point - (p.wall ? world.bodies.walls[e2].center
                                              : endCentre(world, p.end2)),
                              df) +
                        dm;
                break;
            }
        }

        // Energy: what the old contact stored against what the new one stores, less the part
        // of the old stored energy the bodies never paid for. The old model's report at the last
        // step includes the work of that step's force over the first half of its window (the
        // trapezoid (F_prev + F) du / 2), but the bodies will now feel the new force at this
        // time level instead: that half-step work, (F - F_new) du / 2, was never done (for a
        // linear spring zeroed by a reset this gives F_prev F / 2k, the energy cbond releases
        // when a bond breaks: docs/models/cbond.md, Energies). du from the velocities the last
        // force loop used, which are the current ones (the law of motion has not run since).
        if (energy) {
            const double before = was_active ? stored.total() : 0.0;
            const double after = fd.energy[kEnergyStrain] + fd.energy[kEnergyBondStrain];
            double unpaid = 0.0;
            if (was_active && world.clock.dt > 0.0) {
                Vec2 v2c;
                double spin2;
                if (p.wall) {
                    const WallData& w = world.bodies.walls[world.bodies.segments[p.end2].wall];
                    v2c = w.vel + spinCross(w.spin, point - w.center);
                    spin2 = w.spin;
                } else {
                    v2c = b.vel[p.end2] + spinCross(b.spin[p.end2], point - b.pos[p.end2]);
                    spin2 = b.spin[p.end2];
                }
                const Vec2 vrel = v2c - (b.vel[p.end1] + spinCross(b.spin[p.end1], point - x1));
                const double du_n = -vrel.dot(normal) * world.clock.dt,
                             du_s = vrel.dot(t) * world.clock.dt;
                const double dth = (spin2 - b.spin[p.end1]) * world.clock.dt;
                unpaid = 0.5 * ((fn_old - fd.n_force) * du_n - (fs_old - fd.s_force) * du_s -
                                (m_old - fd.moment) * dth);
            }
            const double change = before - after - unpaid + fd.energy[kEnergyReleased];
            world.books.acc.released += change;
            // The current stored energies as well (the next snapshot may come before the next
            // force loop sums them again).
            world.books.acc.strain += fd.energy[kEnergyStrain] - (was_active ? stored.strain : 0.0);
            world.books.acc.bond += fd.energy[kEnergyBondStrain] - (was_active ? stored.bond : 0.0);
            if (world.books.groups.on) {
                bookReleasedToGroups(world, p, change);
                // The groups' current stored energies, shared as the force loop shares them
                // (group_energy.cpp: half to each ball's groups, all to the ball's for a wall).
                const uint64_t g1 = endGroups(world, p, false), g2 = endGroups(world, p, true);
                const double ds = fd.energy[kEnergyStrain] - (was_active ? stored.strain : 0.0);
                const double db = fd.energy[kEnergyBondStrain] - (was_active ? stored.bond : 0.0);
                auto& books = world.books.groups;
                for (uint64_t mk = (g1 | (p.wall ? 0 : g2)) & books.traced; mk; mk &= mk - 1) {
                    const uint64_t bit = mk & (~mk + 1);
                    const double w =
                        p.wall ? ((g1 & bit) ? 1.0 : 0.0)
                               : 0.5 * (((g1 & bit) ? 1.0 : 0.0) + ((g2 & bit) ? 1.0 : 0.0));
                    auto& gr = books.g[__builtin_ctzll(mk)];
                    gr.acc.strain += w * ds;
                    gr.acc.bond += w * db;
                }
            }
            stored.strain = fd.energy[kEnergyStrain];
            stored.bond = fd.energy[kEnergyBondStrain];
        }

        p.n_force = fd.n_force;
        p.s_force = fd.s_force;
        p.moment = fd.moment;
        world.contacts.coldOf(p).overlap = overlap;
        world.contacts.coldOf(p).knest = fd.knest;
        world.contacts.coldOf(p).ksest = fd.ksest;
        c.krest = fd.krest;
        p.sliding = (fd.flags & kFdSliding) != 0;
        p.bonded = (fd.flags & kFdBonded) != 0;
        // The impact rules' duration for this contact, and the guard: the installed contact
        // holds energy no traced approach put in (like a placed contact, its energy check is
        // skipped) and is a persistent contact, not an impact.
        c.duration = nm->ContactDuration(world.contacts.coldOf(p).mass_eff, 0.0);
        if (!(c.duration > 0.0)) c.duration = HUGE_VAL;
        if (GuardWatch* w = world.contacts.watchOf(c)) w->born_overlapped = true;
        if (fd.flags & kFdBroken) queueBreak(world, i, point, fd);
        ++count;
    }
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
