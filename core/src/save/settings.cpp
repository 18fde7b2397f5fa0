// SPDX-License-Identifier: MIT
//
// Section SETT: what the user set (world.hpp, Settings) and the group names. The time-step
// settings the step limits were gathered with (Stepping::last_settings) come along: a change of
// them makes the next step survey the limits again (step.cpp, prepareRun).
#include <cmath>

#include "save/sections.hpp"

namespace talus {

namespace {

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

}  // namespace

void writeSettings(const World& world, SaveWriter& w) {
    const Settings& s = world.settings;
    w.vec2(s.gravity);
    w.i32(static_cast<int32_t>(s.mass_mode));
    writeTimestep(w, s.timestep);
    writeTimestep(w, world.stepping.last_settings);
    w.i32(static_cast<int32_t>(s.guard.energy)), w.f64(s.guard.energy_tolerance);
    w.i32(static_cast<int32_t>(s.guard.resolution)), w.i32(s.guard.min_steps);
    w.i32(static_cast<int32_t>(s.guard.stiffness));
    w.i32(static_cast<int32_t>(s.guard.balance)), w.f64(s.guard.balance_tolerance);
    w.i64(s.guard.balance_every);
    w.i32(static_cast<int32_t>(s.guard.severe)), w.f64(s.guard.severe_created),
        w.i32(s.guard.severe_min_steps);  // (format 2 on)
    w.f64(s.damping.local), w.f64(s.damping.viscous);
    w.i64(s.sort_every);
    w.boolean(world.callbacks.contact_events);
    w.u64(world.bodies.group_names.size());
    for (const auto& g : world.bodies.group_names) w.str(g);
}

void readSettings(RestoreContext& ctx, SaveReader& r) {
    World& world = ctx.world;
    Settings& s = world.settings;
    s.gravity = r.vec2();
    if (!std::isfinite(s.gravity.x()) || !std::isfinite(s.gravity.y()))
        r.fail("gravity is not finite");
    s.mass_mode = r.enumValue<MassMode>(2, "mass mode");
    s.timestep = readTimestep(r);
    world.stepping.last_settings = readTimestep(r);
    s.guard.energy = r.enumValue<GuardAction>(3, "guard energy");
    s.guard.energy_tolerance = r.f64();
    s.guard.resolution = r.enumValue<GuardAction>(3, "guard resolution");
    s.guard.min_steps = r.i32();
    s.guard.stiffness = r.enumValue<GuardAction>(3, "guard stiffness");
    s.guard.balance = r.enumValue<GuardAction>(3, "guard balance");
    s.guard.balance_tolerance = r.f64();
    s.guard.balance_every = r.i64();
    if (s.guard.balance_every < 1) r.fail("guard balance_every must be >= 1");
    if (r.version() >= 2) {
        s.guard.severe = r.enumValue<GuardAction>(3, "guard severe");
        s.guard.severe_created = r.f64();
        s.guard.severe_min_steps = r.i32();
    }
    s.damping.local = r.f64();
    s.damping.viscous = r.f64();
    s.sort_every = r.i64();
    if (s.sort_every < Model::kSortAuto) r.fail("sort interval must be >= -1");
    world.callbacks.contact_events = r.boolean();
    const std::size_t ng = r.count(8, "group names");
    if (ng > 64) r.fail("more than 64 group names");
    for (std::size_t i = 0; i < ng; ++i) world.bodies.group_names.push_back(r.str());
    world.stepping.guard_was_on = s.guard.anyOn();
    r.expectEnd();
}

}  // namespace talus
