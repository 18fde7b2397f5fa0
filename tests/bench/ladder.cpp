// SPDX-License-Identifier: MIT
//
// The force loop's ladder (docs/results/force-loop-ladder.md): where a dense-pack step's time
// goes, from a loop as plain as a textbook DEM kernel over the engine's own data up to the whole
// engine with its features, one rung at a time. Each rung is a whole step (forces, then the
// ball update) on the dense pack of talus/scenes.hpp, loaded from its settled state, warmed up by
// the engine (its balls sorted, its contacts made), then timed:
//
//   plain     the pairs' ends copied into two index arrays, a shear force and a dashpot
//             coefficient per pair: the textbook linear law (explicit dashpot, shear spring
//             capped by Coulomb), forces added onto the balls at once, leapfrog. No detection.
//   law       + the engine's linear law (talus/sdk/linear_law.hpp: the implicit dashpots with
//             their history, the estimates) on each contact's kernel row
//   pair      + the engine's pair record (world/types.hpp: Pair, 48 bytes) and its rule,
//             instead of the index arrays: the forces kept in the record
//   narrow    + the engine's narrowphase and the law's inputs (force/pass_geometry.hpp: the
//             contact point, the half-step shear correction, wall segments with their chain rule)
//   dispatch  + the host's kernel dispatch (force/kernels.hpp: the law's block, the runner)
//   finish    the engine's force loop (force/loop.cpp: activation, separation, the finish of
//             each pair, the broadphase check of pairs apart), every feature off; own ball update
//   engine    the engine's whole step (Model::cycle): + the time-step phase, the law of motion,
//             detection, bookkeeping; fixed step, guard off, tracing off
//   guard     + the stability guard (the engine's default)
//   autostep  + the automatic step's notes (guard on)
//   energy    + energy tracing (guard on)
//   bands     + 8 groups in spatial bands, energy per group (guard on)
//   robin     + 8 groups round-robin (every contact crosses a border), energy per group
//   threads2  the default engine step on 2 threads
//
// The rungs below `finish` keep the pair list they start with (the engine's, after the
// warm-up): in a settled pack over a few thousand steps that is what a kernel between rebuilds
// does, and a contact touching for the first time runs the textbook law from zero shear force.
// Costs, not physics: the rungs' trajectories part after a few steps.
//
// Usage: talus_bench_ladder N STEPS --state FILE [--warmup W] [--rung NAME]... [--memory]
// --memory prints, after the first rung's warm-up, the bytes per disk each store of the world
// holds (its vectors' capacity) and the process's peak resident memory over what it held before
// the model was made.
// Each rung prints one line "RESULT rung=NAME ..." (ns per particle-step, pairs, contacts). The
// timed steps run between callgrind's collection toggles (valgrind/callgrind.h, when the build
// has it): `valgrind --tool=callgrind --collect-atstart=no [--cache-sim=yes]` counts them alone
// (scripts/bench/ladder.sh).
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "force/force.hpp"
#include "force/kernels.hpp"
#include "force/pass_geometry.hpp"
#include "force/pass_law.hpp"
#include "force/view.hpp"
#include "step/step.hpp"
#include "talus/errors.hpp"
#include "talus/model.hpp"
#include "talus/scenes.hpp"
#include "world/world.hpp"

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define TALUS_LADDER_START() CALLGRIND_START_INSTRUMENTATION
#define TALUS_LADDER_STOP() CALLGRIND_STOP_INSTRUMENTATION
#else
#define TALUS_LADDER_START() ((void)0)
#define TALUS_LADDER_STOP() ((void)0)
#endif

