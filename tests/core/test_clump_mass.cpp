// SPDX-License-Identifier: MIT
// Clump mass properties (docs/physics/clumps.md "Mass properties") against the exact values of
// derived here, closed forms, symmetry and an independent scan-line integration.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "talus/clump_mass.hpp"
#include "talus/errors.hpp"

using talus::MassProps;
using talus::Pebble;
using talus::Vec2;

namespace {

constexpr double kPi = 3.14159265358979323846;

bool relNear(double got, double want, double rel) {
    return std::abs(got - want) <= rel * std::max(std::abs(want), 1e-300);
}

// Centroid check: relative to the clump size `scale` (a centroid component may be 0).
bool vecNear(const Vec2& got, const Vec2& want, double tol) { return (got - want).norm() <= tol; }

struct Row {
    const char* name;
    std::vector<Pebble> pebbles;
    double area;
    Vec2 centroid;
    double jc;
};

// Exact areas, centroids and inertias of disk unions worked out independently (unit density,
// unit thickness), given to 11 digits:
// 1e-9 relative is well above the table's rounding (<= 1e-10 relative).
std::vector<Row> table36() {
    const double h = std::sqrt(3.0) / 2.0;
    return {
        {"C1", {{{0, 0}, 1}, {{1.0, 0}, 1}}, 5.0548156086, {0.5, 0}, 4.4406307593},
        {"C2", {{{0, 0}, 1}, {{1.5, 0}, 1}}, 5.8298735532, {0.75, 0}, 6.6283092247},
        {"C3", {{{0, 0}, 1}, {{1.0, 0}, 0.5}}, 3.5762242071, {0.1443937741, 0}, 2.1497560231},
        {"C4", {{{-1, 0}, 1}, {{0, 0}, 1}, {{1, 0}, 1}}, 6.9680385636, {0, 0}, 9.8378729960},
        {"C5",
         {{{0, 0}, 1}, {{1, 0}, 1}, {{0.5, h}, 1}},
         6.4444397880,
         {0.5, 0.2886751346},
         6.8137421629},
        {"C6", {{{-2, 0}, 1}, {{0, 0}, 1}, {{2, 0}, 1}}, 9.4247779608, {0, 0}, 29.8451302091},
        {"C7",
         {{{0, 0}, 1}, {{2, 0}, 1}, {{1, 2 * h}, 1}},
         9.4247779608,
         {1, 0.5773502692},
         17.2787595947},
        // C8: a small disk inside a big one; the table's naive +4.9 % identifies r = 0.3 at 0.5.
        {"C8", {{{0, 0}, 1}, {{0.5, 0}, 0.3}}, 3.1415926536, {0, 0}, 1.5707963268},
    };
}

// Independent reference: scan lines in y. On each line the union of the disks' chords is an
// exact union of x-intervals, whose length and x-moments are exact; only the y-integration is
// numerical (midpoint rule). The chord length has square-root behaviour at the top and bottom
// of each circle and kinks where circles cross, so the midpoint error is O(h^1.5) per such
// point, not O(h^2).
MassProps scanLine(const std::vector<Pebble>& ps, int rows) {
    double ylo = 1e300, yhi = -1e300;
    for (const auto& p : ps) {
        ylo = std::min(ylo, p.pos.y() - p.radius);
        yhi = std::max(yhi, p.pos.y() + p.radius);
    }
    const double h = (yhi - ylo) / rows;
    double a = 0, sx = 0, sy = 0, j = 0;
    std::vector<std::pair<double, double>> iv;
    for (int k = 0; k < rows; ++k) {
        const double y = ylo + (k + 0.5) * h;
        iv.clear();
        for (const auto& p : ps) {
            const double dy = y - p.pos.y();
            const double q = p.radius * p.radius - dy * dy;
            if (q > 0) iv.emplace_back(p.pos.x() - std::sqrt(q), p.pos.x() + std::sqrt(q));
        }
        std::sort(iv.begin(), iv.end());
        double len = 0, m1 = 0, m2 = 0;  // \int dx, \int x dx, \int x^2 dx over the union
        double cur0 = 0, cur1 = 0;
        bool open = false;
        auto flush = [&] {
            len += cur1 - cur0;
            m1 += 0.5 * (cur1 * cur1 - cur0 * cur0);
            m2 += (cur1 * cur1 * cur1 - cur0 * cur0 * cur0) / 3.0;
        };
        for (const auto& v : iv) {
            if (open && v.first <= cur1) {
                cur1 = std::max(cur1, v.second);
            } else {
                if (open) flush();
                cur0 = v.first;
                cur1 = v.second;
                open = true;
            }
        }
        if (open) flush();
        a += len * h;
        sx += m1 * h;
        sy += y * len * h;
        j += (m2 + y * y * len) * h;
    }
    MassProps out;
    out.area = a;
    out.centroid = Vec2(sx / a, sy / a);
    out.polar_moment = j - a * out.centroid.squaredNorm();
    return out;
}

std::vector<Pebble> randomCluster(unsigned seed, int n) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> pos(-1.0, 1.0), rad(0.25, 0.8);
    std::vector<Pebble> ps;
    for (int i = 0; i < n; ++i) ps.push_back({{pos(rng), pos(rng)}, rad(rng)});
    return ps;
}

}  // namespace

