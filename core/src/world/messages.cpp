// SPDX-License-Identifier: MIT
//
// What the engine says: numbers and vectors for messages, warnings, the description of a pair
// ("ball 3 at (x, y) and wall 2 ...") and the non-finite stop.
#include "world/messages.hpp"

#include "api/operations.hpp"
#include "talus/errors.hpp"

namespace talus {

std::string describePair(const World& world, const Pair& p) {
    std::string s = "contact ball " + std::to_string(world.bodies.balls.handle[p.end1]) + " - ";
    if (p.wall) {
        const Segment& seg = world.bodies.segments[p.end2];
        s += "wall " + std::to_string(seg.wall + 1) + " segment " +
             std::to_string(p.end2 - world.bodies.walls[seg.wall].first_segment + 1);
    } else {
        s += "ball " + std::to_string(world.bodies.balls.handle[p.end2]);
    }
    s += " (model '" + world.contacts.ruleOf(p).model_name + "')";
    Vec2 n, point;
    double overlap;
    if (pairGeometry(world, p, n, overlap, point)) s += " at " + vecText(point);
    return s;
}

std::string severeNote(const std::string& why) {
    return "; a severe finding (" + why +
           "): the run stops (m:guard{severe = \"warn\"} reports severe findings as warnings; "
           "docs/physics/guard.md)";
}

std::string vecText(const Vec2& v) {
    return "(" + messageNumber(v.x()) + ", " + messageNumber(v.y()) + ")";
}

std::string messageNumber(double v, int digits) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

void Model::warn(const std::string& text) { talus::warn(*m_world, text); }

void warn(World& world, const std::string& text) {
    if (world.callbacks.warning_handler) world.callbacks.warning_handler(text);
}

void throwNonFinite(const World& world, const std::string& what) {
    throw NumericalError("non-finite state at step " + std::to_string(world.clock.step) +
                         " (t = " + messageNumber(world.clock.time) + " s): " + what);
}

}  // namespace talus
