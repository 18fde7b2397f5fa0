// SPDX-License-Identifier: MIT
// Exact mass properties of a union of disks (docs/physics/clumps.md "Mass properties").
//
// Green's theorem turns the area integrals of the union into line integrals over its boundary,
// which is made of the arcs of each circle that no other disk covers (traversed
// counter-clockwise, since the union lies on the inner side of every such arc). On a circle
// x = cx + r cos t, y = cy + r sin t each integrand is a trigonometric polynomial in t, so every
// arc integral has a closed-form antiderivative (arcAntiderivative below).
#include "talus/clump_mass.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "talus/errors.hpp"

namespace talus {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Relative tolerance of the "inside" and "duplicate" decisions, scaled by the radii. A disk
// within this distance of being inside another is treated as inside: the area it would add is
// O(tol * r^2), so the result stays continuous to round-off across the decision.
constexpr double kRelTol = 1e-12;

std::string fmt(double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
}

void validate(const std::vector<Pebble>& pebbles) {
    if (pebbles.empty()) throw InputError("clump mass properties: the pebble list is empty");
    for (std::size_t i = 0; i < pebbles.size(); ++i) {
        const Pebble& p = pebbles[i];
        if (!std::isfinite(p.radius) || !(p.radius > 0.0))
            throw InputError("clump pebble " + std::to_string(i) + ": radius " + fmt(p.radius) +
                             " must be positive and finite");
        if (!std::isfinite(p.pos.x()) || !std::isfinite(p.pos.y()))
            throw InputError("clump pebble " + std::to_string(i) + ": position (" + fmt(p.pos.x()) +
                             ", " + fmt(p.pos.y()) + ") is not finite");
    }
}

// Sums of the four boundary integrals (about the working origin).
struct Moments {
    double a = 0.0;   // A   = 1/2 \oint (x dy - y dx)
    double sx = 0.0;  // S_x = \oint x^2/2 dy        (= \int x dA)
    double sy = 0.0;  // S_y = -\oint y^2/2 dx       (= \int y dA)
    double j = 0.0;   // J_O = \oint (x^3/3 dy - y^3/3 dx)  (= \int (x^2 + y^2) dA)
};

// Antiderivatives in t of the four integrands on the circle (cx + r cos t, cy + r sin t), with
// dx = -r sin t dt, dy = r cos t dt, c = cos t, s = sin t:
//   A  : 1/2 (r^2 + r cx c + r cy s)                      -> 1/2 (r^2 t + r cx s - r cy c)
//   S_x: r/2 (cx^2 c + 2 cx r c^2 + r^2 c^3)
//        using  \int c^2 = t/2 + sin2t/4,  \int c^3 = s - s^3/3
//   S_y: r/2 (cy^2 s + 2 cy r s^2 + r^2 s^3)
//        using  \int s^2 = t/2 - sin2t/4,  \int s^3 = -c + c^3/3
//   J_O: r/3 [(cx + r c)^3 c + (cy + r s)^3 s]
//        = r/3 [cx^3 c + 3 cx^2 r c^2 + 3 cx r^2 c^3 + cy^3 s + 3 cy^2 r s^2 + 3 cy r^2 s^3
//               + r^3 (c^4 + s^4)],  using  \int (c^4 + s^4) = 3t/4 + sin4t/16.
// A full circle gives pi r^2, pi r^2 (cx, cy) and pi r^4/2 + pi r^2 (cx^2 + cy^2), as it must.
Moments arcAntiderivative(double cx, double cy, double r, double t) {
    const double c = std::cos(t), s = std::sin(t);
    const double s2t = 2.0 * s * c;
    const double s4t = 2.0 * s2t * (c * c - s * s);
    const double ic2 = 0.5 * t + 0.25 * s2t;
    const double is2 = 0.5 * t - 0.25 * s2t;
    const double ic3 = s - s * s * s / 3.0;
    const double is3 = -c + c * c * c / 3.0;
    Moments m;
    m.a = 0.5 * (r * r * t + r * cx * s - r * cy * c);
    m.sx = 0.5 * r * (cx * cx * s + 2.0 * cx * r * ic2 + r * r * ic3);
    m.sy = 0.5 * r * (-cy * cy * c + 2.0 * cy * r * is2 + r * r * is3);
    m.j = r / 3.0 *
          (cx * cx * cx * s + 3.0 * cx * cx * r * ic2 + 3.0 * cx * r * r * ic3 - cy * cy * cy * c +
           3.0 * cy * cy * r * is2 + 3.0 * cy * r * r * is3 + r * r * r * (0.75 * t + s4t / 16.0));
    return m;
}

void addArc(Moments& acc, double cx, double cy, double r, double t0, double t1) {
    const Moments hi = arcAntiderivative(cx, cy, r, t1);
    const Moments lo = arcAntiderivative(cx, cy, r, t0);
    acc.a += hi.a - lo.a;
    acc.sx += hi.sx - lo.sx;
    acc.sy += hi.sy - lo.sy;
    acc.j += hi.j - lo.j;
}

// Turn moments about the working origin into MassProps (J_c = J_O - A |x_c|^2).
MassProps finish(const Moments& m, const Vec2& origin) {
    MassProps out;
    out.area = m.a;
    const Vec2 xc(m.sx / m.a, m.sy / m.a);
    out.centroid = origin + xc;
    out.polar_moment = m.j - m.a * xc.squaredNorm();
    return out;
}

// Working origin: the centre of the pebble centres' bounding box, so that the moments are
// computed in coordinates of the clump's own size (limits cancellation in J_O - A |x_c|^2 and
// makes the result translation-invariant to round-off).
Vec2 workingOrigin(const std::vector<Pebble>& pebbles) {
    Vec2 lo = pebbles.front().pos, hi = lo;
    for (const Pebble& p : pebbles) {
        lo = lo.cwiseMin(p.pos);
        hi = hi.cwiseMax(p.pos);
    }
    return 0.5 * (lo + hi);
}

}  // namespace