TEST_CASE("union of disks matches the exact table 3.6", "[clump]") {
    for (const Row& row : table36()) {
        INFO(row.name);
        const MassProps m = talus::unionMassProps(row.pebbles);
        CHECK(relNear(m.area, row.area, 1e-9));
        CHECK(vecNear(m.centroid, row.centroid, 1e-9));
        CHECK(relNear(m.polar_moment, row.jc, 1e-9));
    }
}

TEST_CASE("physical clumps of the An (2006) rock (rho 2600, R 0.1)", "[clump]") {
    // Table 3.6 gives m and I to 7 significant digits: 1e-6 relative.
    const double R = 0.1, rho = 2600.0, h = std::sqrt(3.0) / 2.0;
    struct Case {
        std::vector<Pebble> ps;
        double m, I;
    };
    const std::vector<Case> cases = {
        {{{{-2 * R, 0}, R}, {{0, 0}, R}, {{2 * R, 0}, R}}, 245.0442, 7.759734},
        {{{{0, 0}, R}, {{2 * R, 0}, R}, {{R, 2 * R * h}, R}}, 245.0442, 4.492477},
        {{{{-R, 0}, R}, {{0, 0}, R}, {{R, 0}, R}}, 181.1690, 2.557847},
    };
    for (const auto& c : cases) {
        const talus::RigidMass rm = talus::scaledToDensity(talus::unionMassProps(c.ps), rho);
        CHECK(relNear(rm.mass, c.m, 1e-6));
        CHECK(relNear(rm.inertia, c.I, 1e-6));
    }
    // The naive ratios of the table for the overlapping row (x1.353 and x1.118).
    const auto naive = talus::scaledToDensity(talus::sumMassProps(cases[2].ps), rho);
    CHECK(relNear(naive.mass / 181.1690, 1.353, 1e-3));
    CHECK(relNear(naive.inertia / 2.557847, 1.118, 1e-3));
}

TEST_CASE("plain sum equals its closed form", "[clump]") {
    // Disks r1 = 1 at 0 and r2 = 0.5 at (1, 0) (C3): A = pi (1 + 1/4), x_c = A2 / A,
    // J = sum A_i r_i^2 / 2 + A1 x_c^2 + A2 (1 - x_c)^2. Round-off only: 1e-14.
    const std::vector<Pebble> ps = {{{0, 0}, 1}, {{1, 0}, 0.5}};
    const double a1 = kPi, a2 = kPi * 0.25, a = a1 + a2, xc = a2 / a;
    const double j = a1 * 0.5 + a2 * 0.125 + a1 * xc * xc + a2 * (1 - xc) * (1 - xc);
    const MassProps m = talus::sumMassProps(ps);
    CHECK(relNear(m.area, a, 1e-14));
    CHECK(vecNear(m.centroid, Vec2(xc, 0), 1e-14));
    CHECK(relNear(m.polar_moment, j, 1e-14));
    // Table 3.6's naive columns: C3 sum area 3.9270, C8 naive J_c +4.9 %.
    CHECK(relNear(m.area, 3.9270, 1e-4));
    const MassProps c8 = talus::sumMassProps({{{0, 0}, 1}, {{0.5, 0}, 0.3}});
    CHECK(relNear(c8.polar_moment / (kPi / 2) - 1.0, 0.049, 0.02));
    // The mode switch routes to the same functions.
    CHECK(talus::clumpMassProps(ps, talus::ClumpMassMode::PlainSum).area == m.area);
    CHECK(talus::clumpMassProps(ps, talus::ClumpMassMode::Union).area ==
          talus::unionMassProps(ps).area);
    CHECK_THROWS_AS(talus::clumpMassProps(ps, talus::ClumpMassMode::Direct), talus::InputError);
}

