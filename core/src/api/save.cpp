// SPDX-License-Identifier: MIT
//
// Save and restore of a whole model (docs/save-format.md). The file is a fixed header (magic,
// format version, byte-order mark, payload length, FNV-1a checksum of the payload) and a payload
// of tagged sections. Everything a cycle reads is saved as it is in memory, down to the order of
// the pairs and the broadphase trees' nodes, because the order in which contact forces are summed
// decides the last bits of every result: a restored model continues bit-identically
// (tests/scripting/save_restore/). The reader checks every count, index and enum before use.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <unordered_set>

#include "force/kernels.hpp"
#include "step/detection.hpp"
#include "talus/errors.hpp"
#include "talus/model.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/save_file.hpp"
#include "talus/save_object.hpp"
#include "world/body_store.hpp"
#include "world/broadphase.hpp"
#include "world/contact_store.hpp"
#include "world/lanes.hpp"
#include "world/types.hpp"

#ifndef TALUS_ENGINE_VERSION
#error "TALUS_ENGINE_VERSION must be defined by the build (project version)"
#endif

namespace talus {

// ------------------------------------------------------------------------ primitives

uint64_t fnv1a64(const uint8_t* p, std::size_t n, uint64_t h) {
    for (std::size_t i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

void SaveWriter::beginSection(const char* tag) {
    bytes(tag, 4);
    m_open.push_back(m_data.size());
    u64(0);
}

void SaveWriter::endSection() {
    const std::size_t at = m_open.back();
    m_open.pop_back();
    const uint64_t len = m_data.size() - at - 8;
    std::memcpy(m_data.data() + at, &len, 8);
}

void SaveReader::fail(const std::string& why) const {
    throw InputError("restore: " + m_where + ": " + why);
}

void SaveReader::expectEnd() const {
    if (!atEnd()) fail(std::to_string(left()) + " unexpected bytes at the end");
}

bool SaveReader::boolean() {
    const uint8_t v = u8();
    if (v > 1) fail("invalid boolean " + std::to_string(v));
    return v != 0;
}

std::size_t SaveReader::count(std::size_t elem_size, const char* what) {
    const uint64_t n = u64();
    if (elem_size && n > left() / elem_size)
        fail(std::string(what) + ": count " + std::to_string(n) + " does not fit in the " +
             std::to_string(left()) + " bytes left");
    return static_cast<std::size_t>(n);
}

std::string SaveReader::str() {
    std::string s(count(1, "string"), '\0');
    bytes(s.data(), s.size());
    return s;
}

std::string SaveReader::peekTag() const {
    if (left() < 4) return "";
    return std::string(reinterpret_cast<const char*>(m_p + m_pos), 4);
}

SaveReader SaveReader::section(const char* tag) {
    if (left() < 12) fail(std::string("section '") + tag + "' is missing (the file ends early)");
    char got[4];
    bytes(got, 4);
    if (std::memcmp(got, tag, 4) != 0) {
        std::string g;
        for (char c : got) g += (c >= 32 && c < 127) ? c : '?';
        fail(std::string("expected section '") + tag + "', found '" + g + "'");
    }
    const std::size_t n = count(1, tag);
    SaveReader sub(m_p + m_pos, n, m_where + ", section '" + tag + "'");
    m_pos += n;
    return sub;
}

namespace {

void writeTotals(SaveWriter& w, const EnergyTotals& e) { w.pod(e); }
EnergyTotals readTotals(SaveReader& r) { return r.pod<EnergyTotals>(); }

// What the script changed since the last step (step/script_work.cpp), booked at the next step.
void writeMotion(SaveWriter& w, const BodyMotion& m) {
    w.f64(m.mass), w.f64(m.inv_mass), w.f64(m.inertia), w.f64(m.inv_inertia);
    w.vec2(m.vel), w.f64(m.spin), w.vec2(m.force), w.f64(m.moment);
    w.u8(m.fixity), w.u64(m.groups);
}
BodyMotion readMotion(SaveReader& r) {
    BodyMotion m;
    m.mass = r.f64(), m.inv_mass = r.f64(), m.inertia = r.f64(), m.inv_inertia = r.f64();
    m.vel = r.vec2(), m.spin = r.f64(), m.force = r.vec2(), m.moment = r.f64();
    m.fixity = r.u8(), m.groups = r.u64();
    return m;
}
void writeScriptChanges(SaveWriter& w, const EnergyBooks::ScriptChanges& sc) {
    w.boolean(sc.seen), w.vec2(sc.gravity);
    w.f64(sc.damping.local), w.f64(sc.damping.viscous);
    w.u64(sc.bodies.size());
    for (const ScriptBody& e : sc.bodies) {
        w.u32(e.index), w.u32(e.generation);
        w.boolean(e.clump), w.boolean(e.existed), w.boolean(e.deleted);
        writeMotion(w, e.before), writeMotion(w, e.gone);
    }
}
void readScriptChanges(SaveReader& r, EnergyBooks::ScriptChanges& sc, const BodyStore& bs) {
    sc.seen = r.boolean(), sc.gravity = r.vec2();
    sc.damping.local = r.f64(), sc.damping.viscous = r.f64();
    sc.bodies.resize(r.count(2 * 89 + 11, "script changes"));
    sc.index.clear();
    for (std::size_t k = 0; k < sc.bodies.size(); ++k) {
        ScriptBody& e = sc.bodies[k];
        e.index = r.u32(), e.generation = r.u32();
        e.clump = r.boolean(), e.existed = r.boolean(), e.deleted = r.boolean();
        e.before = readMotion(r), e.gone = readMotion(r);
        if (e.clump ? e.index >= bs.clumps.size() : (e.index == 0 || e.index > bs.slot_of.size()))
            r.fail("a script change names a body out of range");
        const uint64_t key =
            e.clump ? ((uint64_t(1) << 63) | e.index) : ((uint64_t(e.generation) << 32) | e.index);
        if (!sc.index.emplace(key, k).second) r.fail("a body is named twice in the script changes");
    }
}

void writeTimestep(SaveWriter& w, const TimestepSettings& t) {
    w.boolean(t.automatic);
    w.f64(t.fixed), w.f64(t.safety), w.f64(t.resolution), w.f64(t.max), w.f64(t.growth);
}
TimestepSettings readTimestep(SaveReader& r) {
    TimestepSettings t;
    t.automatic = r.boolean();
    t.fixed = r.f64(), t.safety = r.f64(), t.resolution = r.f64(), t.max = r.f64();
    t.growth = r.f64();
    return t;
}

void writeModelState(SaveWriter& w, ContactModel& m) {
    const std::vector<uint8_t> bytes = saveContactModel(m);
    w.u64(bytes.size());
    w.bytes(bytes.data(), bytes.size());
}

std::vector<uint8_t> readModelState(SaveReader& r) {
    std::vector<uint8_t> bytes(r.count(1, "contact model state"));
    r.bytes(bytes.data(), bytes.size());
    return bytes;
}

/// Restores a contact model's state, naming where in the file it failed.
void applyModelState(SaveReader& r, ContactModel& m, const std::vector<uint8_t>& bytes,
                     int32_t version, const std::string& what) {
    try {
        restoreContactModel(m, bytes, version);
    } catch (const InputError& e) {
        r.fail(what + ": " + e.what());
    }
}

}  // namespace

// ------------------------------------------------------------------------ save

void Model::saveState(SaveWriter& w) const {
    const World& world = *m_world;
    // Trackers are not saved (docs/save-format.md): their records belong to the run that reads
    // them, and their events call back into the script.
    if (!world.trackers.list.empty())
        throw InputError("save: the model has " + std::to_string(world.trackers.list.size()) +
                         " tracker(s), which are not saved; read their records and clear them "
                         "(m:clear_trackers()) before saving");
    // Barriers are not saved yet (docs/rockfall.md, "Barriers"): refused rather than dropped.
    if (!world.barriers.list.empty())
        throw InputError("save: the model has " + std::to_string(world.barriers.list.size()) +
                         " barrier(s), which are not saved yet (what they caught would be lost)");
    const auto& b = world.bodies.balls;

    w.beginSection("SETT");
    w.vec2(world.settings.gravity);
    w.i32(static_cast<int32_t>(world.settings.mass_mode));
    writeTimestep(w, world.settings.timestep);
    writeTimestep(w, world.stepping.last_settings);
    w.i32(static_cast<int32_t>(world.settings.guard.energy)),
        w.f64(world.settings.guard.energy_tolerance);
    w.i32(static_cast<int32_t>(world.settings.guard.resolution)),
        w.i32(world.settings.guard.min_steps);
    w.i32(static_cast<int32_t>(world.settings.guard.stiffness));
    w.i32(static_cast<int32_t>(world.settings.guard.balance)),
        w.f64(world.settings.guard.balance_tolerance);
    w.i64(world.settings.guard.balance_every);
    w.i32(static_cast<int32_t>(world.settings.guard.severe)),
        w.f64(world.settings.guard.severe_created), w.i32(world.settings.guard.severe_min_steps);
    w.f64(world.settings.damping.local), w.f64(world.settings.damping.viscous);
    w.i64(world.settings.sort_every);
    w.boolean(world.callbacks.contact_events);
    w.u64(world.bodies.group_names.size());
    for (const auto& g : world.bodies.group_names) w.str(g);
    w.endSection();

    w.beginSection("CLCK");
    w.f64(world.clock.time), w.i64(world.clock.step), w.f64(world.clock.dt),
        w.f64(world.clock.dt_prev), w.f64(world.clock.window);
    w.i32(static_cast<int32_t>(world.stepping.rule));
    w.i32(static_cast<int32_t>(world.stepping.where.kind)), w.u32(world.stepping.where.index),
        w.u64(world.stepping.where.key);
    w.boolean(world.clock.first_cycle), w.boolean(world.guard_state.warned_no_model),
        w.boolean(world.stepping.limits_stale);
    w.vec2(world.stepping.limits_gravity);
    w.boolean(world.stepping.idle);
    w.f64(world.stepping.cap);
    w.f64(world.stepping.limits.stability), w.f64(world.stepping.limits.resolution),
        w.f64(world.stepping.limits.approach);
    w.u64(world.stepping.limits.stability_key), w.u64(world.stepping.limits.resolution_key),
        w.u64(world.stepping.limits.approach_key);
    w.endSection();

    w.beginSection("BALL");
    w.u64(b.size());
    w.vec2Array(b.pos), w.vec2Array(b.vel), w.vec2Array(b.force), w.vec2Array(b.fapp);
    w.array(b.angle), w.array(b.spin), w.array(b.moment), w.array(b.mapp);
    w.array(b.radius), w.array(b.mass), w.array(b.inv_mass), w.array(b.inertia);
    w.array(b.inv_inertia), w.array(b.density), w.array(b.fixity), w.array(b.handle);
    w.array(b.proxy);
    w.u64(b.fat.size());
    for (const Box& f : b.fat) w.box(f);
    w.array(b.groups), w.array(b.kn), w.array(b.ks), w.array(b.fric);
    w.array(b.k_tran), w.array(b.k_rot), w.array(b.clump);
    w.array(world.bodies.slot_of), w.array(world.bodies.generation),
        w.array(world.bodies.free_handles);
    w.u64(world.bodies.fixed_balls);
    w.endSection();

    w.beginSection("CLMP");
    w.u64(world.bodies.clumps.size());
    for (const ClumpData& c : world.bodies.clumps) {
        w.u32(c.generation), w.boolean(c.alive);
        w.vec2(c.pos), w.vec2(c.vel), w.f64(c.angle), w.f64(c.spin);
        w.f64(c.mass), w.f64(c.inv_mass), w.f64(c.inertia), w.f64(c.inv_inertia);
        w.f64(c.density), w.i32(static_cast<int32_t>(c.mode));
        w.vec2(c.force), w.f64(c.moment), w.vec2(c.fapp), w.f64(c.mapp);
        w.u8(c.fixity), w.u64(c.groups), w.f64(c.kn), w.f64(c.ks), w.f64(c.fric);
        w.array(c.pebbles), w.vec2Array(c.offset), w.array(c.angle_offset);
    }
    w.u64(world.bodies.live_clumps), w.u64(world.bodies.pebble_count);
    w.u64(world.bodies.clump_templates.size());
    for (const ClumpTemplate& t : world.bodies.clump_templates) {
        w.u64(t.pebbles.size());
        for (const Pebble& p : t.pebbles) w.vec2(p.pos), w.f64(p.radius);
        w.i32(static_cast<int32_t>(t.mass_mode));
        w.f64(t.props.area), w.vec2(t.props.centroid), w.f64(t.props.polar_moment);
    }
    w.endSection();

    w.beginSection("WALL");
    w.u64(world.bodies.walls.size());
    for (const WallData& wd : world.bodies.walls) {
        w.u32(wd.generation), w.boolean(wd.alive), w.boolean(wd.closed);
        w.u32(wd.first_segment), w.u32(wd.segment_count);
        w.u32(wd.first_vertex), w.u32(wd.vertex_count);
        w.vec2(wd.vel), w.f64(wd.spin), w.vec2(wd.center), w.u64(wd.groups);
        w.f64(wd.kn), w.f64(wd.ks), w.f64(wd.fric), w.vec2(wd.force), w.f64(wd.moment);
        // Servo (wall_servo.cpp): settings with dir and length resolved, and its last step.
        w.f64(wd.knest), w.boolean(wd.has_servo);
        const WallServoState& sv = wd.servo;
        w.boolean(sv.settings.on), w.boolean(sv.settings.stress), w.f64(sv.settings.target);
        w.f64(sv.settings.length), w.f64(sv.settings.gain), w.f64(sv.settings.alpha);
        w.f64(sv.settings.vmax), w.vec2(sv.settings.dir);
        w.f64(sv.force), w.f64(sv.stress), w.f64(sv.vel), w.f64(sv.gain), w.f64(sv.knest);
    }
    w.i32(world.bodies.servos_on);
    w.u64(world.bodies.segments.size());
    for (const Segment& s : world.bodies.segments) {
        w.u32(s.wall), w.u32(s.a), w.u32(s.b), w.i32(s.prev), w.i32(s.next), w.i32(s.proxy);
        w.box(s.fat);
    }
    w.vec2Array(world.bodies.vertices);
    w.endSection();

    // Rules: per rule its model's name, plugin version and Version(), then the prototype's
    // SaveRestore (the settable properties and any state).
    const auto& rules = world.contacts.rules;
    w.beginSection("RULE");
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
    w.endSection();

    w.beginSection("PAIR");
    const auto& pairs = world.contacts.pairs;
    const auto& cold = world.contacts.cold;
    w.u64(pairs.size());
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        const Pair& p = pairs[i];
        const PairCold& c = cold[i];
        w.u32(p.end1), w.u32(p.end2);
        w.boolean(p.wall), w.boolean(p.active), w.boolean(p.sliding), w.boolean(p.bonded);
        w.boolean(p.loading);
        w.u32(uint32_t{c.steps} | uint32_t{c.apart} << 16);  // (files before the idle count: 0)
        w.u32(p.rule);
        w.f64(c.mass_eff), w.f64(c.inv_mass_eff_s), w.f64(c.activity);
        w.f64(p.n_force), w.f64(p.s_force), w.f64(p.moment), w.f64(c.overlap);
        w.f64(c.knest), w.f64(c.ksest), w.f64(c.work), w.f64(c.work_peak);
        w.f64(c.overlap_max), w.f64(c.force_at_max), w.f64(c.rate_at_max);
        w.f64(c.knest_at_max), w.f64(c.dt_at_max), w.f64(c.approach_rate), w.f64(c.closure);
        w.boolean(c.born_overlapped);
        w.u32(c.rules_version), w.u64(c.key), w.f64(c.krest), w.f64(c.duration);
        w.f64(world.contacts.stored[i].strain), w.f64(world.contacts.stored[i].bond);
        w.boolean(p.model != nullptr);
        syncLane(world.contacts, p);
        if (p.model) writeModelState(w, *p.model);
    }
    // Pairs whose bond broke or was removed (api/bonds.cpp), sorted by key: the map is only
    // looked up, so its order is no state, and sorting makes the file independent of it.
    std::vector<std::pair<uint64_t, uint64_t>> unbonded(world.contacts.unbonded.begin(),
                                                        world.contacts.unbonded.end());
    std::sort(unbonded.begin(), unbonded.end());
    w.u64(unbonded.size());
    for (const auto& [key, gens] : unbonded) w.u64(key), w.u64(gens);
    w.endSection();

    w.beginSection("BRPH");
    w.f64(world.contacts.margin);
    w.boolean(world.contacts.broadphase_ready);
    if (world.contacts.broadphase_ready) {
        world.contacts.broadphase->save(w);
        world.contacts.wall_broadphase->save(w);
    }
    w.array(world.contacts.moved_balls), w.array(world.contacts.moved_segments);
    w.array(world.contacts.ball_moved), w.array(world.contacts.segment_moved);
    w.endSection();

    w.beginSection("ENRG");
    const EnergyBooks& e = world.books;
    w.boolean(e.on);
    writeTotals(w, e.acc), writeTotals(w, e.snapshot);
    // (the flag that once said "the next force loop books the contacts' baseline" now says
    // "the books are still opening": a file of either kind restores with the books opening)
    w.f64(e.dashpot_pending), w.boolean(e.opening != 0 || e.strain_baseline_pending),
        w.f64(e.last_placed);
    w.boolean(e.groups.on), w.u64(e.groups.traced);
    w.u64(e.groups.g.size());
    for (const auto& g : e.groups.g) w.pod(g);
    w.u64(e.groups.exchange.size());
    for (const auto& x : e.groups.exchange) {
        w.u32(x.end1), w.u32(x.end2), w.boolean(x.wall), w.boolean(x.gone1), w.boolean(x.gone2);
        w.u64(x.g1), w.u64(x.g2), w.vec2(x.f1), w.f64(x.m1), w.f64(x.m2);
        w.vec2(x.v1), w.vec2(x.v2), w.f64(x.w1), w.f64(x.w2);
    }
    writeScriptChanges(w, e.script);
    w.endSection();

    w.beginSection("GARD");
    const GuardState& g = world.guard_state;
    w.i64(g.underresolved), w.str(g.underresolved_first);
    w.i64(g.energy_gain), w.str(g.energy_gain_first);
    w.i64(g.stiffness_lies), w.str(g.stiffness_lies_first);
    w.i64(g.placed), w.f64(g.placed_energy), w.str(g.placed_first);
    writeTotals(w, g.balance.open);
    w.i64(g.balance.open_step), w.f64(g.balance.peak), w.f64(g.balance.reported);
    w.i64(g.balance.findings), w.str(g.balance.first), w.str(g.balance.last);
    w.endSection();

    w.beginSection("EVNT");
    w.u64(world.callbacks.events.size());
    for (const Event& ev : world.callbacks.events) {
        w.i32(static_cast<int32_t>(ev.kind)), w.f64(ev.time), w.vec2(ev.pos);
        w.u64(ev.contact.value), w.i32(ev.mode), w.str(ev.model);
    }
    w.endSection();
}

// ------------------------------------------------------------------------ restore

std::unique_ptr<Model> Model::restoreState(SaveReader& in, PluginRegistry& registry,
                                           std::vector<std::string>& notes) {
    auto mp = std::make_unique<Model>(ModelDef{}, registry);
    World& world = *mp->m_world;
    auto& bs = world.bodies;
    auto& cs = world.contacts;
    auto& b = bs.balls;
    std::vector<int32_t> rule_versions;  // per rule: the Version() its data was saved with

    {
        SaveReader r = in.section("SETT");
        world.settings.gravity = r.vec2();
        if (!std::isfinite(world.settings.gravity.x()) ||
            !std::isfinite(world.settings.gravity.y()))
            r.fail("gravity is not finite");
        world.settings.mass_mode = r.enumValue<MassMode>(2, "mass mode");
        world.settings.timestep = readTimestep(r);
        world.stepping.last_settings = readTimestep(r);
        world.settings.guard.energy = r.enumValue<GuardAction>(3, "guard energy");
        world.settings.guard.energy_tolerance = r.f64();
        world.settings.guard.resolution = r.enumValue<GuardAction>(3, "guard resolution");
        world.settings.guard.min_steps = r.i32();
        world.settings.guard.stiffness = r.enumValue<GuardAction>(3, "guard stiffness");
        world.settings.guard.balance = r.enumValue<GuardAction>(3, "guard balance");
        world.settings.guard.balance_tolerance = r.f64();
        world.settings.guard.balance_every = r.i64();
        if (world.settings.guard.balance_every < 1) r.fail("guard balance_every must be >= 1");
        world.settings.guard.severe = r.enumValue<GuardAction>(3, "guard severe");
        world.settings.guard.severe_created = r.f64();
        world.settings.guard.severe_min_steps = r.i32();
        world.settings.damping.local = r.f64();
        world.settings.damping.viscous = r.f64();
        world.settings.sort_every = r.i64();
        if (world.settings.sort_every < Model::kSortAuto) r.fail("sort interval must be >= -1");
        world.callbacks.contact_events = r.boolean();
        const std::size_t ng = r.count(8, "group names");
        if (ng > 64) r.fail("more than 64 group names");
        for (std::size_t i = 0; i < ng; ++i) world.bodies.group_names.push_back(r.str());
        world.stepping.guard_was_on = world.settings.guard.anyOn();
        r.expectEnd();
    }
    {
        SaveReader r = in.section("CLCK");
        world.clock.time = r.f64(), world.clock.step = r.i64(), world.clock.dt = r.f64(),
        world.clock.dt_prev = r.f64();
        world.clock.window = r.f64();
        world.stepping.rule = r.enumValue<StepRule>(9, "step rule");
        world.stepping.where.kind = r.enumValue<StepWhere::Kind>(4, "step origin");
        world.stepping.where.index = r.u32(), world.stepping.where.key = r.u64();
        world.clock.first_cycle = r.boolean(), world.guard_state.warned_no_model = r.boolean();
        world.stepping.limits_stale = r.boolean();
        world.stepping.limits_gravity = r.vec2();
        world.stepping.idle = r.boolean();
        world.stepping.cap = r.f64();
        world.stepping.limits.stability = r.f64(), world.stepping.limits.resolution = r.f64();
        world.stepping.limits.approach = r.f64();
        world.stepping.limits.stability_key = r.u64(),
        world.stepping.limits.resolution_key = r.u64();
        world.stepping.limits.approach_key = r.u64();
        if (world.clock.step < 0) r.fail("negative step count");
        r.expectEnd();
    }
    {
        SaveReader r = in.section("BALL");
        const std::size_t n = r.count(8 * 20, "balls");
        if (n >= kDeadSlot) r.fail("too many balls");
        b.resize(n);
        auto vecs = [&](std::vector<Vec2>& v, const char* what) {
            r.vec2Array(v, what);
            if (v.size() != n) r.fail(std::string(what) + ": wrong number of entries");
        };
        vecs(b.pos, "pos"), vecs(b.vel, "vel"), vecs(b.force, "force"), vecs(b.fapp, "fapp");
        r.array(b.angle, n, "angle"), r.array(b.spin, n, "spin"), r.array(b.moment, n, "moment");
        r.array(b.mapp, n, "mapp"), r.array(b.radius, n, "radius"), r.array(b.mass, n, "mass");
        r.array(b.inv_mass, n, "inv_mass"), r.array(b.inertia, n, "inertia");
        r.array(b.inv_inertia, n, "inv_inertia"), r.array(b.density, n, "density");
        r.array(b.fixity, n, "fixity"), r.array(b.handle, n, "handle");
        r.array(b.proxy, n, "proxy");
        if (r.count(32, "fat boxes") != n) r.fail("fat boxes: wrong number of entries");
        for (Box& f : b.fat) f = r.box();
        r.array(b.groups, n, "groups"), r.array(b.kn, n, "kn"), r.array(b.ks, n, "ks");
        r.array(b.fric, n, "fric"), r.array(b.k_tran, n, "k_tran"), r.array(b.k_rot, n, "k_rot");
        r.array(b.clump, n, "clump");
        r.array(bs.slot_of, "handle table");
        r.array(bs.generation, bs.slot_of.size(), "generations");
        r.array(bs.free_handles, "free handles");
        world.bodies.fixed_balls = r.u64();
        r.expectEnd();
        // The handle tables: every live slot named by exactly one handle, and back.
        for (std::size_t s = 0; s < n; ++s) {
            const uint32_t h = b.handle[s];
            if (h == 0 || h > bs.slot_of.size() || bs.slot_of[h - 1] != s)
                r.fail("ball slot " + std::to_string(s) + " has an invalid handle");
            if (!(b.radius[s] > 0.0) || !std::isfinite(b.radius[s]))
                r.fail("ball slot " + std::to_string(s) + " has an invalid radius");
        }
        std::size_t live = 0, fixed = 0;
        for (uint32_t slot : bs.slot_of) {
            if (slot == kDeadSlot) continue;
            if (slot >= n) r.fail("the handle table names a slot out of range");
            ++live;
        }
        if (live != n) r.fail("the handle table does not match the balls");
        for (uint32_t h : bs.free_handles)
            if (h == 0 || h > bs.slot_of.size() || bs.slot_of[h - 1] != kDeadSlot)
                r.fail("a free handle is in use or out of range");
        for (uint8_t f : b.fixity) {
            if (f > (kFixX | kFixY | kFixSpin)) r.fail("invalid fixity bits");
            fixed += f != 0;
        }
        if (fixed != world.bodies.fixed_balls) r.fail("the count of fixed balls does not match");
    }
    {
        SaveReader r = in.section("CLMP");
        const std::size_t nc = r.count(100, "clumps");
        bs.clumps.resize(nc);
        for (std::size_t k = 0; k < nc; ++k) {
            ClumpData& c = bs.clumps[k];
            c.generation = r.u32(), c.alive = r.boolean();
            c.pos = r.vec2(), c.vel = r.vec2(), c.angle = r.f64(), c.spin = r.f64();
            c.mass = r.f64(), c.inv_mass = r.f64(), c.inertia = r.f64(), c.inv_inertia = r.f64();
            c.density = r.f64();
            c.mode = r.enumValue<ClumpMassMode>(3, "clump mass mode");
            c.force = r.vec2(), c.moment = r.f64(), c.fapp = r.vec2(), c.mapp = r.f64();
            c.fixity = r.u8(), c.groups = r.u64();
            c.kn = r.f64(), c.ks = r.f64(), c.fric = r.f64();
            r.array(c.pebbles, "pebbles");
            r.vec2Array(c.offset, "pebble offsets");
            r.array(c.angle_offset, "pebble angles");
            if (c.offset.size() != c.pebbles.size() || c.angle_offset.size() != c.pebbles.size())
                r.fail("clump " + std::to_string(k + 1) + ": pebble arrays differ in length");
            if (c.fixity > (kFixX | kFixY | kFixSpin)) r.fail("invalid clump fixity bits");
        }
        bs.live_clumps = r.u64(), bs.pebble_count = r.u64();
        const std::size_t nt = r.count(8, "clump templates");
        world.bodies.clump_templates.resize(nt);
        for (ClumpTemplate& t : world.bodies.clump_templates) {
            t.pebbles.resize(r.count(24, "template pebbles"));
            for (Pebble& p : t.pebbles) p.pos = r.vec2(), p.radius = r.f64();
            t.mass_mode = r.enumValue<ClumpMassMode>(3, "template mass mode");
            t.props.area = r.f64(), t.props.centroid = r.vec2(), t.props.polar_moment = r.f64();
        }
        r.expectEnd();
        // Pebbles and their clumps name each other.
        std::size_t live = 0, pebbles = 0;
        for (std::size_t k = 0; k < nc; ++k) {
            const ClumpData& c = bs.clumps[k];
            if (!c.alive) {
                if (!c.pebbles.empty()) r.fail("a deleted clump has pebbles");
                continue;
            }
            ++live;
            if (c.pebbles.empty()) r.fail("clump " + std::to_string(k + 1) + " has no pebbles");
            for (uint32_t h : c.pebbles) {
                if (h == 0 || h > bs.slot_of.size() || bs.slot_of[h - 1] == kDeadSlot ||
                    b.clump[bs.slot_of[h - 1]] != k)
                    r.fail("clump " + std::to_string(k + 1) + " names an invalid pebble");
                ++pebbles;
            }
        }
        std::size_t marked = 0;
        for (uint32_t k : b.clump) {
            if (k == kNoClump) continue;
            if (k >= nc || !bs.clumps[k].alive) r.fail("a ball names an invalid clump");
            ++marked;
        }
        if (live != bs.live_clumps || pebbles != bs.pebble_count || marked != pebbles)
            r.fail("the clump counts do not match");
    }
    {
        SaveReader r = in.section("WALL");
        const std::size_t nw = r.count(200, "walls");
        bs.walls.resize(nw);
        for (WallData& wd : bs.walls) {
            wd.generation = r.u32(), wd.alive = r.boolean(), wd.closed = r.boolean();
            wd.first_segment = r.u32(), wd.segment_count = r.u32();
            wd.first_vertex = r.u32(), wd.vertex_count = r.u32();
            wd.vel = r.vec2(), wd.spin = r.f64(), wd.center = r.vec2(), wd.groups = r.u64();
            wd.kn = r.f64(), wd.ks = r.f64(), wd.fric = r.f64();
            wd.force = r.vec2(), wd.moment = r.f64();
            wd.knest = r.f64(), wd.has_servo = r.boolean();
            WallServoState& sv = wd.servo;
            sv.settings.on = r.boolean(), sv.settings.stress = r.boolean();
            sv.settings.target = r.f64(), sv.settings.length = r.f64();
            sv.settings.gain = r.f64(), sv.settings.alpha = r.f64(), sv.settings.vmax = r.f64();
            sv.settings.dir = r.vec2();
            sv.force = r.f64(), sv.stress = r.f64(), sv.vel = r.f64(), sv.gain = r.f64();
            sv.knest = r.f64();
        }
        world.bodies.servos_on = r.i32();
        int servos = 0;
        for (const WallData& wd : bs.walls)
            servos += wd.alive && wd.has_servo && wd.servo.settings.on;
        bs.segments.resize(r.count(56, "segments"));
        for (Segment& s : bs.segments) {
            s.wall = r.u32(), s.a = r.u32(), s.b = r.u32();
            s.prev = r.i32(), s.next = r.i32(), s.proxy = r.i32();
            s.fat = r.box();
        }
        r.vec2Array(bs.vertices, "vertices");
        r.expectEnd();
        if (servos != world.bodies.servos_on)
            r.fail("the count of servos switched on does not match");
        const uint64_t ns = bs.segments.size(), nv = bs.vertices.size();
        for (const WallData& wd : bs.walls)
            if (uint64_t(wd.first_segment) + wd.segment_count > ns ||
                uint64_t(wd.first_vertex) + wd.vertex_count > nv)
                r.fail("a wall names segments or vertices out of range");
        for (std::size_t i = 0; i < ns; ++i) {
            const Segment& s = bs.segments[i];
            const auto seg_ok = [&](int32_t k) { return k >= -1 && k < int64_t(ns); };
            if (s.wall >= nw || s.a >= nv || s.b >= nv || !seg_ok(s.prev) || !seg_ok(s.next))
                r.fail("segment " + std::to_string(i) + " is inconsistent");
            const WallData& wd = bs.walls[s.wall];
            if (i < wd.first_segment || i >= uint64_t(wd.first_segment) + wd.segment_count)
                r.fail("segment " + std::to_string(i) + " is outside its wall");
            if (s.prev >= 0 && bs.segments[s.prev].wall != s.wall)
                r.fail("segment " + std::to_string(i) + " links to another wall");
            if (s.next >= 0 && bs.segments[s.next].wall != s.wall)
                r.fail("segment " + std::to_string(i) + " links to another wall");
            if (s.a == s.b) r.fail("segment " + std::to_string(i) + " has one vertex");
        }
    }
    {
        SaveReader r = in.section("RULE");
        const std::size_t nr = r.count(40, "rules");
        if (nr == 0) r.fail("no rule (the default rule is always saved)");
        cs.rules.clear();
        for (std::size_t i = 0; i < nr; ++i) {
            auto rule = std::make_unique<Rule>();
            const bool has = r.boolean();
            rule->model_name = r.str();
            // A model name becomes a library name (libtalus_<name>.so) in the plugin search:
            // only names a plugin can have, never a path.
            for (char ch : rule->model_name)
                if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '-')
                    r.fail("rule " + std::to_string(i) + ": invalid contact model name");
            if (has) {
                const std::string plugin_version = r.str();
                const int32_t version = r.i32();
                std::vector<uint8_t> state = readModelState(r);
                try {
                    rule->factory = &registry.find(rule->model_name);
                    rule->batch = rule->factory->batch;
                    rule->kernel = kernelOf(*rule->factory);
                } catch (const std::exception& e) {
                    r.fail("contact model '" + rule->model_name + "' (plugin version " +
                           plugin_version + ") is not available: " + e.what());
                }
                if (rule->factory->plugin_version != plugin_version)
                    notes.push_back("contact model '" + rule->model_name +
                                    "' was saved by plugin version " + plugin_version +
                                    "; the loaded plugin is version " +
                                    rule->factory->plugin_version);
                rule->prototype = registry.createPrototype(*rule->factory);
                if (version > rule->prototype->Version())
                    r.fail("contact model '" + rule->model_name + "': its data was saved by " +
                           "model version " + std::to_string(version) + " (plugin " +
                           plugin_version + "), newer than the loaded plugin's version " +
                           std::to_string(rule->prototype->Version()) + " can read");
                applyModelState(r, *rule->prototype, state, version,
                                "rule " + std::to_string(i) + " ('" + rule->model_name + "')");
                rule->pool = std::make_unique<ObjectPool>(rule->prototype->ObjectSize());
                rule_versions.push_back(version);
            } else {
                rule_versions.push_back(0);
            }
            rule->group_a = r.i32(), rule->group_b = r.i32();
            rule->specificity = r.i32(), rule->order = r.i32();
            rule->activity = r.f64();
            rule->warned_no_stiffness = r.boolean();
            rule->warned_negative_dissipation = r.boolean();
            rule->installed = r.boolean();
            const auto group_ok = [&](int g) {
                return g >= -1 && g < static_cast<int>(world.bodies.group_names.size());
            };
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
    {
        SaveReader r = in.section("PAIR");
        const std::size_t np = r.count(150, "pairs");
        cs.pairs.reserve(np);
        cs.cold.reserve(np);
        cs.stored.reserve(np);
        for (std::size_t i = 0; i < np; ++i) {
            Pair p;
            PairCold c;
            p.end1 = r.u32(), p.end2 = r.u32();
            p.wall = r.boolean(), p.active = r.boolean(), p.sliding = r.boolean();
            p.bonded = r.boolean(), p.loading = r.boolean();
            const uint32_t watch = r.u32();
            c.steps = static_cast<uint16_t>(watch & 0xffffu);
            c.apart = static_cast<uint16_t>(watch >> 16);
            const uint32_t rule = r.u32();
            c.mass_eff = r.f64(), c.inv_mass_eff_s = r.f64(), c.activity = r.f64();
            if (!(c.activity >= 0.0) || !std::isfinite(c.activity))
                r.fail("pair " + std::to_string(i) + " has an invalid activity distance");
            p.n_force = r.f64(), p.s_force = r.f64(), p.moment = r.f64(), c.overlap = r.f64();
            c.knest = r.f64(), c.ksest = r.f64(), c.work = r.f64(), c.work_peak = r.f64();
            c.overlap_max = r.f64(), c.force_at_max = r.f64(), c.rate_at_max = r.f64();
            c.knest_at_max = r.f64(), c.dt_at_max = r.f64(), c.approach_rate = r.f64();
            c.closure = r.f64();
            c.born_overlapped = r.boolean();
            c.rules_version = r.u32(), c.key = r.u64(), c.krest = r.f64(), c.duration = r.f64();
            PairStored held;
            held.strain = r.f64(), held.bond = r.f64();
            const bool has_model = r.boolean();
            const std::string at = "pair " + std::to_string(i);
            if (p.end1 >= b.size() || (p.wall ? p.end2 >= bs.segments.size() : p.end2 >= b.size()))
                r.fail(at + " names a body out of range");
            if (!p.wall && p.end1 == p.end2) r.fail(at + " joins a ball to itself");
            const uint64_t want =
                p.wall ? (uint64_t(b.handle[p.end1]) << 32) | (kWallBit | p.end2)
                       : (uint64_t(std::min(b.handle[p.end1], b.handle[p.end2])) << 32) |
                             std::max(b.handle[p.end1], b.handle[p.end2]);
            if (c.key != want) r.fail(at + " has a key that does not match its ends");
            if (!p.wall && b.handle[p.end1] > b.handle[p.end2])
                r.fail(at + " has its ends in the wrong order");
            if (rule >= cs.rules.size() || !cs.rules[rule]->prototype)
                r.fail(at + " names an invalid contact-model rule");
            if (!has_model) r.fail(at + " has no contact model object");
            p.rule = static_cast<uint16_t>(rule);
            std::vector<uint8_t> state = readModelState(r);
            if (!cs.key_index.emplace(c.key, static_cast<uint32_t>(cs.pairs.size())).second)
                r.fail(at + " repeats the key of another pair");
            cs.pairs.push_back(p);
            cs.cold.push_back(c);
            cs.stored.push_back(held);
            // Clone with the ends' properties (as the pair was made), then its saved state.
            Pair& q = cs.pairs.back();
            PairCold& qc = cs.cold.back();
            q.watched = q.active && qc.steps <= kGuardWatch;
            q.model = nullptr;
            try {
                q.model = cloneFor(world, q, qc.mass_eff);
            } catch (const std::exception& e) {
                cs.pairs.pop_back();
                cs.cold.pop_back();
                cs.stored.pop_back();
                r.fail(at + ": " + e.what());
            }
            applyModelState(r, *q.model, state, rule_versions[rule],
                            at + " ('" + world.contacts.ruleOf(q).model_name + "')");
        }
        const std::size_t nu = r.count(16, "unbonded pairs");
        for (std::size_t i = 0; i < nu; ++i) {
            const uint64_t key = r.u64();
            if (!cs.unbonded.emplace(key, r.u64()).second) r.fail("an unbonded pair repeats");
        }
        r.expectEnd();
    }
    {
        SaveReader r = in.section("BRPH");
        cs.margin = r.f64();
        if (!(cs.margin >= 0.0) || !std::isfinite(cs.margin)) r.fail("invalid margin");
        cs.broadphase_ready = r.boolean();
        if (cs.broadphase_ready) {
            cs.broadphase->restore(r);
            cs.wall_broadphase->restore(r);
            // Every body's proxy is a leaf naming that body, and there are no other leaves
            // (a query's hit is turned into a slot through the leaf's body).
            std::unordered_set<int32_t> used;
            for (std::size_t s = 0; s < b.size(); ++s)
                if (!cs.broadphase->isLeaf(b.proxy[s]) ||
                    cs.broadphase->user(b.proxy[s]) != b.handle[s] ||
                    !used.insert(b.proxy[s]).second)
                    r.fail("ball slot " + std::to_string(s) + " has an invalid broadphase proxy");
            if (cs.broadphase->leafCount() != b.size())
                r.fail("the ball tree holds bodies that do not exist");
            used.clear();
            std::size_t segs = 0;
            for (std::size_t g = 0; g < bs.segments.size(); ++g) {
                const int32_t px = bs.segments[g].proxy;
                if (!bs.walls[bs.segments[g].wall].alive && px == -1) continue;
                if (!cs.wall_broadphase->isLeaf(px) || cs.wall_broadphase->user(px) != g ||
                    !used.insert(px).second)
                    r.fail("segment " + std::to_string(g) + " has an invalid broadphase proxy");
                ++segs;
            }
            if (cs.wall_broadphase->leafCount() != segs)
                r.fail("the wall tree holds segments that do not exist");
        }
        r.array(cs.moved_balls, "moved balls"), r.array(cs.moved_segments, "moved segments");
        r.array(cs.ball_moved, "ball flags"), r.array(cs.segment_moved, "segment flags");
        // The force loop reads a flag per ball and per segment, and the detection clears the
        // flags of the listed bodies: sizes and entries must match the bodies.
        if (cs.broadphase_ready ? (cs.ball_moved.size() != b.size() ||
                                   cs.segment_moved.size() != bs.segments.size())
                                : (!cs.moved_balls.empty() || !cs.moved_segments.empty()))
            r.fail("moved-body flags do not match the bodies");
        for (uint32_t s : cs.moved_balls)
            if (s >= cs.ball_moved.size()) r.fail("a moved ball is out of range");
        for (uint32_t s : cs.moved_segments)
            if (s >= cs.segment_moved.size()) r.fail("a moved segment is out of range");
        for (uint8_t f : cs.ball_moved)
            if (f > 1) r.fail("invalid moved flag");
        for (uint8_t f : cs.segment_moved)
            if (f > 1) r.fail("invalid moved flag");
        r.expectEnd();
    }
    {
        SaveReader r = in.section("ENRG");
        EnergyBooks& e = world.books;
        e.on = r.boolean();
        e.acc = readTotals(r), e.snapshot = readTotals(r);
        // Still opening when saved (api/energy.cpp): they open afresh, at the snapshot after
        // next (as over loaded contacts), where everything they start from is known again.
        e.dashpot_pending = r.f64(), e.opening = r.boolean() ? 2 : 0;
        e.strain_baseline_pending = false;
        e.last_placed = r.f64();
        e.groups.on = r.boolean(), e.groups.traced = r.u64();
        e.groups.g.resize(r.count(sizeof(EnergyBooks::GroupBooks::Group), "group books"));
        for (auto& g : e.groups.g) g = r.pod<EnergyBooks::GroupBooks::Group>();
        const std::size_t ng = e.groups.g.size();
        if (ng > world.bodies.group_names.size() || (ng < 64 && (e.groups.traced >> ng) != 0))
            r.fail("group books do not match the groups");
        e.groups.exchange.resize(r.count(100, "exchange records"));
        for (auto& x : e.groups.exchange) {
            x.end1 = r.u32(), x.end2 = r.u32(), x.wall = r.boolean();
            x.gone1 = r.boolean(), x.gone2 = r.boolean();
            x.g1 = r.u64(), x.g2 = r.u64(), x.f1 = r.vec2(), x.m1 = r.f64(), x.m2 = r.f64();
            x.v1 = r.vec2(), x.v2 = r.vec2(), x.w1 = r.f64(), x.w2 = r.f64();
            if (x.end1 >= b.size() || x.end2 >= (x.wall ? bs.walls.size() : b.size()))
                r.fail("an exchange record names a body out of range");
        }
        readScriptChanges(r, e.script, bs);
        r.expectEnd();
    }
    {
        SaveReader r = in.section("GARD");
        GuardState& g = world.guard_state;
        g.underresolved = r.i64(), g.underresolved_first = r.str();
        g.energy_gain = r.i64(), g.energy_gain_first = r.str();
        g.stiffness_lies = r.i64(), g.stiffness_lies_first = r.str();
        g.placed = r.i64(), g.placed_energy = r.f64(), g.placed_first = r.str();
        g.balance.open = readTotals(r);
        g.balance.open_step = r.i64(), g.balance.peak = r.f64(), g.balance.reported = r.f64();
        g.balance.findings = r.i64(), g.balance.first = r.str(), g.balance.last = r.str();
        r.expectEnd();
    }
    {
        SaveReader r = in.section("EVNT");
        world.callbacks.events.resize(r.count(40, "events"));
        for (Event& ev : world.callbacks.events) {
            ev.kind = r.enumValue<EventKind>(2, "event kind");
            ev.time = r.f64(), ev.pos = r.vec2(), ev.contact.value = r.u64();
            ev.mode = r.i32(), ev.model = r.str();
        }
        r.expectEnd();
    }
    return mp;
}

// ------------------------------------------------------------------------ the file

std::vector<uint8_t> saveModelBytes(const Model& model, const std::vector<uint8_t>& host) {
    SaveWriter w;
    w.bytes(kSaveMagic, 8);
    w.u32(kSaveFormatVersion);
    w.u32(kSaveByteOrderMark);
    w.u64(0);  // payload length, patched below
    w.u64(0);  // checksum, patched below
    w.beginSection("HEAD");
    w.str(TALUS_ENGINE_VERSION);
    w.endSection();
    model.saveState(w);
    w.beginSection("HOST");
    w.bytes(host.data(), host.size());
    w.endSection();
    w.bytes("END.", 4);
    auto& d = w.data();
    const uint64_t len = d.size() - kSaveHeaderSize;
    const uint64_t sum = fnv1a64(d.data() + kSaveHeaderSize, len);
    std::memcpy(d.data() + 16, &len, 8);
    std::memcpy(d.data() + 24, &sum, 8);
    return std::move(d);
}

void saveModelFile(const Model& model, const std::string& path, const std::vector<uint8_t>& host) {
    const std::vector<uint8_t> bytes = saveModelBytes(model, host);
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw InputError("save: cannot write '" + tmp + "': " + std::strerror(errno));
    const bool ok =
        std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size() && std::fflush(f) == 0;
    const int err = errno;
    if (std::fclose(f) != 0 || !ok) {
        std::remove(tmp.c_str());
        throw InputError("save: cannot write '" + tmp + "': " + std::strerror(ok ? errno : err));
    }
    // rename() replaces `path` atomically: a crash before this line leaves the old file.
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e = errno;
        std::remove(tmp.c_str());
        throw InputError("save: cannot rename '" + tmp + "' to '" + path +
                         "': " + std::strerror(e));
    }
}

RestoredModel restoreModelBytes(const uint8_t* data, std::size_t size, const std::string& name,
                                PluginRegistry& registry, bool verify_checksum) {
    SaveReader file(data, size, "'" + name + "'");
    if (size == 0) file.fail("empty file (not a Talus save file)");
    const std::size_t magic_have = std::min<std::size_t>(size, 8);
    if (std::memcmp(data, kSaveMagic, magic_have) != 0)
        file.fail("not a Talus save file (it does not start with \"TALUSSAV\")");
    if (size < kSaveHeaderSize)
        file.fail("truncated: " + std::to_string(size) + " bytes, shorter than the " +
                  std::to_string(kSaveHeaderSize) + "-byte header");
    char magic[8];
    file.bytes(magic, 8);
    const uint32_t format = file.u32();
    const uint32_t bom = file.u32();
    if (bom != kSaveByteOrderMark) {
        uint32_t swapped = __builtin_bswap32(bom);
        file.fail(swapped == kSaveByteOrderMark
                      ? "written on a machine of the other byte order (not supported)"
                      : "corrupted header (byte-order mark)");
    }
    if (format != kSaveFormatVersion)
        file.fail("save format version " + std::to_string(format) + "; this build of Talus (" +
                  TALUS_ENGINE_VERSION + ") reads version " + std::to_string(kSaveFormatVersion));
    const uint64_t len = file.u64();
    const uint64_t sum = file.u64();
    if (len != size - kSaveHeaderSize)
        file.fail(len > size - kSaveHeaderSize
                      ? "truncated: the header announces " + std::to_string(len) +
                            " bytes of data, the file has " + std::to_string(size - kSaveHeaderSize)
                      : "corrupted: " + std::to_string(size - kSaveHeaderSize - len) +
                            " bytes more than the header announces");
    if (verify_checksum && fnv1a64(data + kSaveHeaderSize, len) != sum)
        file.fail("corrupted: the checksum does not match the data");

    RestoredModel out;
    {
        SaveReader r = file.section("HEAD");
        out.engine_version = r.str();
        r.expectEnd();
    }
    if (out.engine_version != TALUS_ENGINE_VERSION)
        out.notes.push_back("saved by Talus " + out.engine_version + "; this is Talus " +
                            TALUS_ENGINE_VERSION);
    out.model = Model::restoreState(file, registry, out.notes);
    {
        SaveReader r = file.section("HOST");
        out.host.resize(r.left());
        r.bytes(out.host.data(), out.host.size());
    }
    char end[4];
    file.bytes(end, 4);
    if (std::memcmp(end, "END.", 4) != 0) file.fail("corrupted end marker");
    file.expectEnd();
    return out;
}

RestoredModel restoreModelFile(const std::string& path, PluginRegistry& registry) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError("restore: cannot open '" + path + "': " + std::strerror(errno));
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)),
                               std::istreambuf_iterator<char>());
    if (f.bad()) throw InputError("restore: cannot read '" + path + "'");
    return restoreModelBytes(bytes.data(), bytes.size(), path, registry, true);
}

}  // namespace talus
