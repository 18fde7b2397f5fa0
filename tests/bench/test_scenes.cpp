// SPDX-License-Identifier: MIT
//
// Physics sanity of the dense-pack scene (talus/scenes.hpp) that the speed benchmark times:
// a small pack settles to rest, the walls carry its weight, no contact is overlapped by more
// than a small fraction of a radius, and the saved state round-trips exactly.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "talus/model.hpp"
#include "talus/scenes.hpp"

using namespace talus;

namespace {

DensePackDef smallPack() {
    DensePackDef d;
    d.n = 500;
    d.seed = 7;
    return d;
}

std::string tempPath(const char* name) {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir && *dir ? dir : "/tmp") + "/talus_test_scenes_" + name;
}

}  // namespace

TEST_CASE("dense pack: damping ratio from restitution", "[scenes]") {
    // the closed form of a linear spring-dashpot: e = exp(-pi beta / sqrt(1 - beta^2)) for the full
    // dashpot.
    for (double e : {0.1, 0.5, 0.9}) {
        const double b = dampingRatioForRestitution(e);
        CHECK(std::exp(-M_PI * b / std::sqrt(1.0 - b * b)) == Approx(e).epsilon(1e-12));
    }
    // No-tension variant (same section): reaches only e > exp(-2) while underdamped.
    for (double e : {0.2, 0.5, 0.9}) {
        const double bt = dampingRatioForRestitution(e, true);
        CHECK(std::exp(-bt * (M_PI - 2.0 * std::asin(bt)) / std::sqrt(1.0 - bt * bt)) ==
              Approx(e).epsilon(1e-9));
    }
    CHECK_THROWS(dampingRatioForRestitution(0.1, true));
    // The value docs/benchmarks.md uses for e = 0.5.
    CHECK(dampingRatioForRestitution(0.5) == Approx(0.2154538).epsilon(1e-6));
}

TEST_CASE("dense pack: deterministic and overlap-free at build", "[scenes]") {
    const DensePackDef d = smallPack();
    Model a, b;
    const DensePack pa = buildDensePack(a, d);
    const DensePack pb = buildDensePack(b, d);
    REQUIRE(pa.balls.size() == 500);
    REQUIRE(a.wallCount() == 4);
    double min_gap = 1e300;
    for (std::size_t i = 0; i < pa.balls.size(); ++i) {
        CHECK(a.ballPos(pa.balls[i]) == b.ballPos(pb.balls[i]));
        const double r = a.ballRadius(pa.balls[i]);
        CHECK(r >= d.r_min);
        CHECK(r <= d.r_max);
        const Vec2 x = a.ballPos(pa.balls[i]);
        min_gap =
            std::min({min_gap, x.x() - r, pa.width - x.x() - r, x.y() - r, pa.height - x.y() - r});
        for (std::size_t j = 0; j < i; ++j)
            min_gap = std::min(min_gap,
                               (x - a.ballPos(pa.balls[j])).norm() - r - a.ballRadius(pa.balls[j]));
    }
    CHECK(min_gap > 0.0);
}

TEST_CASE("dense pack: settles to rest with the weight on the walls", "[scenes]") {
    const DensePackDef d = smallPack();
    Model model;
    const DensePack pack = buildDensePack(model, d);
    const SettleResult sr = settleDensePack(model, pack, d);
    INFO("settled in " << sr.steps << " steps, KE/disk " << sr.ke_per_ball);
    REQUIRE(sr.converged);
    // Settling restores the scene's own damping (none) for later cycles.
    CHECK(model.damping().local == 0.0);

    // One more step so that the wall forces are those of the settled state.
    model.cycle(1);
    Vec2 on_walls = Vec2::Zero();
    for (WallId w : {pack.floor, pack.right, pack.top, pack.left}) on_walls += model.wallForce(w);
    INFO("walls carry " << -on_walls.y() << " N of " << pack.weight << " N; floor "
                        << -model.wallForce(pack.floor).y() << " N");
    CHECK(-on_walls.y() == Approx(pack.weight).epsilon(0.01));
    CHECK(std::fabs(on_walls.x()) < 0.01 * pack.weight);
    CHECK(model.wallForce(pack.top).squaredNorm() == 0.0);  // the pack settled below the lid

    // The deepest overlap: a column of about 12 disks over a few contacts gives a few newtons,
    // i.e. overlaps of a few micrometres with kn = 1e6 N/m; 1% of the smallest radius (8 um)
    // is a generous bound that a wrong stiffness, mass or gravity would still break.
    double max_overlap = 0.0;
    for (const ContactInfo& c : model.contacts(true))
        max_overlap = std::max(max_overlap, c.overlap);
    INFO("max overlap " << max_overlap << " m");
    CHECK(max_overlap > 0.0);
    CHECK(max_overlap < 0.01 * d.r_min);

    // The settled state round-trips exactly through the file, and rebuilds the same scene.
    const PackState st = capturePackState(model, pack, d);
    const std::string path = tempPath("state.txt");
    savePackState(st, path);
    const PackState back = loadPackState(path);
    CHECK(sameScene(back.def, d));
    REQUIRE(back.balls.size() == st.balls.size());
    bool exact = true;
    for (std::size_t i = 0; i < st.balls.size(); ++i) {
        const PackBall &x = st.balls[i], &y = back.balls[i];
        exact = exact && x.radius == y.radius && x.x == y.x && x.y == y.y && x.vx == y.vx &&
                x.vy == y.vy && x.spin == y.spin;
    }
    CHECK(exact);
    Model again;
    const DensePack p2 = buildDensePackFromState(again, back);
    CHECK(p2.width == pack.width);
    CHECK(again.ballPos(p2.balls[17]) == model.ballPos(pack.balls[17]));
    CHECK(again.ballMass(p2.balls[17]) == model.ballMass(pack.balls[17]));
    std::remove(path.c_str());

    // The LAMMPS data file holds one Atoms and one Velocities line per disk.
    const std::string lmp = tempPath("pack.data");
    writeLammpsData(st, lmp);
    std::ifstream in(lmp);
    std::string line;
    int lines = 0;
    while (std::getline(in, line)) ++lines;
    CHECK(lines == 2 * d.n + 14);
    std::remove(lmp.c_str());
}