TEST_CASE("union is invariant under translation and rotation", "[clump]") {
    // Only round-off of the transformed inputs differs: 1e-12 relative (to the clump's size
    // for the centroid).
    const auto ps = randomCluster(7, 9);
    const MassProps m0 = talus::unionMassProps(ps);
    const Vec2 shift(12.375, -7.25);
    for (double ang : {0.3, 1.7, -2.9, kPi}) {
        const double c = std::cos(ang), s = std::sin(ang);
        std::vector<Pebble> q = ps;
        for (auto& p : q)
            p.pos = Vec2(c * p.pos.x() - s * p.pos.y(), s * p.pos.x() + c * p.pos.y()) + shift;
        const MassProps m = talus::unionMassProps(q);
        const Vec2 want = Vec2(c * m0.centroid.x() - s * m0.centroid.y(),
                               s * m0.centroid.x() + c * m0.centroid.y()) +
                          shift;
        INFO("angle " << ang);
        CHECK(relNear(m.area, m0.area, 1e-12));
        CHECK(relNear(m.polar_moment, m0.polar_moment, 1e-12));
        CHECK(vecNear(m.centroid, want, 1e-12 * (1.0 + shift.norm())));
    }
}

TEST_CASE("many overlapping disks against scan-line integration", "[clump]") {
    // 200000 rows over a height of about 3.6: h = 1.8e-5. With at most ~2n + n(n-1) = 130
    // singular points (n = 10) each contributing at most ~ r^0.5 h^1.5 ~ 8e-8 to the area, the
    // reference is good to ~1e-5 absolute; we allow 1e-5 relative on A, J_c and the centroid
    // (measured agreement is ~1e-8). A missed or doubly counted arc changes A by >= 1e-3.
    for (unsigned seed : {1u, 2u, 3u}) {
        const auto ps = randomCluster(seed, 10);
        const MassProps m = talus::unionMassProps(ps);
        const MassProps ref = scanLine(ps, 200000);
        INFO("seed " << seed << " A " << m.area << " ref " << ref.area);
        CHECK(relNear(m.area, ref.area, 1e-5));
        CHECK(vecNear(m.centroid, ref.centroid, 1e-5));
        CHECK(relNear(m.polar_moment, ref.polar_moment, 1e-5));
    }
}

TEST_CASE("covered intervals that wrap across the +-pi cut", "[clump]") {
    // Disk 0 is covered around t = pi from both sides of the cut by disks above-left and
    // below-left, and by one straight to the left (its interval straddles the cut itself).
    const std::vector<Pebble> ps = {{{0, 0}, 1},
                                    {{-1.2, 0.25}, 0.6},
                                    {{-1.2, -0.25}, 0.6},
                                    {{-1.0, 0}, 0.5},
                                    {{-0.9, 0.6}, 0.4}};
    const MassProps m = talus::unionMassProps(ps);
    const MassProps ref = scanLine(ps, 200000);
    CHECK(relNear(m.area, ref.area, 1e-5));
    CHECK(vecNear(m.centroid, ref.centroid, 1e-5));
    CHECK(relNear(m.polar_moment, ref.polar_moment, 1e-5));
    // C1 mirrored: the lens of the second disk straddles the cut of the first.
    const MassProps c1 = talus::unionMassProps({{{0, 0}, 1}, {{-1, 0}, 1}});
    CHECK(relNear(c1.area, 5.0548156086, 1e-9));
    CHECK(vecNear(c1.centroid, Vec2(-0.5, 0), 1e-9));
    CHECK(relNear(c1.polar_moment, 4.4406307593, 1e-9));
}

