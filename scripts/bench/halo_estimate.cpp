// SPDX-License-Identifier: MIT
//
// Halo (ghost-layer) counts and pack/unpack cost for a spatial domain decomposition of a dense
// pack, measured on a settled single-machine state (docs/scaling.md). Standalone: no Talus
// library, no MPI; it reads the text state that scripts/bench/dense_pack.sh caches
// (build-bench/bench-cache/state_n<N>_seed1.txt: radius x y vx vy spin per disk).
//
//   g++ -O3 -std=c++17 -o halo_estimate scripts/bench/halo_estimate.cpp
//   ./halo_estimate STATE [margin_over_mean_radius=0.05]
//
// What it counts, with Talus's broadphase rule (core/src/broadphase.hpp): a fat box is the disk's
// box grown by 2 margins when (re)inserted; two disks are a candidate pair while their fat boxes
// overlap. For a border at x = c (or y = c) between domains L and R, a disk of R must be a ghost
// on L when its fat box can reach a fat box owned by L, whose far edge is at most
// c + r_max + 2 margin: with fresh fat boxes, |x - c| < r + r_max + 4 margin. Counted per metre
// of border (both directions), averaged over many cuts away from the walls:
//   - ghosts (region rule above), and the disks that really have a candidate across (the least
//     any rule could send);
//   - contacts (overlap > 0) and candidate pairs whose ends lie on the two sides;
//   - disks crossing the border in one step at their current velocity (migration).
// Then it times the pack and unpack of per-step ghost data (x, v, spin: 40 bytes) from the
// structure-of-arrays layout of BallArrays, with the ghosts of all cuts of an 8-slab split.
// Times are wall clock on whatever machine runs it; counts and bytes do not depend on load.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Vec2 {
    double x, y;
};

struct State {
    std::vector<double> r, spin;
    std::vector<Vec2> pos, vel;
    double width = 0, height = 0, dt = 0;
};

State load(const char* path) {
    std::ifstream in(path);
    if (!in) {
        std::fprintf(stderr, "cannot open %s\n", path);
        std::exit(1);
    }
    State s;
    std::string line;
    bool body = false;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        if (line[0] == '#') {
            if (line.find("radius x y") != std::string::npos) body = true;
            continue;
        }
        std::istringstream ls(line);
        if (!body) {
            std::string key;
            double v = 0;
            ls >> key >> v;
            if (key == "width") s.width = v;
            if (key == "height") s.height = v;
            if (key == "timestep") s.dt = v;
            continue;
        }
        double r, x, y, vx, vy, w;
        if (ls >> r >> x >> y >> vx >> vy >> w) {
            s.r.push_back(r), s.pos.push_back({x, y}), s.vel.push_back({vx, vy}),
                s.spin.push_back(w);
        }
    }
    if (s.r.empty() || s.width <= 0 || s.height <= 0) {
        std::fprintf(stderr, "%s: no disks or no width/height\n", path);
        std::exit(1);
    }
    return s;
}

/// All pairs closer than `reach` between centres (a uniform grid); calls f(i, j) with i < j.
template <class F>
void forPairs(const State& s, double reach, F f) {
    const std::size_t n = s.r.size();
    const int nx = std::max(1, int(s.width / reach)), ny = std::max(1, int(s.height / reach) + 1);
    auto cx = [&](double x) { return std::clamp(int(x / s.width * nx), 0, nx - 1); };
    auto cy = [&](double y) { return std::clamp(int(y / (s.height * 1.05) * ny), 0, ny - 1); };
    std::vector<std::vector<uint32_t>> cells(std::size_t(nx) * ny);
    for (uint32_t i = 0; i < n; ++i) cells[cy(s.pos[i].y) * nx + cx(s.pos[i].x)].push_back(i);
    for (uint32_t i = 0; i < n; ++i) {
        const int ix = cx(s.pos[i].x), iy = cy(s.pos[i].y);
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int jx = ix + dx, jy = iy + dy;
                if (jx < 0 || jy < 0 || jx >= nx || jy >= ny) continue;
                for (uint32_t j : cells[jy * nx + jx])
                    if (j > i) f(i, j);
            }
    }
}

double nowSeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s STATE [margin_over_mean_radius]\n", argv[0]);
        return 2;
    }
    const State s = load(argv[1]);
    const std::size_t n = s.r.size();
    double rmean = 0, rmax = 0;
    for (double r : s.r) rmean += r, rmax = std::max(rmax, r);
    rmean /= double(n);
    const double margin = (argc > 2 ? std::atof(argv[2]) : 0.05) * rmean;

    // --- contacts and candidate pairs (fresh fat boxes: box + 2 margins each side)
    struct Link {
        uint32_t i, j;
        bool contact;
    };
    std::vector<Link> links;
    std::vector<uint8_t> has_cand(n, 0);
    forPairs(s, 2 * rmax + 4 * margin, [&](uint32_t i, uint32_t j) {
        const double dx = s.pos[j].x - s.pos[i].x, dy = s.pos[j].y - s.pos[i].y;
        const double reach = s.r[i] + s.r[j] + 4 * margin;
        if (std::fabs(dx) < reach && std::fabs(dy) < reach) {
            const double d = std::hypot(dx, dy);
            links.push_back({i, j, d < s.r[i] + s.r[j]});
        }
    });
    std::size_t contacts = 0;
    for (const Link& l : links) contacts += l.contact;
    // Packed density away from the walls (the middle of the pack): disks per m^2.
    double ymax = 0;
    for (const Vec2& p : s.pos) ymax = std::max(ymax, p.y);
    std::printf(
        "state: %zu disks, box %.4g x %.4g m, pack top %.4g m, r_mean %.4g m, r_max %.4g m,"
        " margin %.4g m\n",
        n, s.width, s.height, ymax, rmean, rmax, margin);
    std::printf(
        "contacts (ball-ball, overlap > 0): %.3f per disk; candidate pairs (fat boxes "
        "overlap): %.3f per disk\n",
        double(contacts) / n, double(links.size()) / n);

    // --- cuts: vertical (x = c) and horizontal (y = c), at least 6 r_max from any wall
    const double keep = 6 * rmax;
    struct Tally {
        double length = 0, ghosts = 0, needed = 0, cross_contacts = 0, cross_cands = 0, migrate = 0,
               width_sum = 0;
        int cuts = 0;
    } tv, th;
    auto cut = [&](bool vertical, double c, Tally& t, std::vector<uint32_t>* ghost_list) {
        auto coord = [&](uint32_t i) { return vertical ? s.pos[i].x : s.pos[i].y; };
        auto speed = [&](uint32_t i) { return vertical ? s.vel[i].x : s.vel[i].y; };
        auto along = [&](uint32_t i) { return vertical ? s.pos[i].y : s.pos[i].x; };
        // Only disks whose coordinate along the border is 6 r_max inside the walls count, so
        // that the border length is well defined.
        const double lo = keep, hi = vertical ? ymax - keep : s.width - keep;
        auto inside = [&](uint32_t i) { return along(i) > lo && along(i) < hi; };
        for (uint32_t i = 0; i < n; ++i) {
            if (!inside(i)) continue;
            const double d = std::fabs(coord(i) - c);
            const double w = s.r[i] + rmax + 4 * margin;
            if (d < w) {
                t.ghosts += 1, t.width_sum += w;
                if (ghost_list) ghost_list->push_back(i);
            }
            const double next = coord(i) + speed(i) * s.dt;
            if ((coord(i) < c) != (next < c)) t.migrate += 1;
        }
        std::vector<uint8_t> needed(n, 0);
        for (const Link& l : links) {
            if (!inside(l.i) || !inside(l.j)) continue;
            if ((coord(l.i) < c) == (coord(l.j) < c)) continue;
            t.cross_cands += 1, t.cross_contacts += l.contact;
            needed[l.i] = needed[l.j] = 1;
        }
        for (uint8_t b : needed) t.needed += b;
        t.length += hi - lo;
        t.cuts += 1;
    };
    const int kCuts = 40;
    for (int k = 0; k < kCuts; ++k) {
        cut(true, keep + (s.width - 2 * keep) * (k + 0.5) / kCuts, tv, nullptr);
        cut(false, keep + (ymax - 2 * keep) * (k + 0.5) / kCuts, th, nullptr);
    }
    // Number density in the interior (between the cuts' limits).
    std::size_t interior = 0;
    for (uint32_t i = 0; i < n; ++i)
        interior += s.pos[i].x > keep && s.pos[i].x < s.width - keep && s.pos[i].y > keep &&
                    s.pos[i].y < ymax - keep;
    const double rho = double(interior) / ((s.width - 2 * keep) * (ymax - 2 * keep));
    std::printf("interior number density: %.6g disks/m^2 (%.4f disks per (2 r_mean)^2)\n", rho,
                rho * 4 * rmean * rmean);
    std::printf("\nper metre of border, both directions (mean over %d cuts each):\n", kCuts);
    std::printf(
        "| cuts | ghosts (region rule) | ghosts needed (candidate across) | contacts across "
        "| candidates across | migrating per step | mean ghost width / r_mean |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    for (const Tally* t : {&tv, &th})
        std::printf("| %s | %.6g | %.6g | %.6g | %.6g | %.3g | %.3f |\n",
                    t == &tv ? "vertical" : "horizontal", t->ghosts / t->length,
                    t->needed / t->length, t->cross_contacts / t->length,
                    t->cross_cands / t->length, t->migrate / t->length,
                    t->width_sum / t->ghosts / rmean);
    const double g_per_m = (tv.ghosts + th.ghosts) / (tv.length + th.length);
    const double c_per_m = (tv.cross_contacts + th.cross_contacts) / (tv.length + th.length);
    const double p_per_m = (tv.cross_cands + th.cross_cands) / (tv.length + th.length);
    const double gw = (tv.width_sum + th.width_sum) / (tv.ghosts + th.ghosts);
    std::printf(
        "RESULT rho=%.6g ghosts_per_m=%.6g contacts_per_m=%.6g candidates_per_m=%.6g "
        "ghost_width=%.6g r_mean=%.6g contacts_per_disk=%.4f candidates_per_disk=%.4f\n",
        rho, g_per_m, c_per_m, p_per_m, gw, rmean, double(contacts) / n, double(links.size()) / n);

    // --- pack / unpack of per-step ghost data from SoA (BallArrays: pos, vel as Vec2; spin)
    std::vector<uint32_t> ghosts;
    Tally scratch;
    for (int k = 1; k < 8; ++k) cut(true, s.width * k / 8.0, scratch, &ghosts);
    std::vector<uint32_t> sorted = ghosts;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t g = ghosts.size();
    std::vector<double> buf(5 * g);
    std::vector<Vec2> gpos(g), gvel(g);
    std::vector<double> gspin(g);
    auto timeIt = [&](const std::vector<uint32_t>& list, bool unpack) {
        double best = 1e30;
        for (int rep = 0; rep < 15; ++rep) {
            const int inner = 200;
            const double t0 = nowSeconds();
            for (int it = 0; it < inner; ++it) {
                if (!unpack) {
                    double* b = buf.data();
                    for (uint32_t i : list) {
                        b[0] = s.pos[i].x, b[1] = s.pos[i].y, b[2] = s.vel[i].x, b[3] = s.vel[i].y,
                        b[4] = s.spin[i];
                        b += 5;
                    }
                } else {
                    const double* b = buf.data();
                    for (std::size_t k = 0; k < list.size(); ++k, b += 5)
                        gpos[k] = {b[0], b[1]}, gvel[k] = {b[2], b[3]}, gspin[k] = b[4];
                }
                // Keep the compiler from dropping the loop.
                asm volatile("" : : "r"(buf.data()), "r"(gpos.data()) : "memory");
            }
            best = std::min(best, (nowSeconds() - t0) / inner / double(list.size()));
        }
        return best * 1e9;
    };
    const double pack_shuffled = timeIt(ghosts, false), pack_sorted = timeIt(sorted, false);
    const double unpack = timeIt(ghosts, true);
    // Contact-state migration record: a flat copy of ~376 bytes per contact (docs/scaling.md).
    const std::size_t rec = 376, nrec = 4096;
    std::vector<unsigned char> src(rec * nrec, 1), dst(rec * nrec);
    double best_rec = 1e30;
    for (int rep = 0; rep < 15; ++rep) {
        const double t0 = nowSeconds();
        for (int it = 0; it < 50; ++it) {
            for (std::size_t k = 0; k < nrec; ++k)
                std::memcpy(&dst[k * rec], &src[((k * 2654435761u) % nrec) * rec], rec);
            asm volatile("" : : "r"(dst.data()) : "memory");
        }
        best_rec = std::min(best_rec, (nowSeconds() - t0) / 50 / double(nrec));
    }
    // The same gather from a rank's share of 10M disks (625 000 disks, 16 ranks; arrays of 25 MB,
    // beyond this machine's caches) for 4 000 ghosts, in random order and in increasing order
    // (Morton-sorted balls put a border's disks in runs).
    const std::size_t nbig = 625000, gbig = 4000;
    State big;
    big.pos.assign(nbig, {1.0, 2.0}), big.vel.assign(nbig, {3.0, 4.0}), big.spin.assign(nbig, 5.0);
    std::vector<uint32_t> rnd(gbig), run(gbig);
    uint64_t z = 1;
    for (std::size_t k = 0; k < gbig; ++k) {
        z = z * 6364136223846793005ull + 1442695040888963407ull;  // LCG: any spread will do
        rnd[k] = uint32_t((z >> 33) % nbig);
        run[k] = uint32_t(k * (nbig / gbig) / 8 * 8 + k % 8);  // runs of 8 disks
    }
    std::vector<double> bigbuf(5 * gbig);
    auto timeBig = [&](const std::vector<uint32_t>& list) {
        double best = 1e30;
        for (int rep = 0; rep < 15; ++rep) {
            const double t0 = nowSeconds();
            for (int it = 0; it < 20; ++it) {
                double* b = bigbuf.data();
                for (uint32_t i : list) {
                    b[0] = big.pos[i].x, b[1] = big.pos[i].y, b[2] = big.vel[i].x,
                    b[3] = big.vel[i].y, b[4] = big.spin[i];
                    b += 5;
                }
                asm volatile("" : : "r"(bigbuf.data()) : "memory");
            }
            best = std::min(best, (nowSeconds() - t0) / 20 / double(list.size()));
        }
        return best * 1e9;
    };
    const double pack_big_random = timeBig(rnd), pack_big_runs = timeBig(run);
    std::printf(
        "RESULT pack_big_random_ns=%.2f pack_big_runs_ns=%.2f (625000 disks, 4000 ghosts; "
        "warm repeats, so the random case is partly cached: a lower bound)\n",
        pack_big_random, pack_big_runs);
    std::printf(
        "\npack/unpack, %zu ghosts of an 8-slab split of this pack, 40 bytes each, min of "
        "15 x 200 repetitions:\n",
        g);
    std::printf(
        "RESULT pack_ns_per_ghost_memory_order=%.2f pack_ns_per_ghost_sorted=%.2f "
        "unpack_ns_per_ghost=%.2f contact_record_copy_ns=%.1f\n",
        pack_shuffled, pack_sorted, unpack, best_rec * 1e9);
    return 0;
}
