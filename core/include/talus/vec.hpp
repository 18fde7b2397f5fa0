// SPDX-License-Identifier: MIT
// 2D vector type and the few operations the engine needs beyond Eigen's.
#pragma once

#include <Eigen/Core>

namespace talus {

using Vec2 = Eigen::Vector2d;

/// z-component of the cross product a x b.
inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// a rotated by +90 degrees: the tangent t = (-n_y, n_x) of a contact normal n.
inline Vec2 perp(const Vec2& a) { return Vec2(-a.y(), a.x()); }

/// Velocity of a point at offset r from a body turning at `spin` [rad/s]: spin x r.
inline Vec2 spinCross(double spin, const Vec2& r) { return Vec2(-spin * r.y(), spin * r.x()); }

/// Axis-aligned box in world units.
struct Box {
    Vec2 lo{0.0, 0.0};
    Vec2 hi{0.0, 0.0};
    bool overlaps(const Box& o) const {
        return lo.x() <= o.hi.x() && o.lo.x() <= hi.x() && lo.y() <= o.hi.y() && o.lo.y() <= hi.y();
    }
    bool contains(const Box& o) const {
        return lo.x() <= o.lo.x() && lo.y() <= o.lo.y() && o.hi.x() <= hi.x() && o.hi.y() <= hi.y();
    }
};

}  // namespace talus
