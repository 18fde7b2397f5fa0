// SPDX-License-Identifier: MIT
//
// Dense-pack speed benchmark (docs/benchmarks.md). Builds and settles the dense pack of
// talus/scenes.hpp (or loads a cached settled state), then, from that state, times cycle(steps)
// with the fixed step and prints ns per particle-step, contacts and pairs per particle, and the
// per-phase profile. Every timed run starts from a fresh model built from the same saved state,
// the same state the LAMMPS input reads (--export-lammps), so the two codes start equal.
//
// Usage: talus_bench_dense_pack N STEPS [sorted|unsorted|both] [options]
//   sorted     memory reordering on (Model::setSortInterval, --sort-interval steps)
//   unsorted   off: the disks stay in creation order, which the builder randomises
// Options:
//   --state FILE          settled-state cache: loaded if it holds this scene, else written
//   --export-lammps FILE  LAMMPS data file of the starting state
//   --warmup STEPS        untimed steps before the timed run (default 1000)
//   --sort-interval K     (default 1000, as LAMMPS's default atom sort)
//   --seed S  --aspect A  scene parameters (defaults 1 and 4)
//   --guard on|off        the engine's stability guard (default: the engine's default)
//   --auto-step           the automatic time step for the timed run (its limits gathered by the
//                         force loop every step), instead of the scene's fixed step
//   --groups N            assign the balls to N groups (0-64) before the timed run (with
//                         --energy on: energy traced per group)
//   --group-layout L      how: "robin" (round-robin in creation order: nearly every contact
//                         crosses a group border, the worst case) or "bands" (N vertical bands of
//                         equal width: contacts cross only at the bands' borders); default robin
//   --no-profile          time without the per-phase clock reads
//   --no-kernels          the shipped models' FDlaw instead of the host's kernels
//                         (testing::setKernels)
//   --settle-only         stop after settling (and exporting)
//   --tiles K             for large N (scripts/bench/scaling.sh): instead of settling N disks
//                         from the lattice, settle N/K disks (aspect A) and lay K copies side by
//                         side, every other one mirrored, in a box K times as wide, then relax
//                         that with local damping (see tiledState); the state is of N disks,
//                         aspect K*A
//   --tile-state FILE     settled-state cache of the N/K-disk pack (with --tiles)
// Each timed run prints one machine-readable line starting with "RESULT" (key=value pairs);
// scripts/bench/dense_pack.sh collects them.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include "force_switches.hpp"
#include "talus/errors.hpp"
#include "talus/model.hpp"
#include "talus/scenes.hpp"
#include "talus/splitmix.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
    int n = 0;
    int64_t steps = 0;
    std::string mode = "both";
    std::string state_path;
    std::string lammps_path;
    int64_t warmup = 1000;
    int64_t sort_interval = 1000;
    uint64_t seed = 1;
    double aspect = 4.0;
    std::string guard;  // "" = engine default
    bool auto_step = false;
    std::string energy = "off";  // energy tracing during the timed run
    std::string balance = "on";  // the run-level balance check (while tracing)
    int groups = 0;              // balls assigned to this many groups (energy per group)
    std::string group_layout = "robin";
    bool profile = true;
    bool kernels = true;
    bool settle_only = false;
    int tiles = 1;                // > 1: the state is made from K copies of an N/K pack
    std::string tile_state_path;  // cache of the N/K pack
};

[[noreturn]] void usage(const char* why) {
    std::fprintf(stderr,
                 "error: %s\nusage: talus_bench_dense_pack N STEPS [sorted|unsorted|both] "
                 "[--state FILE] [--export-lammps FILE] [--warmup S] [--sort-interval K] "
                 "[--seed S] [--aspect A] [--guard on|off] [--energy on|off] [--groups N] "
                 "[--group-layout robin|bands] "
                 "[--balance on|off] "
                 "[--no-profile] [--no-kernels] [--settle-only] [--tiles K] "
                 "[--tile-state FILE]\n",
                 why);
    std::exit(2);
}

