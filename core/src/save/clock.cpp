// SPDX-License-Identifier: MIT
//
// Section CLCK: the clock (time, step, the last two steps and their velocity window) and the
// automatic step's state (world.hpp, Stepping): the rule that set the last step and where, the
// limits the last force loop gathered for the next one and the pairs that set them.
#include "save/sections.hpp"

namespace talus {

void writeClock(const World& world, SaveWriter& w) {
    const Clock& c = world.clock;
    const Stepping& st = world.stepping;
    w.f64(c.time), w.i64(c.step), w.f64(c.dt), w.f64(c.dt_prev), w.f64(c.window);
    w.i32(static_cast<int32_t>(st.rule));
    w.i32(static_cast<int32_t>(st.where.kind)), w.u32(st.where.index), w.u64(st.where.key);
    w.boolean(c.first_cycle), w.boolean(world.guard_state.warned_no_model),
        w.boolean(st.limits_stale);
    w.vec2(st.limits_gravity);
    w.boolean(st.idle);
    w.f64(st.cap);
    w.f64(st.limits.stability), w.f64(st.limits.resolution), w.f64(st.limits.approach);
    w.u64(st.limits.stability_key), w.u64(st.limits.resolution_key), w.u64(st.limits.approach_key);
}

void readClock(RestoreContext& ctx, SaveReader& r) {
    Clock& c = ctx.world.clock;
    Stepping& st = ctx.world.stepping;
    c.time = r.f64(), c.step = r.i64(), c.dt = r.f64(), c.dt_prev = r.f64();
    c.window = r.f64();
    st.rule = r.enumValue<StepRule>(9, "step rule");
    st.where.kind = r.enumValue<StepWhere::Kind>(4, "step origin");
    st.where.index = r.u32(), st.where.key = r.u64();
    c.first_cycle = r.boolean(), ctx.world.guard_state.warned_no_model = r.boolean();
    st.limits_stale = r.boolean();
    st.limits_gravity = r.vec2();
    st.idle = r.boolean();
    st.cap = r.f64();
    st.limits.stability = r.f64(), st.limits.resolution = r.f64();
    st.limits.approach = r.f64();
    st.limits.stability_key = r.u64(), st.limits.resolution_key = r.u64();
    st.limits.approach_key = r.u64();
    if (c.step < 0) r.fail("negative step count");
    r.expectEnd();
}

}  // namespace talus
