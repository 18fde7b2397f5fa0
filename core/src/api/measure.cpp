// SPDX-License-Identifier: MIT
//
// Measurement regions (PFC measurement circles, here circles and axis-aligned boxes) and the
// unbalanced force (PFC's mechanical ratio). Both are queries: they read the state the last
// cycle left (positions, velocities and the contact forces computed at those positions) and
// cost nothing per step. Definitions: docs/lua-api.md, "Measurement".
#include <algorithm>
#include <cmath>
#include <limits>

#include "api/operations.hpp"
#include "step/group_energy.hpp"
#include "step/step.hpp"
#include "talus/errors.hpp"
#include "world/body_store.hpp"
#include "world/contact_store.hpp"
#include "world/messages.hpp"
#include "world/types.hpp"

namespace talus {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Area of the intersection of two disks of radii R and r whose centres are d apart (the
/// lens: two circular segments).
double diskDiskArea(double R, double r, double d) {
    if (d >= R + r) return 0.0;
    if (d <= std::fabs(R - r)) {
        const double m = std::min(R, r);
        return kPi * m * m;
    }
    const double ca = std::clamp((d * d + r * r - R * R) / (2.0 * d * r), -1.0, 1.0);
    const double cb = std::clamp((d * d + R * R - r * r) / (2.0 * d * R), -1.0, 1.0);
    const double k = (-d + r + R) * (d + r - R) * (d - r + R) * (d + r + R);
    return r * r * std::acos(ca) + R * R * std::acos(cb) - 0.5 * std::sqrt(std::max(k, 0.0));
}

/// Area of the disk of radius r about the origin below and left of (a, b): the disk cut by
/// the quadrant {X <= a, Y <= b}. At abscissa x the disk's chord is |Y| <= s(x) = sqrt(r^2 -
/// x^2), of which the part Y <= b has length clamp(b + s, 0, 2s); integrated in closed form
/// with S(x) = int_0^x s = (x s(x) + r^2 asin(x / r)) / 2, split where s(x) = |b|.
double diskQuadrantArea(double r, double a, double b) {
    const double r2 = r * r;
    const auto S = [&](double x) {
        x = std::clamp(x, -r, r);
        return 0.5 * (x * std::sqrt(std::max(r2 - x * x, 0.0)) + r2 * std::asin(x / r));
    };
    const double A = std::clamp(a, -r, r);
    if (b <= -r || A <= -r) return 0.0;
    if (b >= r) return 2.0 * (S(A) - S(-r));
    const double c = std::sqrt(r2 - b * b);  // s(x) > |b| for |x| < c
    double area = 0.0;
    // |x| >= c: the whole chord (b > 0) or nothing (b < 0).
    if (b > 0.0) {
        area += 2.0 * (S(std::min(A, -c)) - S(-r));
        if (A > c) area += 2.0 * (S(A) - S(c));
    }
    // |x| < c: from -s(x) up to b.
    if (A > -c) {
        const double hi = std::min(A, c);
        area += b * (hi + c) + S(hi) - S(-c);
    }
    return area;
}

/// Area of the disk (centre p, radius r) inside the box [lo, hi], exactly: inclusion-exclusion
/// over the four quadrants at the box's corners.
double diskBoxArea(const Vec2& p, double r, const Vec2& lo, const Vec2& hi) {
    const double x1 = lo.x() - p.x(), x2 = hi.x() - p.x();
    const double y1 = lo.y() - p.y(), y2 = hi.y() - p.y();
    if (x1 >= r || x2 <= -r || y1 >= r || y2 <= -r) return 0.0;
    return diskQuadrantArea(r, x2, y2) - diskQuadrantArea(r, x1, y2) - diskQuadrantArea(r, x2, y1) +
           diskQuadrantArea(r, x1, y1);
}

}  // namespace

namespace {

void checkRegion(const MeasureRegion& rg) {
    if (rg.circle) {
        if (!(rg.radius > 0.0) || !std::isfinite(rg.radius) || !std::isfinite(rg.center.x()) ||
            !std::isfinite(rg.center.y()))
            throw InputError("measure: circle needs a finite centre and a radius > 0 (got " +
                             vecText(rg.center) + ", " + messageNumber(rg.radius) + ")");
    } else if (!(rg.hi.x() > rg.lo.x()) || !(rg.hi.y() > rg.lo.y()) ||
               !std::isfinite(rg.lo.x() + rg.lo.y() + rg.hi.x() + rg.hi.y())) {
        throw InputError("measure: box needs finite xmin < xmax and ymin < ymax (got " +
                         vecText(rg.lo) + " to " + vecText(rg.hi) + ")");
    }
}

bool inside(const MeasureRegion& rg, const Vec2& x) {
    if (rg.circle) return (x - rg.center).squaredNorm() <= rg.radius * rg.radius;
    return x.x() >= rg.lo.x() && x.x() <= rg.hi.x() && x.y() >= rg.lo.y() && x.y() <= rg.hi.y();
}

/// The balls whose centre is inside (their flags, full areas, mean position and velocity).
struct BallsInside {
    std::vector<char> in;
    double area = 0.0;
    Vec2 mean_x{0.0, 0.0}, mean_v{0.0, 0.0};
};

/// Balls: the solid area inside (exact intersections), the porosity, and the balls whose centre
/// is inside.
BallsInside measureBalls(const World& world, const MeasureRegion& rg, MeasureResult& r) {
    const auto& b = world.bodies.balls;
    BallsInside in;
    in.in.assign(b.size(), 0);
    for (std::size_t s = 0; s < b.size(); ++s) {
        const Vec2& x = b.pos[s];
        const double rad = b.radius[s];
        r.solid += rg.circle ? diskDiskArea(rg.radius, rad, (x - rg.center).norm())
                             : diskBoxArea(x, rad, rg.lo, rg.hi);
        if (inside(rg, x)) {
            in.in[s] = 1;
            ++r.balls;
            in.area += kPi * rad * rad;
            in.mean_x += x;
            in.mean_v += b.vel[s];
        }
    }
    r.porosity = 1.0 - r.solid / r.area;
    return in;
}

/// Contacts: touching ones (overlap > 0, or bonded). Each end whose centre is inside counts the
/// contact for the coordination number and adds its share of the stress, the moment of the
/// contact force about the end's centre (a pebble: its clump's centroid):
///   sum_p sum_c (x_c - x_p) (x) F_cp,
/// which for bodies in equilibrium is the integral of the Cauchy stress over them (tension
/// positive). Divided by the balls' area and multiplied by the solid fraction (PFC 3's
/// correction for balls that straddle the boundary), it is 1/A of it when every ball is inside.
void measureContacts(const World& world, const MeasureRegion& rg, const BallsInside& in,
                     MeasureResult& r) {
    double sxx = 0.0, syy = 0.0, sxy = 0.0, syx = 0.0;
    int64_t ends_in = 0;
    for (const Pair& p : world.contacts.pairs) {
        if (!p.active) continue;
        Vec2 normal, point;
        double overlap;
        if (!pairGeometry(world, p, normal, overlap, point)) continue;
        if (!(overlap > 0.0 || p.bonded)) continue;
        if (inside(rg, point)) ++r.contacts;
        const Vec2 f = p.n_force * normal + p.s_force * perp(normal);  // on end 2
        const auto add = [&](uint32_t slot, const Vec2& force) {
            const Vec2 arm = point - endCentre(world, slot);
            sxx += arm.x() * force.x();
            syy += arm.y() * force.y();
            sxy += arm.x() * force.y();
            syx += arm.y() * force.x();
            ++ends_in;
        };
        if (in.in[p.end1]) add(p.end1, -f);
        if (!p.wall && in.in[p.end2]) add(p.end2, f);
    }
    r.coordination =
        r.balls > 0 ? static_cast<double>(ends_in) / static_cast<double>(r.balls) : 0.0;
    if (in.area > 0.0) {
        const double k = (1.0 - r.porosity) / in.area;
        r.stress_xx = k * sxx;
        r.stress_yy = k * syy;
        r.stress_xy = 0.5 * k * (sxy + syx);  // equal in equilibrium (moment balance per ball)
    }
}

/// Strain rate: the velocity gradient L of the least-squares fit v = v0 + L (x - x_mean) over
/// the balls whose centre is inside; centred, the fit decouples: L = B M^-1 with
/// M = sum dx dx^T, B = sum dv dx^T. Needs three balls not on one line (NaN otherwise).
void measureStrainRate(const World& world, BallsInside& in, MeasureResult& r) {
    const auto& b = world.bodies.balls;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    r.rate_xx = r.rate_yy = r.rate_xy = r.rate_spin = nan;
    if (r.balls < 3) return;
    in.mean_x /= static_cast<double>(r.balls);
    in.mean_v /= static_cast<double>(r.balls);
    double mxx = 0.0, mxy = 0.0, myy = 0.0, bxx = 0.0, bxy = 0.0, byx = 0.0, byy = 0.0;
    for (std::size_t s = 0; s < b.size(); ++s) {
        if (!in.in[s]) continue;
        const Vec2 dx = b.pos[s] - in.mean_x, dv = b.vel[s] - in.mean_v;
        mxx += dx.x() * dx.x();
        mxy += dx.x() * dx.y();
        myy += dx.y() * dx.y();
        bxx += dv.x() * dx.x();
        bxy += dv.x() * dx.y();
        byx += dv.y() * dx.x();
        byy += dv.y() * dx.y();
    }
    const double det = mxx * myy - mxy * mxy;
    if (!(det > 1e-12 * (mxx + myy) * (mxx + myy))) return;
    // M^-1 = [myy, -mxy; -mxy, mxx] / det
    const double lxx = (bxx * myy - bxy * mxy) / det;
    const double lxy = (-bxx * mxy + bxy * mxx) / det;
    const double lyx = (byx * myy - byy * mxy) / det;
    const double lyy = (-byx * mxy + byy * mxx) / det;
    r.rate_xx = lxx;
    r.rate_yy = lyy;
    r.rate_xy = 0.5 * (lxy + lyx);
    r.rate_spin = 0.5 * (lyx - lxy);
}

}  // namespace

MeasureResult Model::measure(const MeasureRegion& rg) const {
    const World& world = *m_world;
    checkRegion(rg);
    MeasureResult r;
    r.area =
        rg.circle ? kPi * rg.radius * rg.radius : (rg.hi.x() - rg.lo.x()) * (rg.hi.y() - rg.lo.y());
    BallsInside in = measureBalls(world, rg, r);
    measureContacts(world, rg, in, r);
    measureStrainRate(world, in, r);
    return r;
}

UnbalancedForce Model::unbalanced() const { return unbalancedForce(*m_world); }

}  // namespace talus