Options parse(int argc, char** argv) {
    Options o;
    std::vector<std::string> pos;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) usage(("missing value after " + a).c_str());
            return argv[++i];
        };
        if (a == "--state")
            o.state_path = value();
        else if (a == "--export-lammps")
            o.lammps_path = value();
        else if (a == "--warmup")
            o.warmup = std::atoll(value().c_str());
        else if (a == "--sort-interval")
            o.sort_interval = std::atoll(value().c_str());
        else if (a == "--seed")
            o.seed = std::strtoull(value().c_str(), nullptr, 10);
        else if (a == "--aspect")
            o.aspect = std::atof(value().c_str());
        else if (a == "--guard")
            o.guard = value();
        else if (a == "--auto-step")
            o.auto_step = true;
        else if (a == "--energy")
            o.energy = value();
        else if (a == "--groups")
            o.groups = std::atoi(value().c_str());
        else if (a == "--group-layout")
            o.group_layout = value();
        else if (a == "--balance")
            o.balance = value();
        else if (a == "--no-profile")
            o.profile = false;
        else if (a == "--no-kernels")
            o.kernels = false;
        else if (a == "--settle-only")
            o.settle_only = true;
        else if (a == "--tiles")
            o.tiles = std::atoi(value().c_str());
        else if (a == "--tile-state")
            o.tile_state_path = value();
        else if (a.rfind("--", 0) == 0)
            usage(("unknown option " + a).c_str());
        else
            pos.push_back(a);
    }
    if (pos.size() < 2 || pos.size() > 3) usage("need N and STEPS");
    o.n = std::atoi(pos[0].c_str());
    o.steps = std::atoll(pos[1].c_str());
    if (pos.size() == 3) o.mode = pos[2];
    if (o.n < 1 || o.steps < 1) usage("N and STEPS must be >= 1");
    if (o.mode != "sorted" && o.mode != "unsorted" && o.mode != "both") usage("bad mode");
    if (!o.guard.empty() && o.guard != "on" && o.guard != "off") usage("--guard on|off");
    if ((o.energy != "on" && o.energy != "off") || (o.balance != "on" && o.balance != "off"))
        usage("--energy on|off, --balance on|off");
    if (o.warmup < 0 || o.sort_interval < 1) usage("bad --warmup or --sort-interval");
    if (o.groups < 0 || o.groups > 64) usage("--groups N needs 0 <= N <= 64");
    if (o.group_layout != "robin" && o.group_layout != "bands") usage("--group-layout robin|bands");
    if (o.tiles < 1 || o.n % o.tiles != 0) usage("--tiles K needs K >= 1 dividing N");
    if (o.tiles == 1 && !o.tile_state_path.empty()) usage("--tile-state needs --tiles K > 1");
    return o;
}

