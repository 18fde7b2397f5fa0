// SPDX-License-Identifier: MIT
//
// Narrowphase geometry (accuracy-reference 3.3; seed digest section 1).
// Normals point from end 1 (the ball) to end 2; overlap is positive when the bodies overlap.
//
// Shared vertices of a wall chain. A ball near a vertex shared by segments S (ending there) and
// N (starting there) is in the vertex region of both at a convex corner, and both would push:
// the vertex would push twice. So a shared vertex belongs to one segment: S reports it only when
// the ball is not in N's face region either (N's parameter <= 0), and N never reports its start
// vertex when it has a predecessor. At a concave corner both faces can hold the ball, and both
// face contacts are real.
#pragma once

#include <cmath>

#include "talus/vec.hpp"

namespace talus {

struct ContactGeometry {
    Vec2 normal{0.0, 1.0};
    double overlap = 0.0;
    Vec2 point{0.0, 0.0};
};

/// Ball (centre c, radius r) against segment a-b. `prev`: a is shared with a previous segment;
/// `next`: b is shared with a next segment whose far end is `after`. Returns false if the
/// contact belongs to a neighbouring segment (see the note above).
inline bool ballSegmentGeometry(const Vec2& c, double r, const Vec2& a, const Vec2& b, bool prev,
                                bool next, const Vec2& after, ContactGeometry& g) {
    const Vec2 ab = b - a;
    const double len2 = ab.squaredNorm();
    double t = (c - a).dot(ab) / len2;
    if (t <= 0.0) {
        if (prev) return false;
        t = 0.0;
    } else if (t >= 1.0) {
        if (next && (c - b).dot(after - b) > 0.0) return false;
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