TEST_CASE("degenerate configurations", "[clump]") {
    const MassProps unit = talus::sumMassProps({{{0.3, -0.2}, 1}});
    SECTION("exact duplicates count once") {
        const MassProps m =
            talus::unionMassProps({{{0.3, -0.2}, 1}, {{0.3, -0.2}, 1}, {{0.3, -0.2}, 1}});
        CHECK(relNear(m.area, kPi, 1e-14));
        CHECK(vecNear(m.centroid, unit.centroid, 1e-14));
        CHECK(relNear(m.polar_moment, kPi / 2, 1e-14));
    }
    SECTION("same centre, different radii: the larger disk alone") {
        const MassProps m = talus::unionMassProps({{{0.3, -0.2}, 0.5}, {{0.3, -0.2}, 1}});
        CHECK(relNear(m.area, kPi, 1e-14));
        CHECK(relNear(m.polar_moment, kPi / 2, 1e-14));
    }
    SECTION("internally tangent disk inside") {
        const MassProps m = talus::unionMassProps({{{0, 0}, 1}, {{0.5, 0}, 0.5}});
        CHECK(relNear(m.area, kPi, 1e-12));
        CHECK(relNear(m.polar_moment, kPi / 2, 1e-12));
    }
    SECTION("tangent, barely overlapping and barely apart: continuous") {
        // Two unit disks at d = 2 - e: the lens area is ~ (4/3) sqrt(r) e^1.5 = 4e-14 for
        // e = 1e-9, so A equals the sum 2 pi to ~1e-14; J_c likewise (C6-type closed form
        // J = 2 (pi/2 + pi d^2/4)).
        for (double e : {1e-9, 0.0, -1e-9}) {
            const double d = 2.0 - e;
            const MassProps m = talus::unionMassProps({{{0, 0}, 1}, {{d, 0}, 1}});
            INFO("e " << e);
            CHECK(relNear(m.area, 2 * kPi, 1e-9));
            CHECK(relNear(m.polar_moment, 2 * (kPi / 2 + kPi * d * d / 4), 1e-9));
            CHECK(vecNear(m.centroid, Vec2(d / 2, 0), 1e-12));
        }
    }
}

TEST_CASE("bad pebble input is refused with the index and value", "[clump]") {
    using talus::InputError;
    CHECK_THROWS_AS(talus::unionMassProps({}), InputError);
    CHECK_THROWS_AS(talus::sumMassProps({}), InputError);
    CHECK_THROWS_WITH(talus::unionMassProps({{{0, 0}, 1}, {{1, 0}, -0.5}}),
                      Catch::Contains("pebble 1") && Catch::Contains("-0.5"));
    CHECK_THROWS_WITH(talus::unionMassProps({{{0, 0}, 0.0}}), Catch::Contains("pebble 0"));
    CHECK_THROWS_WITH(talus::sumMassProps({{{0, 0}, 1}, {{0, 0}, 1}, {{0, 0}, NAN}}),
                      Catch::Contains("pebble 2") && Catch::Contains("nan"));
    CHECK_THROWS_WITH(talus::unionMassProps({{{INFINITY, 0}, 1}}),
                      Catch::Contains("pebble 0") && Catch::Contains("inf"));
    CHECK_THROWS_AS(talus::scaledToDensity(talus::sumMassProps({{{0, 0}, 1}}), 0.0), InputError);
    CHECK_THROWS_AS(talus::scaledToDensity(talus::sumMassProps({{{0, 0}, 1}}), NAN), InputError);
}

TEST_CASE("a ring with a hole, and a disk covered only by several others", "[clump]") {
    // Six disks r = 0.6 on a circle of radius 1 overlap their neighbours (spacing 1 < 1.2) and
    // enclose a hole: its boundary is the inner arcs, traversed clockwise around the hole by
    // Green's theorem. A centre disk r = 0.6 is then covered by the ring as a whole (every
    // point of its circle is within 0.57 of a ring centre) though by no single disk, and it
    // fills the hole. Tolerance as for the random clusters (scan line, 1e-5).
    std::vector<Pebble> ring;
    for (int k = 0; k < 6; ++k)
        ring.push_back({{std::cos(k * kPi / 3 + 0.1), std::sin(k * kPi / 3 + 0.1)}, 0.6});
    for (bool centre : {false, true}) {
        std::vector<Pebble> ps = ring;
        if (centre) ps.push_back({{0, 0}, 0.6});
        const MassProps m = talus::unionMassProps(ps);
        const MassProps ref = scanLine(ps, 200000);
        INFO("centre " << centre);
        CHECK(relNear(m.area, ref.area, 1e-5));
        CHECK(vecNear(m.centroid, ref.centroid, 1e-5));
        CHECK(relNear(m.polar_moment, ref.polar_moment, 1e-5));
    }
}
