// SPDX-License-Identifier: MIT
//
// Section EVNT: events not yet delivered (empty between run calls, when a save is taken).
#include "save/sections.hpp"

namespace talus {

void writeEvents(const World& world, SaveWriter& w) {
    w.u64(world.callbacks.events.size());
    for (const Event& ev : world.callbacks.events) {
        w.i32(static_cast<int32_t>(ev.kind)), w.f64(ev.time), w.vec2(ev.pos);
        w.u64(ev.contact.value), w.i32(ev.mode), w.str(ev.model);
    }
}

void readEvents(RestoreContext& ctx, SaveReader& r) {
    auto& events = ctx.world.callbacks.events;
    events.resize(r.count(40, "events"));
    for (Event& ev : events) {
        ev.kind = r.enumValue<EventKind>(2, "event kind");
        ev.time = r.f64(), ev.pos = r.vec2(), ev.contact.value = r.u64();
        ev.mode = r.i32(), ev.model = r.str();
    }
    r.expectEnd();
}

}  // namespace talus