double seconds(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

/// Writes through a temporary file and a rename, so an interrupted run never leaves a truncated
/// cache behind (the next run would stop on it instead of settling again).
void saveStateAtomically(const talus::PackState& st, const std::string& path) {
    const std::string tmp = path + ".tmp";
    talus::savePackState(st, tmp);
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
        throw talus::InputError("cannot rename '" + tmp + "' to '" + path + "'");
}

/// The cached state at `path` if it holds the scene `def`, else nothing.
bool loadCached(const std::string& path, const talus::DensePackDef& def, talus::PackState& st) {
    if (path.empty() || !std::ifstream(path).good()) return false;
    talus::PackState s = talus::loadPackState(path);
    if (talus::sameScene(s.def, def) && s.def.shuffle == def.shuffle) {
        std::printf("state: loaded %s (%zu disks)\n", path.c_str(), s.balls.size());
        st = std::move(s);
        return true;
    }
    std::printf("state: %s holds another scene; making it anew\n", path.c_str());
    return false;
}

/// The settled state of `def`: from the cache at `path` if it holds this scene, else built from
/// the lattice and settled now (and written to `path`).
talus::PackState settledState(const std::string& path, const talus::DensePackDef& def) {
    talus::PackState cached;
    if (loadCached(path, def, cached)) return cached;
    const auto t0 = Clock::now();
    talus::Model model;
    const talus::DensePack pack = talus::buildDensePack(model, def);
    const talus::SettleResult sr = talus::settleDensePack(model, pack, def);
    const double wall = seconds(t0, Clock::now());
    std::printf(
        "settle: N = %d, %lld steps (%.4f s simulated, %.4f s of it undamped) in %.1f s wall, "
        "KE/disk %.3g J (limit %.3g J)%s\n",
        def.n, static_cast<long long>(sr.steps), sr.time, sr.fall_time, wall, sr.ke_per_ball,
        sr.ke_limit, sr.converged ? "" : " -- NOT converged (time cap)");
    std::printf("box %.6g m x %.6g m, weight %.6g N\n", pack.width, pack.height, pack.weight);
    talus::PackState st = talus::capturePackState(model, pack, def);
    if (!path.empty()) {
        saveStateAtomically(st, path);
        std::printf("state: wrote %s\n", path.c_str());
    }
    return st;
}

/// A large settled pack made from K copies of a settled small one (--tiles K). Settling N disks
/// from the lattice costs about N x (fall + damping steps), and both grow with the pack's height,
/// so 1M disks would take hours. The copies stand side by side on the floor, tile k at
/// x + k W0 and mirrored (x -> W0 - x, vx -> -vx, spin -> -spin) when k is odd: at every seam a
/// pack meets its own mirror image, so each disk that leant on a side wall now leans on its image
/// at the same place (a ball-ball overlap of twice its wall overlap, micrometres), and nothing
/// else changes: the height, and so the pressure at every depth, is the small pack's. The copies
/// are then shuffled (the creation order is random, as for a lattice-built pack) and the whole
/// relaxed as the second phase of settleDensePack does: PFC local damping 0.7, guard off, at
/// least kMinRelaxSteps steps (about 60 durations of the shortest contact, 16 steps, for the
/// seams' overlaps to relax; a disturbance travels at about d sqrt(kn/m) = 22 m/s, 0.2 mm per
/// step, so what reaches further is left to the energy test), then until the mean kinetic energy
/// per disk is below the settle's limit. The box is K times as wide, so the scene's aspect is K A;
/// its def.n is N and the rest of the def is the small pack's.
talus::PackState tiledState(const Options& o, const talus::DensePackDef& def,
                            const talus::DensePackDef& tile_def) {
    talus::PackState cached;
    if (loadCached(o.state_path, def, cached)) return cached;
    const talus::PackState tile = settledState(o.tile_state_path, tile_def);
    const auto t0 = Clock::now();
    talus::PackState st;
    st.def = def;
    st.width = o.tiles * tile.width;
    st.height = tile.height;
    st.balls.reserve(static_cast<std::size_t>(def.n));
    for (int k = 0; k < o.tiles; ++k)
        for (talus::PackBall b : tile.balls) {
            if (k % 2 == 1) {
                b.x = tile.width - b.x;
                b.vx = -b.vx;
                b.spin = -b.spin;
            }
            b.x += k * tile.width;
            st.balls.push_back(b);
        }
    talus::SplitMix64 rng(def.seed);
    for (std::size_t i = st.balls.size(); i > 1; --i)  // Fisher-Yates
        std::swap(st.balls[i - 1], st.balls[rng.below(i)]);

    constexpr int64_t kMinRelaxSteps = 1000;
    constexpr int64_t kMaxRelaxSteps = 40000;
    constexpr int64_t kCheckEvery = 200;
    const talus::SettleSettings settle_rule;  // the same KE limit and damping as the settle
    talus::Model model;
    const talus::DensePack pack = talus::buildDensePackFromState(model, st);
    double mean_mass = 0.0, mean_radius = 0.0;
    for (const talus::BallId id : pack.balls)
        mean_mass += model.ballMass(id), mean_radius += model.ballRadius(id);
    mean_mass /= static_cast<double>(pack.balls.size());
    mean_radius /= static_cast<double>(pack.balls.size());
    const double ke_limit = settle_rule.ke_fraction * mean_mass * def.gravity * mean_radius;
    const talus::GuardSettings saved_guard = model.guard();
    const double saved_damping = model.damping().local;
    model.guard() = talus::GuardSettings::allOff();
    model.damping().local = settle_rule.local_damping;
    model.setSortInterval(1000);  // as in the timed runs; the order of the saved state is kept
    int64_t steps = 0;
    double ke = talus::meanKineticEnergy(model), ke_max = ke;
    const double ke_first = ke;
    while (steps < kMaxRelaxSteps) {
        model.cycle(kCheckEvery);
        steps += kCheckEvery;
        ke = talus::meanKineticEnergy(model);
        ke_max = std::max(ke_max, ke);
        if (steps >= kMinRelaxSteps && ke < ke_limit) break;
    }
    model.damping().local = saved_damping;
    model.guard() = saved_guard;
    const double wall = seconds(t0, Clock::now());
    std::printf(
        "tile: %d copies of the %d-disk pack (%.6g m x %.6g m), relaxed %lld steps in %.1f s "
        "wall; KE/disk %.3g J at the start, %.3g J at most, %.3g J at the end (limit %.3g J)%s\n",
        o.tiles, tile_def.n, tile.width, tile.height, static_cast<long long>(steps), wall, ke_first,
        ke_max, ke, ke_limit, ke < ke_limit ? "" : " -- NOT converged (step cap)");
    // capturePackState reads the balls in creation order (pack.balls), whatever the sort did.
    st = talus::capturePackState(model, pack, def);
    if (!o.state_path.empty()) {
        saveStateAtomically(st, o.state_path);
        std::printf("state: wrote %s\n", o.state_path.c_str());
    }
    return st;
}

/// The process's peak resident memory so far [bytes].
std::size_t peakResident() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<std::size_t>(u.ru_maxrss) * 1024;
}

