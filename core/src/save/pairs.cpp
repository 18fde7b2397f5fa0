// SPDX-License-Identifier: MIT
//
// Section PAIR: every broadphase pair in the store's order (the order of the force sums): its
// ends, rule, flags, forces, the guard's and the automatic step's record, key, stored energies,
// and the contact model object's state through its SaveRestore. A restore clones the rule's
// prototype with the ends' properties (as when the pair was made), then restores the saved
// state into the clone. Then the pairs whose bond broke or was removed (api/bonds.cpp).
//
// Where a pair's fields live in memory (Pair, PairCold, PairStored: world/types.hpp) is known
// to writeRecord and readRecord alone; the rest goes through the contact store.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "save/sections.hpp"
#include "step/detection.hpp"
#include "world/lanes.hpp"

namespace talus {

namespace {

/// A pair's fields in file order (the model object's state follows).
/// `g`: the guard's watch as saved (ContactStore::savedWatch; an unwatched contact's is empty).
void writeRecord(SaveWriter& w, const Pair& p, const PairCold& c, const PairStored& s,
                 const GuardWatch& g) {
    w.u32(p.end1), w.u32(p.end2);
    w.boolean(p.wall), w.boolean(p.active), w.boolean(p.sliding), w.boolean(p.bonded);
    w.boolean(p.loading);
    w.u32(uint32_t{g.steps} | uint32_t{g.apart} << 16);  // (files before the idle count: 0)
    w.u32(p.rule);
    w.f64(c.mass_eff), w.f64(c.inv_mass_eff_s), w.f64(c.activity);
    w.f64(p.n_force), w.f64(p.s_force), w.f64(p.moment), w.f64(c.overlap);
    w.f64(c.knest), w.f64(c.ksest), w.f64(g.work), w.f64(g.work_peak);
    w.f64(g.overlap_max), w.f64(g.force_at_max), w.f64(g.rate_at_max);
    w.f64(g.knest_at_max), w.f64(g.dt_at_max), w.f64(g.approach_rate), w.f64(g.closure);
    w.boolean(g.born_overlapped);
    w.u32(c.rules_version), w.u64(c.key), w.f64(c.krest), w.f64(c.duration);
    w.f64(s.strain), w.f64(s.bond);
}

/// The fields writeRecord wrote (the watch into `g`); returns the rule index (checked by the
/// caller).
uint32_t readRecord(SaveReader& r, Pair& p, PairCold& c, PairStored& s, GuardWatch& g,
                    std::size_t i) {
    p.end1 = r.u32(), p.end2 = r.u32();
    p.wall = r.boolean(), p.active = r.boolean(), p.sliding = r.boolean();
    p.bonded = r.boolean(), p.loading = r.boolean();
    const uint32_t watch = r.u32();
    g.steps = static_cast<uint16_t>(watch & 0xffffu);
    g.apart = static_cast<uint16_t>(watch >> 16);
    const uint32_t rule = r.u32();
    c.mass_eff = r.f64(), c.inv_mass_eff_s = r.f64(), c.activity = r.f64();
    if (!(c.activity >= 0.0) || !std::isfinite(c.activity))
        r.fail("pair " + std::to_string(i) + " has an invalid activity distance");
    p.n_force = r.f64(), p.s_force = r.f64(), p.moment = r.f64(), c.overlap = r.f64();
    c.knest = r.f64(), c.ksest = r.f64(), g.work = r.f64(), g.work_peak = r.f64();
    g.overlap_max = r.f64(), g.force_at_max = r.f64(), g.rate_at_max = r.f64();
    g.knest_at_max = r.f64(), g.dt_at_max = r.f64(), g.approach_rate = r.f64();
    g.closure = r.f64();
    g.born_overlapped = r.boolean();
    c.rules_version = r.u32(), c.key = r.u64(), c.krest = r.f64(), c.duration = r.f64();
    s.strain = r.f64(), s.bond = r.f64();
    return rule;
}

/// The pair's ends exist, are in key order and give its key; its rule has a model.
void checkPair(const World& world, SaveReader& r, const Pair& p, const PairCold& c, uint32_t rule,
               const std::string& at) {
    const BallArrays& b = world.bodies.balls;
    if (p.end1 >= b.size() ||
        (p.wall ? p.end2 >= world.bodies.segments.size() : p.end2 >= b.size()))
        r.fail(at + " names a body out of range");
    if (!p.wall && p.end1 == p.end2) r.fail(at + " joins a ball to itself");
    const uint64_t want = p.wall ? (uint64_t(b.handle[p.end1]) << 32) | (kWallBit | p.end2)
                                 : (uint64_t(std::min(b.handle[p.end1], b.handle[p.end2])) << 32) |
                                       std::max(b.handle[p.end1], b.handle[p.end2]);
    if (c.key != want) r.fail(at + " has a key that does not match its ends");
    if (!p.wall && b.handle[p.end1] > b.handle[p.end2])
        r.fail(at + " has its ends in the wrong order");
    if (rule >= world.contacts.rules.size() || !world.contacts.rules[rule]->prototype)
        r.fail(at + " names an invalid contact-model rule");
}

/// Appends a read pair to the store with a model object cloned as when the pair was made (the
/// ends' properties), then its saved state.
void appendPair(RestoreContext& ctx, SaveReader& r, const Pair& p, const PairCold& c,
                const PairStored& s, const GuardWatch& g, uint32_t rule,
                const std::vector<uint8_t>& state, const std::string& at) {
    World& world = ctx.world;
    ContactStore& cs = world.contacts;
    if (!cs.key_index.emplace(c.key, static_cast<uint32_t>(cs.pairs.size())).second)
        r.fail(at + " repeats the key of another pair");
    cs.pairs.push_back(p);
    cs.cold.push_back(c);
    cs.stored.push_back(s);
    Pair& q = cs.pairs.back();
    cs.restoreWatch(q, cs.cold.back(), g);
    q.model = nullptr;
    try {
        q.model = cloneFor(world, q, cs.cold.back().mass_eff);
    } catch (const std::exception& e) {
        cs.pairs.pop_back();
        cs.cold.pop_back();
        cs.stored.pop_back();
        r.fail(at + ": " + e.what());
    }
    applyModelState(r, *q.model, state, ctx.rule_versions[rule],
                    at + " ('" + cs.ruleOf(q).model_name + "')");
}

}  // namespace

void writePairs(const World& world, SaveWriter& w) {
    const ContactStore& cs = world.contacts;
    w.u64(cs.pairs.size());
    for (std::size_t i = 0; i < cs.pairs.size(); ++i) {
        const Pair& p = cs.pairs[i];
        writeRecord(w, p, cs.cold[i], cs.stored[i], cs.savedWatch(p, cs.cold[i]));
        w.boolean(p.model != nullptr);
        syncLane(cs, p);
        if (p.model) writeModelState(w, *p.model);
    }
    // Pairs whose bond broke or was removed, sorted by key: the map is only looked up, so its
    // order is no state, and sorting makes the file independent of it.
    std::vector<std::pair<uint64_t, uint64_t>> unbonded(cs.unbonded.begin(), cs.unbonded.end());
    std::sort(unbonded.begin(), unbonded.end());
    w.u64(unbonded.size());
    for (const auto& [key, gens] : unbonded) w.u64(key), w.u64(gens);
}

void readPairs(RestoreContext& ctx, SaveReader& r) {
    ContactStore& cs = ctx.world.contacts;
    const std::size_t np = r.count(150, "pairs");
    cs.pairs.reserve(np);
    cs.cold.reserve(np);
    cs.stored.reserve(np);
    for (std::size_t i = 0; i < np; ++i) {
        Pair p;
        PairCold c;
        PairStored s;
        GuardWatch g;
        const uint32_t rule = readRecord(r, p, c, s, g, i);
        const bool has_model = r.boolean();
        const std::string at = "pair " + std::to_string(i);
        checkPair(ctx.world, r, p, c, rule, at);
        if (!has_model) r.fail(at + " has no contact model object");
        p.rule = static_cast<uint16_t>(rule);
        const std::vector<uint8_t> state = readModelState(r);
        appendPair(ctx, r, p, c, s, g, rule, state, at);
    }
    const std::size_t nu = r.count(16, "unbonded pairs");
    for (std::size_t i = 0; i < nu; ++i) {
        const uint64_t key = r.u64();
        if (!cs.unbonded.emplace(key, r.u64()).second) r.fail("an unbonded pair repeats");
    }
    r.expectEnd();
}

}  // namespace talus