namespace {

using namespace talus;
using Clock = std::chrono::steady_clock;

const char* const kRungs[] = {"plain",  "law",    "pair",    "narrow",   "dispatch",
                              "finish", "engine", "guard",   "autostep", "energy",
                              "bands",  "robin",  "threads2"};

struct Options {
    int n = 0;
    int64_t steps = 0;
    int64_t warmup = 300;
    std::string state_path;
    std::vector<std::string> rungs;
    bool memory = false;
};

[[noreturn]] void usage(const char* why) {
    std::fprintf(stderr,
                 "error: %s\nusage: talus_bench_ladder N STEPS --state FILE [--warmup W] "
                 "[--rung NAME]... [--memory] (rungs:",
                 why);
    for (const char* r : kRungs) std::fprintf(stderr, " %s", r);
    std::fprintf(stderr, ")\n");
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
        else if (a == "--warmup")
            o.warmup = std::atoll(value().c_str());
        else if (a == "--rung")
            o.rungs.push_back(value());
        else if (a == "--memory")
            o.memory = true;
        else if (a.rfind("--", 0) == 0)
            usage(("unknown option " + a).c_str());
        else
            pos.push_back(a);
    }
    if (pos.size() != 2) usage("need N and STEPS");
    o.n = std::atoi(pos[0].c_str());
    o.steps = std::atoll(pos[1].c_str());
    if (o.n < 1 || o.steps < 1 || o.warmup < 0) usage("N, STEPS >= 1, W >= 0");
    if (o.state_path.empty()) usage("--state FILE (scripts/bench/dense_pack.sh makes it)");
    if (o.rungs.empty()) o.rungs.assign(std::begin(kRungs), std::end(kRungs));
    for (const std::string& r : o.rungs) {
        bool known = false;
        for (const char* k : kRungs) known = known || r == k;
        if (!known) usage(("unknown rung " + r).c_str());
    }
    return o;
}

// ---------------------------------------------------------------- the plain rungs' own parts

/// The ball update of the plain rungs: leapfrog with the step's window, no damping (what the
/// engine's plain law of motion does).
void moveBallsPlain(World& world, const StepContext& step) {
    auto& b = world.bodies.balls;
    const Vec2 g = world.settings.gravity;
    for (std::size_t s = 0; s < b.size(); ++s) {
        const Vec2 v = b.vel[s] + (b.force[s] * b.inv_mass[s] + g) * step.window;
        const double om = b.spin[s] + b.moment[s] * b.inv_inertia[s] * step.window;
        b.vel[s] = v;
        b.spin[s] = om;
        b.pos[s] += v * step.dt;
        b.angle[s] += om * step.dt;
    }
    world.clock.time += step.dt;
    ++world.clock.step;
}

void zeroForces(World& world) {
    auto& b = world.bodies.balls;
    std::fill(b.force.begin(), b.force.end(), Vec2::Zero());
    std::fill(b.moment.begin(), b.moment.end(), 0.0);
}

