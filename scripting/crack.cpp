// SPDX-License-Identifier: MIT
#include "crack.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace talus {

namespace {

/// The value of property `name` of the contact's model, or NaN when the model has none.
double propIfAny(Model& m, const ContactInfo& info, const char* name) {
    const ContactModel* meta = m.contactModelFactory(info.model).reference;
    for (int32_t i = 0; meta && i < meta->PropCount(); ++i) {
        const PropInfo* p = meta->PropInfoAt(i);
        if (p && std::strcmp(p->name, name) == 0) return m.contactProp(info.key, name);
    }
    return std::nan("");
}

}  // namespace

Crack crackOf(Model& m, const Event& ev) {
    Crack c;
    c.time = ev.time;
    c.step = m.step();
    c.pos = ev.pos;
    c.mode = ev.mode;
    c.sigma = ev.sigma;
    c.tau = ev.tau;
    ContactInfo info;
    if (!m.findContact(ev.contact, info)) return c;
    c.ball1 = info.ball1;
    c.ball2 = info.ball2;
    c.normal = info.normal;
    double radius = m.ballRadius(info.ball1);
    if (m.isAlive(info.ball2)) {
        const Vec2 d = m.ballPos(info.ball2) - m.ballPos(info.ball1);
        const double len = d.norm();
        if (len > 0.0) c.normal = d / len;
        radius = std::min(radius, m.ballRadius(info.ball2));
    }
    // The bond's half width as the engine read it from the model when the bond broke; else (a
    // model with none, or an event queued at a save) the contact's model's pb_rad if it still
    // has one, else the smaller ball's radius.
    const double pb_rad = ev.radius > 0.0 ? ev.radius
                          : info.active   ? propIfAny(m, info, "pb_rad")
                                          : std::nan("");
    c.radius = pb_rad > 0.0 ? pb_rad : radius;
    return c;
}

}  // namespace talus
