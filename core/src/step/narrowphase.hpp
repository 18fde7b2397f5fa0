// SPDX-License-Identifier: MIT
//
// Narrowphase geometry (ball-wall geometry as PFC2D defines it).
// Normals point from end 1 (the ball) to end 2; overlap is positive when the bodies overlap.
//
// Shared vertices of a wall chain. Where the chain bends away from the ball (a convex corner, a
// crest), a ball near the vertex is in the vertex region of both segments S (ending there) and N
// (starting there), and both would push: the vertex would push twice. So a convex vertex belongs
// to one segment: S reports it only when the ball is not in N's face region either (N's
// parameter <= 0), and N never reports its start vertex. Where the chain bends toward the ball
// (a concave corner, a valley), the vertex is not shared: each segment measures the ball's
// distance to its own closest point, the vertex included, so the second face's contact grows
// from zero as the vertex enters the ball -- counting it only from when the centre passes over
// the second face would switch on a force of k * overlap at once, which for a shallow valley is
// nearly the ball's whole weight again (tests/core/test_walls.cpp measured +94% at 0.2 degrees).
// A contact whose point runs over a convex vertex keeps its state: it moves to the pair of the
// segment that now reports the ball (step/detection.cpp, "wall vertices";
// docs/physics/walls.md).
#pragma once

#include <cmath>

#include "talus/vec.hpp"

namespace talus {

struct ContactGeometry {
    Vec2 normal{0.0, 1.0};
    double overlap = 0.0;
    Vec2 point{0.0, 0.0};
};

/// True when a chain that runs from `before` through `v` to `after` bends toward the point c
/// (a valley seen from c), from the turn of the chain and the side of c.
inline bool bendsToward(const Vec2& before, const Vec2& v, const Vec2& after, const Vec2& c) {
    const double turn = cross(v - before, after - v);
    const double side = cross(after - before, c - before);
    return turn * side > 0.0;
}

/// Ball (centre c, radius r) against segment a-b. `before` (or nullptr) is the far end of the
/// previous segment, which shares a; `after` (or nullptr) the far end of the next segment, which
/// shares b. Returns false if the contact belongs to a neighbouring segment (see above).
inline bool ballSegmentGeometry(const Vec2& c, double r, const Vec2& a, const Vec2& b,
                                const Vec2* before, const Vec2* after, ContactGeometry& g) {
    const Vec2 ab = b - a;
    const double len2 = ab.squaredNorm();
    double t = (c - a).dot(ab) / len2;
    if (t <= 0.0) {
        if (before && !bendsToward(*before, a, b, c)) return false;
        t = 0.0;
    } else if (t >= 1.0) {
        if (after && !bendsToward(a, b, *after, c) && (c - b).dot(*after - b) > 0.0) return false;
        t = 1.0;
    }
    const Vec2 q = a + t * ab;
    const Vec2 d = q - c;
    const double dist = d.norm();
    if (dist > 0.0) {
        g.normal = d / dist;
    } else {
        // Centre exactly on the segment: push along the segment's left normal.
        g.normal = -perp(ab).normalized();
    }
    g.overlap = r - dist;
    g.point = c + (r - 0.5 * g.overlap) * g.normal;
    return true;
}

}  // namespace talus
