// SPDX-License-Identifier: MIT
//
// The servos' section of a save file ("SRVG", docs/save-format.md): every servo's resolved
// settings and its state, so that a restored model goes on with its ramps where they were. The
// section is written only when the model has servos, after the events; a file without it (an
// older file, or a model without servos) restores with none. Format version 3 added each servo's
// equilibrium hold (settings and counts) after its state; a version-2 file's servos restore
// without a hold.
#include "api/operations.hpp"
#include "talus/save_file.hpp"

namespace talus {

void saveServos(const World& world, SaveWriter& w) {
    if (world.servos.list.empty()) return;
    w.beginSection("SRVG");
    w.i32(world.servos.on);
    w.u64(world.servos.list.size());
    for (const ServoData& sd : world.servos.list) {
        const ServoState& st = sd.state;
        const ServoSettings& s = st.settings;
        w.boolean(sd.alive), w.f64(sd.ramp_from);
        w.u64(s.walls.size());
        for (std::size_t k = 0; k < s.walls.size(); ++k)
            w.u32(s.walls[k].index), w.u32(s.walls[k].generation), w.vec2(s.dirs[k]);
        w.i32(static_cast<int32_t>(s.control)), w.f64(s.target), w.f64(s.length);
        w.u32(s.span[0].index), w.u32(s.span[0].generation);
        w.u32(s.span[1].index), w.u32(s.span[1].generation);
        w.f64(s.gauge), w.i64(s.ramp), w.f64(s.alpha), w.f64(s.vmax), w.boolean(s.on);
        w.i64(st.steps), w.f64(st.start), w.f64(st.force), w.f64(st.stress), w.f64(st.length);
        w.f64(st.knest), w.f64(st.speed), w.f64(st.displacement);
        w.array(st.forces);
        w.f64(s.hold_ratio), w.f64(s.hold_resume), w.i64(s.hold_max_steps), w.f64(st.ratio),
            w.i64(st.held);
        w.i64(st.holds), w.i64(st.holds_capped), w.i64(st.hold_run), w.i64(st.since_hold),
            w.boolean(st.capped);
    }
    w.endSection();
}

void restoreServos(World& world, SaveReader& in) {
    SaveReader r = in.section("SRVG");
    const int32_t on = r.i32();
    world.servos.list.resize(r.count(100, "servos"));
    int counted = 0;
    for (ServoData& sd : world.servos.list) {
        ServoState& st = sd.state;
        ServoSettings& s = st.settings;
        sd.alive = r.boolean(), sd.ramp_from = r.f64();
        const std::size_t n = r.count(24, "servo walls");
        s.walls.resize(n), s.dirs.resize(n);
        for (std::size_t k = 0; k < n; ++k) {
            s.walls[k].index = r.u32(), s.walls[k].generation = r.u32(), s.dirs[k] = r.vec2();
            if (sd.alive) (void)world.bodies.wallOf(s.walls[k]);  // names a wall of the model
        }
        s.control = r.enumValue<ServoControl>(4, "servo control");
        s.target = r.f64(), s.length = r.f64();
        s.span[0].index = r.u32(), s.span[0].generation = r.u32();
        s.span[1].index = r.u32(), s.span[1].generation = r.u32();
        s.gauge = r.f64(), s.ramp = r.i64(), s.alpha = r.f64(), s.vmax = r.f64(),
        s.on = r.boolean();
        st.steps = r.i64(), st.start = r.f64(), st.force = r.f64(), st.stress = r.f64();
        st.length = r.f64(), st.knest = r.f64(), st.speed = r.f64(), st.displacement = r.f64();
        r.array(st.forces, "servo forces");
        if (r.version() >= 3) {
            s.hold_ratio = r.f64(), s.hold_resume = r.f64(), s.hold_max_steps = r.i64(),
            st.ratio = r.f64();
            st.held = r.i64(), st.holds = r.i64(), st.holds_capped = r.i64();
            st.hold_run = r.i64(), st.since_hold = r.i64(), st.capped = r.boolean();
        }
        counted += sd.alive && s.on;
    }
    r.expectEnd();
    if (counted != on) r.fail("the count of servos switched on does not match");
    world.servos.on = on;
}

}  // namespace talus