void timedRun(const Options& o, const talus::PackState& st, bool sorted) {
    // The memory the model takes: the peak resident memory after its run over the peak before
    // it was made (the state loaded, the process's libraries).
    const std::size_t peak_before = peakResident();
    talus::Model model;
    const talus::DensePack pack = talus::buildDensePackFromState(model, st);
    // Rebuilt from its saved state, the pack's contacts start overlapping at the first step, as
    // saved: on purpose, so not reported.
    model.setPlacementWarning(false);
    if (o.guard == "off")
        model.guard() = talus::GuardSettings::allOff();
    else if (o.guard == "on")
        model.guard() = talus::GuardSettings{};  // every check at its default (warn)
    const bool guard_on = model.guard().anyOn();
    if (o.balance == "off") model.guard().balance = talus::GuardAction::Off;
    if (o.auto_step) model.timestep().automatic = true;
    model.setSortInterval(sorted ? o.sort_interval : 0);
    model.profile().enabled = o.profile;
    talus::testing::setKernels(model, o.kernels);
    if (o.warmup > 0) model.cycle(o.warmup);
    if (o.groups > 0) {
        int k = 0;
        for (const talus::BallId id : model.ballIds()) {
            int g = k++ % o.groups;
            if (o.group_layout == "bands")
                g = std::clamp(static_cast<int>(model.ballPos(id).x() / pack.width * o.groups), 0,
                               o.groups - 1);
            model.addBallGroup(id, "g" + std::to_string(g));
        }
    }
    model.setEnergyTracing(o.energy == "on");
    model.profile().reset();
    const double ke_start = talus::meanKineticEnergy(model);

    const auto t0 = Clock::now();
    const std::clock_t c0 = std::clock();
    model.cycle(o.steps);
    const double wall = seconds(t0, Clock::now());
    // CPU time of the process over the same interval: cpu/wall well below 1 means the machine
    // was busy and the wall time is inflated (LAMMPS prints the same as "% CPU use").
    const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    // Taken before the queries below: the lists they return are the bench's, not the model's.
    const std::size_t peak_after = peakResident();

    const double n = static_cast<double>(model.ballCount());
    const std::size_t active = model.contactCount(true);
    const std::size_t pairs = model.contactCount(false);
    std::size_t wall_contacts = 0;
    for (const talus::ContactInfo& c : model.contacts(true)) wall_contacts += c.wall.valid();
    const double ns = 1e9 * wall / (static_cast<double>(o.steps) * n);
    const talus::Profile& p = model.profile();
    double floor_share = 0.0;
    if (pack.weight > 0.0) floor_share = -model.wallForce(pack.floor).y() / pack.weight;

    std::printf(
        "\n== Talus dense pack, N = %d, %lld steps (after %lld warm-up), memory order %s%s\n", o.n,
        static_cast<long long>(o.steps), static_cast<long long>(o.warmup),
        sorted ? "sorted every " : "unsorted",
        sorted ? (std::to_string(o.sort_interval) + " steps").c_str() : "");
    std::printf("wall time %.3f s (%.1f%% CPU use): %.2f ns per particle-step\n", wall,
                100.0 * cpu / wall, ns);
    std::printf(
        "contacts per particle %.4f (ball-ball %.4f, %zu wall contacts), pairs per "
        "particle %.4f\n",
        double(active) / n, double(active - wall_contacts) / n, wall_contacts, double(pairs) / n);
    const double ke_end = talus::meanKineticEnergy(model);
    const double bytes_per_disk = static_cast<double>(peak_after - peak_before) / n;
    std::printf("memory: %.0f bytes per disk (peak resident over the peak before the model)\n",
                bytes_per_disk);
    std::printf(
        "mean KE per disk %.3g J at the start, %.3g J at the end; the floor carries %.4f "
        "of the weight\n",
        ke_start, ke_end, floor_share);
    if (o.profile) std::printf("%s", p.report(model.ballCount()).c_str());
    std::printf(
        "RESULT code=talus n=%d steps=%lld warmup=%lld mode=%s sort_interval=%lld guard=%s "
        "energy=%s groups=%d group_layout=%s balance=%s "
        "profile=%d wall_s=%.6f cpu_s=%.6f ns_per_particle_step=%.4f contacts_per_particle=%.5f "
        "ball_contacts_per_particle=%.5f wall_contacts=%zu pairs_per_particle=%.5f "
        "t_timestep=%.6f t_motion=%.6f t_detection=%.6f t_force=%.6f t_bookkeeping=%.6f "
        "proxy_moves=%lld pairs_created=%lld contacts_created=%lld ke_start=%.4g ke_end=%.4g "
        "bytes_per_disk=%.1f\n",
        o.n, static_cast<long long>(o.steps), static_cast<long long>(o.warmup),
        sorted ? "sorted" : "unsorted", static_cast<long long>(sorted ? o.sort_interval : 0),
        guard_on ? "on" : "off", o.energy.c_str(), o.groups, o.group_layout.c_str(),
        o.balance.c_str(), o.profile ? 1 : 0, wall, cpu, ns, double(active) / n,
        double(active - wall_contacts) / n, wall_contacts, double(pairs) / n, p.timestep, p.motion,
        p.detection, p.force_displacement, p.bookkeeping, static_cast<long long>(p.proxy_moves),
        static_cast<long long>(p.pairs_created), static_cast<long long>(p.contacts_created),
        ke_start, ke_end, bytes_per_disk);
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    try {
        talus::DensePackDef def;
        def.n = o.n;
        def.seed = o.seed;
        def.aspect = o.aspect;
        talus::PackState st;
        if (o.tiles == 1) {
            st = settledState(o.state_path, def);
        } else {
            talus::DensePackDef tile_def = def;
            tile_def.n = o.n / o.tiles;
            def.aspect = o.aspect * o.tiles;
            st = tiledState(o, def, tile_def);
        }
        if (!o.lammps_path.empty()) {
            talus::writeLammpsData(st, o.lammps_path);
            std::printf("lammps: wrote %s\n", o.lammps_path.c_str());
        }
        if (o.settle_only) return 0;
        if (o.mode != "unsorted") timedRun(o, st, true);
        if (o.mode != "sorted") timedRun(o, st, false);
    } catch (const talus::Error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