/// Ball (c, r) against segment a-b: the closest point, no chain rule.
bool plainSegment(const Vec2& c, double r, const Vec2& a, const Vec2& b, Vec2& normal,
                  double& overlap) {
    const Vec2 ab = b - a;
    const double t = std::clamp((c - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    const Vec2 d = a + t * ab - c;
    const double dist2 = d.squaredNorm();
    if (dist2 >= r * r) return false;
    const double dist = std::sqrt(dist2);
    normal = d / dist;
    overlap = r - dist;
    return true;
}

/// The pair list as index arrays (end 2 a segment when kWallBit is set) and, per pair, the
/// textbook law's shear force and dashpot coefficient, or the contact's kernel row.
struct PlainPairs {
    std::vector<uint32_t> end1, end2;
    std::vector<double> shear, damping;
    std::vector<double*> row;  // the contact's kernel row (the law rung), else nullptr
    double kn = 0.0, ks = 0.0, fric = 0.0;
};

PlainPairs plainPairs(World& world, const DensePackDef& def) {
    PlainPairs pp;
    const auto& b = world.bodies.balls;
    pp.kn = def.kn;
    pp.ks = def.ks_ratio * def.kn;
    pp.fric = def.fric;
    const double beta = dampingRatioForRestitution(def.restitution, def.dp_mode % 2 == 1);
    for (const Pair& p : world.contacts.pairs) {
        pp.end1.push_back(p.end1);
        pp.end2.push_back(p.wall ? (p.end2 | kWallBit) : p.end2);
        pp.shear.push_back(p.s_force);
        const double m1 = b.mass[p.end1];
        const double me = p.wall ? m1 : m1 * b.mass[p.end2] / (m1 + b.mass[p.end2]);
        pp.damping.push_back(2.0 * beta * std::sqrt(me * pp.kn));
        Rule& rule = world.contacts.ruleOf(p);
        pp.row.push_back(p.lane != kNoLane ? rule.lanes->row(p.lane) : nullptr);
    }
    return pp;
}

/// The geometry the plain rungs take: ball-ball by the centre line, ball-segment by the closest
/// point; normal from end 1 to end 2, the contact point's relative velocity.
struct PlainContact {
    Vec2 n;
    double overlap;
    double arm1, arm2;  // from each centre to the contact point, along the normal
    Vec2 vrel;
};

inline bool plainGeometry(const World& world, uint32_t i, uint32_t j, PlainContact& c) {
    const auto& b = world.bodies.balls;
    const Vec2 x1 = b.pos[i];
    const double r1 = b.radius[i];
    if (!(j & kWallBit)) {
        const Vec2 d = b.pos[j] - x1;
        const double rs = r1 + b.radius[j];
        const double d2 = d.squaredNorm();
        if (d2 >= rs * rs) return false;
        const double dist = std::sqrt(d2);
        c.n = d / dist;
        c.overlap = rs - dist;
        c.arm1 = r1 - 0.5 * c.overlap;
        c.arm2 = b.radius[j] - 0.5 * c.overlap;
        const Vec2 t = perp(c.n);
        c.vrel = (b.vel[j] - b.spin[j] * c.arm2 * t) - (b.vel[i] + b.spin[i] * c.arm1 * t);
        return true;
    }
    const Segment& s = world.bodies.segments[j & ~kWallBit];
    if (!plainSegment(x1, r1, world.bodies.vertices[s.a], world.bodies.vertices[s.b], c.n,
                      c.overlap))
        return false;
    c.arm1 = r1 - 0.5 * c.overlap;
    c.arm2 = 0.0;
    c.vrel = -(b.vel[i] + b.spin[i] * c.arm1 * perp(c.n));
    return true;
}

/// Forces f on end 2 and -f on end 1 at the contact point.
inline void plainApply(World& world, uint32_t i, uint32_t j, const PlainContact& c, double fn,
                       double fs, double moment) {
    auto& b = world.bodies.balls;
    const Vec2 t = perp(c.n);
    const Vec2 f = fn * c.n + fs * t;
    b.force[i] -= f;
    b.moment[i] -= c.arm1 * fs + moment;
    if (!(j & kWallBit)) {
        b.force[j] += f;
        b.moment[j] += moment - c.arm2 * fs;  // (the arm points against the normal)
    }
}

/// The textbook law of pair k, its shear force in `shear`.
inline void textbookLaw(const PlainPairs& pp, std::size_t k, const PlainContact& c, double dt,
                        double& fn, double& shear) {
    const double spring = pp.kn * c.overlap;
    fn = spring - pp.damping[k] * c.vrel.dot(c.n);
    double fs = shear - pp.ks * c.vrel.dot(perp(c.n)) * dt;
    const double cap = pp.fric * std::max(spring, 0.0);
    if (std::fabs(fs) > cap) fs = std::copysign(cap, fs);
    shear = fs;
}

/// plain: the textbook law.
void stepPlain(World& world, PlainPairs& pp, const StepContext& step) {
    zeroForces(world);
    const double dt = step.dt;
    for (std::size_t k = 0; k < pp.end1.size(); ++k) {
        const uint32_t i = pp.end1[k], j = pp.end2[k];
        PlainContact c;
        if (!plainGeometry(world, i, j, c)) {
            pp.shear[k] = 0.0;
            continue;
        }
        double fn;
        textbookLaw(pp, k, c, dt, fn, pp.shear[k]);
        plainApply(world, i, j, c, fn, pp.shear[k], 0.0);
    }
    moveBallsPlain(world, step);
}

/// The law's block for a contact's kernel row, as the host fills it.
inline KernelFd plainBlock(const StepContext& step, double time, uint32_t flags, double overlap,
                           double u_dot_n, double u_dot_s, double t_dot_rel, double fn, double fs,
                           double m) {
    KernelFd kf;
    kf.flags = flags;
    kf.tdel = step.dt;
    kf.time = time;
    kf.u_n = overlap;
    kf.u_dot_n = u_dot_n;
    kf.u_dot_s = u_dot_s;
    kf.t_dot_rel = t_dot_rel;
    kf.du_n = u_dot_n * step.dt;
    kf.du_s = u_dot_s * step.dt;
    kf.dtheta = t_dot_rel * step.dt;
    kf.n_force = fn;
    kf.s_force = fs;
    kf.moment = m;
    return kf;
}

/// law: the engine's linear law on the contacts' rows (the textbook law where a pair has none).
void stepLaw(World& world, PlainPairs& pp, const StepContext& step) {
    zeroForces(world);
    const double dt = step.dt;
    const auto& b = world.bodies.balls;
    for (std::size_t k = 0; k < pp.end1.size(); ++k) {
        const uint32_t i = pp.end1[k], j = pp.end2[k];
        PlainContact c;
        if (!plainGeometry(world, i, j, c)) {
            pp.shear[k] = 0.0;
            continue;
        }
        const double un_dot = -c.vrel.dot(c.n);
        const double us_dot = c.vrel.dot(perp(c.n));
        if (double* row = pp.row[k]) {
            const double t_dot = ((j & kWallBit) ? 0.0 : b.spin[j]) - b.spin[i];
            KernelFd kf = plainBlock(step, world.clock.time, 0u, c.overlap, un_dot, us_dot, t_dot,
                                     0.0, pp.shear[k], 0.0);
            kf.mass_eff = row[sdk::LinearLaw::kLaneMassEff];
            if (sdk::LinearLaw::linearLaneStep(row, kf)) {
                pp.shear[k] = kf.s_force;
                plainApply(world, i, j, c, kf.n_force, kf.s_force, kf.moment);
            }
            continue;
        }
        double fn;
        textbookLaw(pp, k, c, dt, fn, pp.shear[k]);
        plainApply(world, i, j, c, fn, pp.shear[k], 0.0);
    }
    moveBallsPlain(world, step);
}

/// pair: the same over the engine's pair records and rules.
void stepPair(World& world, const PlainPairs& pp, const StepContext& step) {
    zeroForces(world);
    const double dt = step.dt;
    const auto& b = world.bodies.balls;
    auto& rules = world.contacts.rules;
    for (std::size_t k = 0; k < world.contacts.pairs.size(); ++k) {
        Pair& p = world.contacts.pairs[k];
        const Rule& rule = *rules[p.rule];
        const uint32_t j = p.wall ? (p.end2 | kWallBit) : p.end2;
        PlainContact c;
        if (!plainGeometry(world, p.end1, j, c) || c.overlap <= -rule.activity) {
            p.s_force = 0.0;
            continue;
        }
        const double un_dot = -c.vrel.dot(c.n);
        const double us_dot = c.vrel.dot(perp(c.n));
        if (p.lane != kNoLane) {
            double* row = rule.lanes->row(p.lane);
            const double t_dot = (p.wall ? 0.0 : b.spin[p.end2]) - b.spin[p.end1];
            KernelFd kf = plainBlock(step, world.clock.time, 0u, c.overlap, un_dot, us_dot, t_dot,
                                     p.n_force, p.s_force, p.moment);
            kf.mass_eff = row[sdk::LinearLaw::kLaneMassEff];
            if (sdk::LinearLaw::linearLaneStep(row, kf)) {
                p.n_force = kf.n_force, p.s_force = kf.s_force, p.moment = kf.moment;
                plainApply(world, p.end1, j, c, kf.n_force, kf.s_force, kf.moment);
            }
            continue;
        }
        textbookLaw(pp, k, c, dt, p.n_force, p.s_force);
        plainApply(world, p.end1, j, c, p.n_force, p.s_force, 0.0);
    }
    moveBallsPlain(world, step);
}

/// Forces from a law's output onto the ends at the contact point (pass 3's arithmetic).
inline void applyAt(World& world, const Pair& p, const PairEntry& e, double fn, double fs,
                    double m) {
    auto& b = world.bodies.balls;
    const ContactGeometry& g = e.g;
    const Vec2 f = fn * g.normal + fs * perp(g.normal);
    b.force[p.end1] -= f;
    b.moment[p.end1] -= cross(g.point - b.pos[p.end1], f) + m;
    if (!p.wall) {
        b.force[p.end2] += f;
        b.moment[p.end2] += cross(g.point - e.x2, f) + m;
    }
}

/// narrow and dispatch: the engine's pass 1, then the law on the row: the SDK's step called
/// directly (narrow), or the engine's law pass for a contact on a row (dispatch: pass_law.hpp's
/// kernelLaw, the runner the scene's loop is compiled for, FDlaw where the kernel declines).
template <bool kDispatch>
void stepNarrow(World& world, PlainPairs& pp, const StepContext& step) {
    using Off = LoopFeatures<false, false, false>;
    zeroForces(world);
    FdBlock fd_template = world.contacts.fd_template;
    fd_template.tdel = step.dt;
    fd_template.time = world.clock.time;
    fd_template.flags = 0;
    prepareRuleRows(world);
    const ForceView v = forceView(world, step, fd_template, 1, false);
    PairEntry e;
    ForceThreadPart part;
    part.fd = fd_template;
    for (std::size_t i = 0; i < v.pairs.size(); ++i) {
        Pair& p = v.pairs[i];
        const PairStep ps = geometryPass<Off>(v, i, e, nullptr);
        if (ps == PairStep::Apart || ps == PairStep::Elsewhere) continue;
        if (p.lane == kNoLane) {
            const PlainContact c{e.g.normal, e.g.overlap, 0.0, 0.0, e.vrel};
            double fn = 0.0;
            if (c.overlap > 0.0) textbookLaw(pp, i, c, step.dt, fn, p.s_force);
            applyAt(world, p, e, fn, p.s_force, 0.0);
            continue;
        }
        KernelFd kf;
        bool done;
        if constexpr (kDispatch) {
            done = kernelLaw<Off, Runner::Linear>(v, i, e, kf, part.fd, part, true);
        } else {
            double* row = v.rule(p).lanes->row(p.lane);
            kf = kernelBlock(v, p, e);
            kf.mass_eff = row[sdk::LinearLaw::kLaneMassEff];
            done = sdk::LinearLaw::linearLaneStep(row, kf);
        }
        if (!done) continue;
        applyAt(world, p, e, kf.n_force, kf.s_force, kf.moment);
        p.n_force = kf.n_force, p.s_force = kf.s_force, p.moment = kf.moment;
    }
    moveBallsPlain(world, step);
}

/// finish: the engine's force loop, every feature off; the plain ball update.
void stepFinish(World& world, const StepContext& step) {
    forceDisplacement(world, step);
    moveBallsPlain(world, step);
}

// ---------------------------------------------------------------- memory

/// The process's peak resident memory so far [bytes].
std::size_t peakResident() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<std::size_t>(u.ru_maxrss) * 1024;
}

template <class V>
std::size_t held(const V& v) {
    return v.capacity() * sizeof(typename V::value_type);
}

/// The bytes per disk each store of the world holds, from its vectors' capacities.
void printMemory(const World& world, std::size_t peak_before) {
    const auto& b = world.bodies.balls;
    const auto& cs = world.contacts;
    const double n = static_cast<double>(b.size());
    const auto line = [&](const char* store, double bytes) {
        std::printf("MEMORY store=%s bytes_per_disk=%.1f\n", store, bytes / n);
    };
    line("pairs (Pair)", held(cs.pairs));
    line("pairs (PairCold)", held(cs.cold));
    line("pairs (PairStored)", held(cs.stored));
    // A node per key (the key, the index, the next pointer: 24 bytes, 32 as allocated) and a
    // bucket array.
    line("pairs (key index)", cs.key_index.size() * 32.0 + cs.key_index.bucket_count() * 8.0);
    double pools = 0.0, rows = 0.0;
    for (const auto& r : cs.rules) {
        if (r->pool) pools += r->pool->bytes();
        if (r->lanes) rows += r->lanes->bytes();
    }
    line("guard watches (young contacts)", held(cs.watches) + held(cs.free_watches));
    line("model objects (pools)", pools);
    line("kernel rows", rows);
    const double balls = held(b.pos) + held(b.vel) + held(b.force) + held(b.fapp) + held(b.angle) +
                         held(b.spin) + held(b.moment) + held(b.mapp) + held(b.radius) +
                         held(b.mass) + held(b.inv_mass) + held(b.inertia) + held(b.inv_inertia) +
                         held(b.density) + held(b.fixity) + held(b.handle) + held(b.proxy) +
                         held(b.fat) + held(b.groups) + held(b.kn) + held(b.ks) + held(b.fric) +
                         held(b.k_tran) + held(b.k_rot) + held(b.clump) +
                         held(world.bodies.slot_of) + held(world.bodies.generation);
    line("balls", balls);
    const std::size_t peak = peakResident();
    std::printf("MEMORY store=peak resident over the empty process bytes_per_disk=%.1f\n",
                static_cast<double>(peak - peak_before) / n);
}

// ---------------------------------------------------------------- a rung's run

struct Setup {
    bool guard = false, automatic = false, energy = false;
    int groups = 0;  // 8 ...
    bool bands = false;
    int threads = 1;
};

Setup setupOf(const std::string& rung) {
    Setup s;
    if (rung == "guard" || rung == "autostep" || rung == "energy" || rung == "bands" ||
        rung == "robin" || rung == "threads2")
        s.guard = true;
    s.automatic = rung == "autostep";
    s.energy = rung == "energy" || rung == "bands" || rung == "robin";
    if (rung == "bands" || rung == "robin") s.groups = 8, s.bands = rung == "bands";
    if (rung == "threads2") s.threads = 2;
    return s;
}

/// The balls into `count` groups: horizontal bands of equal width (bands), or round-robin in
/// creation order.
void assignGroups(Model& model, int count, bool bands, double width) {
    int k = 0;
    for (const BallId id : model.ballIds()) {
        int g = k++ % count;
        if (bands) {
            const double x = model.ballPos(id).x();
            g = std::clamp(static_cast<int>(x / width * count), 0, count - 1);
        }
        model.addBallGroup(id, "g" + std::to_string(g));
    }
}

void runRung(const Options& o, const PackState& st, const std::string& rung, bool memory) {
    const std::size_t peak_before = peakResident();
    Model model;
    const DensePack pack = buildDensePackFromState(model, st);
    model.setPlacementWarning(false);
    model.setSortInterval(Model::kSortAutoEvery);
    const Setup s = setupOf(rung);
    if (o.warmup > 0) model.cycle(o.warmup);
    model.guard() = s.guard ? GuardSettings{} : GuardSettings::allOff();
    model.timestep().automatic = s.automatic;
    if (s.groups > 0) assignGroups(model, s.groups, s.bands, pack.width);
    model.setEnergyTracing(s.energy);
    model.setThreads(s.threads);
    model.profile().enabled = false;
    World& world = worldOf(model);
    if (memory) printMemory(world, peak_before);
    const std::size_t npairs = world.contacts.pairs.size();
    std::size_t contacts = 0;
    for (const Pair& p : world.contacts.pairs) contacts += p.active;

    const bool own = rung == "plain" || rung == "law" || rung == "pair" || rung == "narrow" ||
                     rung == "dispatch" || rung == "finish";
    PlainPairs pp;
    if (own) pp = plainPairs(world, st.def);
    if (own) {
        // The engine's step settings as a cycle would take them (fixed step, guard off).
        prepareRun(world);
        computeTimestep(world);
    }
    const StepContext step = beginStep(world);
    const auto t0 = Clock::now();
    TALUS_LADDER_START();
    if (!own) {
        model.cycle(o.steps);
    } else {
        for (int64_t k = 0; k < o.steps; ++k) {
            if (rung == "plain")
                stepPlain(world, pp, step);
            else if (rung == "law")
                stepLaw(world, pp, step);
            else if (rung == "pair")
                stepPair(world, pp, step);
            else if (rung == "narrow")
                stepNarrow<false>(world, pp, step);
            else if (rung == "dispatch")
                stepNarrow<true>(world, pp, step);
            else
                stepFinish(world, step);
        }
    }
    TALUS_LADDER_STOP();
    const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
    const double n = static_cast<double>(model.ballCount());
    std::printf(
        "RESULT rung=%s n=%d steps=%lld warmup=%lld pairs=%zu contacts=%zu "
        "ns_per_particle_step=%.3f ke_end=%.4g\n",
        rung.c_str(), o.n, static_cast<long long>(o.steps), static_cast<long long>(o.warmup),
        npairs, contacts, 1e9 * wall / (static_cast<double>(o.steps) * n),
        meanKineticEnergy(model));
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    try {
        const PackState st = loadPackState(o.state_path);
        if (static_cast<int>(st.balls.size()) != o.n)
            throw InputError("the state holds " + std::to_string(st.balls.size()) + " disks, not " +
                             std::to_string(o.n));
        bool memory = o.memory;
        for (const std::string& rung : o.rungs) {
            runRung(o, st, rung, memory);
            memory = false;
        }
    } catch (const talus::Error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