MassProps unionMassProps(const std::vector<Pebble>& pebbles) {
    validate(pebbles);
    const Vec2 origin = workingOrigin(pebbles);
    const std::size_t n = pebbles.size();
    Moments acc;
    std::vector<std::pair<double, double>> covered;  // angular intervals in [-pi, pi]
    for (std::size_t i = 0; i < n; ++i) {
        const Vec2 ci = pebbles[i].pos - origin;
        const double ri = pebbles[i].radius;
        covered.clear();
        bool hidden = false;
        for (std::size_t j = 0; j < n && !hidden; ++j) {
            if (j == i) continue;
            const Vec2 dvec = (pebbles[j].pos - origin) - ci;
            const double rj = pebbles[j].radius;
            const double d = dvec.norm();
            const double tol = kRelTol * (ri + rj);
            if (d <= tol && std::abs(ri - rj) <= tol) {
                // Duplicate: the lower index keeps the circle, the higher one is skipped, and
                // the skipped one covers nothing of the kept one.
                if (j < i) hidden = true;
                continue;
            }
            if (d + ri <= rj + tol) {  // i inside j (concentric smaller disks included)
                hidden = true;
                continue;
            }
            if (d + rj <= ri + tol) continue;  // j inside i: covers no arc of circle i
            if (d >= ri + rj) continue;        // apart or tangent: covers no arc
            // Here d > |ri - rj| + tol > 0. Law of cosines: j covers phi +- alpha of circle i.
            const double cosa = std::clamp((d * d + ri * ri - rj * rj) / (2.0 * d * ri), -1.0, 1.0);
            const double alpha = std::acos(cosa);
            const double phi = std::atan2(dvec.y(), dvec.x());
            double a = phi - alpha, b = phi + alpha;  // a in [-2pi, pi], b in [-pi, 2pi]
            if (a < -kPi) {                           // wraps across -pi: split
                covered.emplace_back(a + 2.0 * kPi, kPi);
                covered.emplace_back(-kPi, b);
            } else if (b > kPi) {  // wraps across +pi: split
                covered.emplace_back(a, kPi);
                covered.emplace_back(-kPi, b - 2.0 * kPi);
            } else {
                covered.emplace_back(a, b);
            }
        }
        if (hidden) continue;
        // Free arcs = complement of the merged covered intervals in [-pi, pi].
        std::sort(covered.begin(), covered.end());
        double t = -kPi;  // start of the current free stretch
        for (const auto& iv : covered) {
            if (iv.first > t) addArc(acc, ci.x(), ci.y(), ri, t, iv.first);
            t = std::max(t, iv.second);
        }
        if (t < kPi) addArc(acc, ci.x(), ci.y(), ri, t, kPi);
    }
    TALUS_ASSERT(acc.a > 0.0, "union of disks has a positive area");
    return finish(acc, origin);
}

MassProps sumMassProps(const std::vector<Pebble>& pebbles) {
    validate(pebbles);
    const Vec2 origin = workingOrigin(pebbles);
    Moments acc;
    for (const Pebble& p : pebbles) {
        const Vec2 c = p.pos - origin;
        const double a = kPi * p.radius * p.radius;
        acc.a += a;
        acc.sx += a * c.x();
        acc.sy += a * c.y();
        acc.j += a * (0.5 * p.radius * p.radius + c.squaredNorm());  // parallel axes about origin
    }
    return finish(acc, origin);
}

MassProps clumpMassProps(const std::vector<Pebble>& pebbles, ClumpMassMode mode) {
    switch (mode) {
        case ClumpMassMode::Union:
            return unionMassProps(pebbles);
        case ClumpMassMode::PlainSum:
            return sumMassProps(pebbles);
        case ClumpMassMode::Direct:
            break;
    }
    throw InputError(
        "clump mass properties: the direct mode takes user-given mass, centroid and inertia, "
        "not pebble geometry");
}

RigidMass scaledToDensity(const MassProps& props, double density) {
    if (!std::isfinite(density) || !(density > 0.0))
        throw InputError("clump density " + fmt(density) + " must be positive and finite");
    RigidMass out;
    out.mass = density * props.area;
    out.centroid = props.centroid;
    out.inertia = density * props.polar_moment;
    return out;
}

}  // namespace talus
