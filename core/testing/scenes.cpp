// SPDX-License-Identifier: MIT
//
// Scene builders (talus/scenes.hpp). They use only the public Model API, so they do not depend
// on the engine's internal layout, which changes as the hot loop is optimised.
#include "talus/scenes.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include "talus/errors.hpp"
#include "talus/model.hpp"
#include "talus/splitmix.hpp"

namespace talus {

namespace {

/// Packing fraction a polydisperse dense random pack reaches in 2D (frictional disks settle
/// between about 0.78 and 0.84); used only to estimate how far the lattice falls.
constexpr double kDensePacking = 0.80;

struct Lattice {
    double spacing = 0.0;  // nearest-neighbour distance a
    double pitch = 0.0;    // row pitch a sqrt(3)/2
    int cols = 0, rows = 0;
    double width = 0.0, height = 0.0;
};

Lattice latticeFor(const DensePackDef& d) {
    Lattice l;
    l.spacing = 2.0 * d.r_max * (1.0 + d.lattice_gap);
    l.pitch = l.spacing * std::sqrt(3.0) / 2.0;
    // cols * a / (rows * pitch) = aspect with cols * rows ~ n.
    l.cols =
        std::max(1, static_cast<int>(std::ceil(std::sqrt(d.n * d.aspect * l.pitch / l.spacing))));
    l.rows = (d.n + l.cols - 1) / l.cols;
    // Odd rows are shifted by half a spacing, so the box is half a spacing wider.
    l.width = l.cols * l.spacing + (l.rows > 1 ? 0.5 * l.spacing : 0.0);
    l.height = (l.rows - 1) * l.pitch + l.spacing;
    return l;
}

void checkDef(const DensePackDef& d) {
    auto positive = [](double v) { return v > 0.0 && std::isfinite(v); };
    if (d.n < 1) throw InputError("dense pack: n must be >= 1");
    if (!positive(d.r_min) || !(d.r_max >= d.r_min) || !std::isfinite(d.r_max))
        throw InputError("dense pack: need 0 < r_min <= r_max");
    if (!positive(d.density) || !positive(d.kn) || !positive(d.timestep) || !positive(d.aspect))
        throw InputError("dense pack: density, kn, timestep and aspect must be > 0");
    if (!(d.ks_ratio >= 0.0) || !(d.fric >= 0.0) || !(d.gravity >= 0.0))
        throw InputError("dense pack: ks_ratio, fric and gravity must be >= 0");
    if (!(d.restitution > 0.0 && d.restitution <= 1.0))
        throw InputError("dense pack: restitution must be in (0, 1]");
    if (!(d.lattice_gap > 0.0)) throw InputError("dense pack: lattice_gap must be > 0");
    if (d.dp_mode < 0 || d.dp_mode > 3) throw InputError("dense pack: dp_mode must be 0..3");
}

/// Walls, contact model, gravity and step: everything but the disks.
DensePack setUpBox(Model& model, const DensePackDef& d, double width, double height) {
    if (model.ballCount() != 0 || model.wallCount() != 0)
        throw InputError("dense pack: the model must be empty");
    DensePack pack;
    pack.width = width;
    pack.height = height;
    // Four separate walls, so that a test can read the floor's reaction alone; they meet at the
    // corners without sharing vertices, and a disk inside the box only ever sees their faces.
    auto wall = [&](Vec2 a, Vec2 b) {
        WallDef w;
        w.points = {a, b};
        return model.createWall(w);
    };
    pack.floor = wall(Vec2(0.0, 0.0), Vec2(width, 0.0));
    pack.right = wall(Vec2(width, 0.0), Vec2(width, height));
    pack.top = wall(Vec2(width, height), Vec2(0.0, height));
    pack.left = wall(Vec2(0.0, height), Vec2(0.0, 0.0));

    const double beta = dampingRatioForRestitution(d.restitution, d.dp_mode == 1 || d.dp_mode == 3);
    model.setDefaultContactModel("linear", {{"kn", d.kn},
                                            {"ks", d.ks_ratio * d.kn},
                                            {"fric", d.fric},
                                            {"dp_nratio", beta},
                                            {"dp_sratio", 0.0},
                                            {"dp_mode", static_cast<double>(d.dp_mode)}});
    model.gravity() = Vec2(0.0, -d.gravity);
    model.timestep().automatic = false;
    model.timestep().fixed = d.timestep;
    return pack;
}

BallId addDisk(Model& model, const DensePackDef& d, const PackBall& b) {
    BallDef bd;
    bd.radius = b.radius;
    bd.density = d.density;
    bd.pos = Vec2(b.x, b.y);
    bd.vel = Vec2(b.vx, b.vy);
    bd.spin = b.spin;
    return model.createBall(bd);
}

}  // namespace

double dampingRatioForRestitution(double e, bool no_tension) {
    if (!(e > 0.0 && e <= 1.0)) throw InputError("restitution must be in (0, 1]");
    const double l = std::log(e);
    if (!no_tension) return -l / std::sqrt(M_PI * M_PI + l * l);
    // e = exp(-beta (pi - 2 asin beta) / sqrt(1 - beta^2)) has no closed inverse; e falls
    // monotonically with beta on [0, 1), towards exp(-2) as beta -> 1, so bisect.
    if (e <= std::exp(-2.0))
        throw InputError(
            "a no-tension dashpot cannot give a restitution below exp(-2) = 0.135 "
            "(damping ratio < 1)");
    double lo = 0.0, hi = 1.0 - 1e-12;
    for (int i = 0; i < 100; ++i) {
        const double mid = 0.5 * (lo + hi);
        const double em =
            std::exp(-mid * (M_PI - 2.0 * std::asin(mid)) / std::sqrt(1.0 - mid * mid));
        (em > e ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

DensePack buildDensePack(Model& model, const DensePackDef& d) {
    checkDef(d);
    const Lattice lat = latticeFor(d);
    SplitMix64 rng(d.seed);

    // Sites in lattice order; the top row is spread evenly when it is not full.
    std::vector<PackBall> balls;
    balls.reserve(static_cast<std::size_t>(d.n));
    const int last_row_count = d.n - lat.cols * (lat.rows - 1);
    for (int j = 0; j < lat.rows; ++j) {
        const int count = j + 1 < lat.rows ? lat.cols : last_row_count;
        for (int k = 0; k < count; ++k) {
            const int i = j + 1 < lat.rows ? k : static_cast<int>(int64_t(k) * lat.cols / count);
            PackBall b{};
            b.radius = d.r_min + (d.r_max - d.r_min) * rng.uniform();
            // Each disk stays inside the circle of radius a/2 around its site, and sites are a
            // apart, so no two disks overlap (0.999 keeps a sliver of gap at worst).
            const double reach = 0.999 * (0.5 * lat.spacing - b.radius);
            double dx, dy;
            do {
                dx = (2.0 * rng.uniform() - 1.0) * reach;
                dy = (2.0 * rng.uniform() - 1.0) * reach;
            } while (dx * dx + dy * dy > reach * reach);
            b.x = 0.5 * lat.spacing + i * lat.spacing + ((j & 1) ? 0.5 * lat.spacing : 0.0) + dx;
            b.y = 0.5 * lat.spacing + j * lat.pitch + dy;
            balls.push_back(b);
        }
    }
    if (d.shuffle)  // Fisher-Yates
        for (std::size_t i = balls.size(); i > 1; --i) std::swap(balls[i - 1], balls[rng.below(i)]);

    DensePack pack = setUpBox(model, d, lat.width, lat.height);
    pack.balls.reserve(balls.size());
    for (const PackBall& b : balls) {
        pack.balls.push_back(addDisk(model, d, b));
        pack.weight += model.ballMass(pack.balls.back()) * d.gravity;
    }
    return pack;
}

double meanKineticEnergy(const Model& model) {
    const std::vector<BallId> ids = model.ballIds();
    if (ids.empty()) return 0.0;
    double ke = 0.0;
    for (BallId id : ids) {
        const double w = model.ballSpin(id);
        ke += 0.5 * (model.ballMass(id) * model.ballVel(id).squaredNorm() +
                     model.ballInertia(id) * w * w);
    }
    return ke / static_cast<double>(ids.size());
}

SettleResult settleDensePack(Model& model, const DensePack& pack, const DensePackDef& d,
                             const SettleSettings& s) {
    if (s.check_every < 1) throw InputError("settle: check_every must be >= 1");
    SettleResult r;
    double mean_mass = 0.0, mean_radius = 0.0;
    for (BallId id : pack.balls)
        mean_mass += model.ballMass(id), mean_radius += model.ballRadius(id);
    const double nb = std::max<double>(1.0, static_cast<double>(pack.balls.size()));
    mean_mass /= nb;
    mean_radius /= nb;
    r.ke_limit = s.ke_fraction * mean_mass * d.gravity * mean_radius;

    // Phase 1, undamped fall. It ends once the kinetic energy has peaked and fallen to a tenth
    // of its peak: the pack has landed and only vibrations are left. The lattice compacts from
    // its own packing fraction to about kDensePacking, so the top falls the difference and
    // needs sqrt(2 drop / g); twice that caps the phase in case the rule never fires.
    const Lattice lat = latticeFor(d);
    const double r2 = (d.r_min * d.r_min + d.r_min * d.r_max + d.r_max * d.r_max) / 3.0;
    const double phi_lattice = M_PI * r2 / (lat.spacing * lat.pitch);
    const double drop = std::max(0.0, (1.0 - phi_lattice / kDensePacking) * lat.height);
    const double fall_cap =
        d.gravity > 0.0 ? std::min(s.max_time, 2.0 * std::sqrt(2.0 * drop / d.gravity)) : 0.0;
    const double t0 = model.time();
    const double saved_damping = model.damping().local;
    // Settling is preparation, not a measurement: grazing impacts during the fall are short by
    // nature, and the guard would report each batch of them. Its settings come back after.
    const GuardSettings saved_guard = model.guard();
    model.guard() = GuardSettings::allOff();
    double peak = 0.0;
    while (model.time() - t0 < fall_cap) {
        model.cycle(s.check_every);
        const double ke = meanKineticEnergy(model);
        peak = std::max(peak, ke);
        if (ke < 0.1 * peak) break;
    }
    r.fall_time = model.time() - t0;

    // Phase 2, damped until (nearly) at rest.
    model.damping().local = s.local_damping;
    for (;;) {
        r.ke_per_ball = meanKineticEnergy(model);
        if (r.ke_per_ball < r.ke_limit) {
            r.converged = true;
            break;
        }
        if (model.time() - t0 >= s.max_time) break;
        model.cycle(s.check_every);
    }
    model.damping().local = saved_damping;
    model.guard() = saved_guard;
    r.time = model.time() - t0;
    r.steps = static_cast<int64_t>(std::llround(r.time / d.timestep));
    return r;
}

// ---------------------------------------------------------------------- saved state

PackState capturePackState(const Model& model, const DensePack& pack, const DensePackDef& def) {
    PackState st;
    st.def = def;
    st.width = pack.width;
    st.height = pack.height;
    st.balls.reserve(pack.balls.size());
    for (BallId id : pack.balls) {
        const Vec2 x = model.ballPos(id), v = model.ballVel(id);
        st.balls.push_back(
            PackBall{model.ballRadius(id), x.x(), x.y(), v.x(), v.y(), model.ballSpin(id)});
    }
    return st;
}

namespace {

constexpr const char* kStateMagic = "# talus dense-pack state 1";

struct FileCloser {
    void operator()(std::FILE* f) const {
        if (f) std::fclose(f);
    }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

File openFile(const std::string& path, const char* mode) {
    File f(std::fopen(path.c_str(), mode));
    if (!f)
        throw InputError(std::string("cannot open '") + path + "' for " +
                         (mode[0] == 'r' ? "reading" : "writing") + ": " + std::strerror(errno));
    return f;
}

}  // namespace

void savePackState(const PackState& st, const std::string& path) {
    File f = openFile(path, "w");
    const DensePackDef& d = st.def;
    std::FILE* o = f.get();
    std::fprintf(o, "%s\n", kStateMagic);
    std::fprintf(o, "n %d\nr_min %.17g\nr_max %.17g\ndensity %.17g\nkn %.17g\nks_ratio %.17g\n",
                 d.n, d.r_min, d.r_max, d.density, d.kn, d.ks_ratio);
    std::fprintf(o, "fric %.17g\nrestitution %.17g\ndp_mode %d\naspect %.17g\ngravity %.17g\n",
                 d.fric, d.restitution, d.dp_mode, d.aspect, d.gravity);
    std::fprintf(o, "timestep %.17g\nlattice_gap %.17g\nseed %llu\nshuffle %d\n", d.timestep,
                 d.lattice_gap, static_cast<unsigned long long>(d.seed), d.shuffle ? 1 : 0);
    std::fprintf(o, "width %.17g\nheight %.17g\nballs %zu\n", st.width, st.height, st.balls.size());
    std::fprintf(o, "# radius x y vx vy spin\n");
    for (const PackBall& b : st.balls)
        std::fprintf(o, "%.17g %.17g %.17g %.17g %.17g %.17g\n", b.radius, b.x, b.y, b.vx, b.vy,
                     b.spin);
    if (std::fflush(o) != 0 || std::ferror(o)) throw InputError("error writing '" + path + "'");
}

PackState loadPackState(const std::string& path) {
    File f = openFile(path, "r");
    std::FILE* in = f.get();
    auto bad = [&](const std::string& what) {
        return InputError("dense-pack state '" + path + "': " + what);
    };
    char line[256];
    if (!std::fgets(line, sizeof line, in) ||
        std::strncmp(line, kStateMagic, std::strlen(kStateMagic)) != 0)
        throw bad("not a dense-pack state file (first line)");
    PackState st;
    DensePackDef& d = st.def;
    std::size_t count = 0;
    auto key = [&](const char* name, const char* fmt, void* out) {
        char want[64];
        std::snprintf(want, sizeof want, " %s %s", name, fmt);
        if (std::fscanf(in, want, out) != 1) throw bad(std::string("expected '") + name + "'");
    };
    unsigned long long seed = 0;
    int shuffle = 0;
    key("n", "%d", &d.n);
    key("r_min", "%lf", &d.r_min);
    key("r_max", "%lf", &d.r_max);
    key("density", "%lf", &d.density);
    key("kn", "%lf", &d.kn);
    key("ks_ratio", "%lf", &d.ks_ratio);
    key("fric", "%lf", &d.fric);
    key("restitution", "%lf", &d.restitution);
    key("dp_mode", "%d", &d.dp_mode);
    key("aspect", "%lf", &d.aspect);
    key("gravity", "%lf", &d.gravity);
    key("timestep", "%lf", &d.timestep);
    key("lattice_gap", "%lf", &d.lattice_gap);
    key("seed", "%llu", &seed);
    key("shuffle", "%d", &shuffle);
    key("width", "%lf", &st.width);
    key("height", "%lf", &st.height);
    key("balls", "%zu", &count);
    d.seed = seed;
    d.shuffle = shuffle != 0;
    if (count != static_cast<std::size_t>(d.n)) throw bad("ball count differs from n");
    checkDef(d);
    if (std::fscanf(in, " ") != 0 || !std::fgets(line, sizeof line, in) ||
        std::strncmp(line, "# radius", 8) != 0)
        throw bad("missing the column line");
    st.balls.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        PackBall& b = st.balls[i];
        if (std::fscanf(in, "%lf %lf %lf %lf %lf %lf", &b.radius, &b.x, &b.y, &b.vx, &b.vy,
                        &b.spin) != 6)
            throw bad("ball line " + std::to_string(i + 1) + " is malformed or missing");
    }
    return st;
}

bool sameScene(const DensePackDef& a, const DensePackDef& b) {
    return a.n == b.n && a.r_min == b.r_min && a.r_max == b.r_max && a.density == b.density &&
           a.kn == b.kn && a.ks_ratio == b.ks_ratio && a.fric == b.fric &&
           a.restitution == b.restitution && a.dp_mode == b.dp_mode && a.aspect == b.aspect &&
           a.gravity == b.gravity && a.timestep == b.timestep && a.lattice_gap == b.lattice_gap &&
           a.seed == b.seed;
}

DensePack buildDensePackFromState(Model& model, const PackState& st) {
    checkDef(st.def);
    DensePack pack = setUpBox(model, st.def, st.width, st.height);
    pack.balls.reserve(st.balls.size());
    for (const PackBall& b : st.balls) {
        pack.balls.push_back(addDisk(model, st.def, b));
        pack.weight += model.ballMass(pack.balls.back()) * st.def.gravity;
    }
    return pack;
}

void writeLammpsData(const PackState& st, const std::string& path) {
    File f = openFile(path, "w");
    std::FILE* o = f.get();
    const DensePackDef& d = st.def;
    std::fprintf(
        o,
        "LAMMPS data file: Talus dense pack, n %d, seed %llu (units si; the density column "
        "needs 'set ... density/disc' for disk masses)\n\n",
        d.n, static_cast<unsigned long long>(d.seed));
    std::fprintf(o, "%zu atoms\n1 atom types\n\n", st.balls.size());
    std::fprintf(o, "0 %.17g xlo xhi\n0 %.17g ylo yhi\n%.17g %.17g zlo zhi\n\n", st.width,
                 st.height, -d.r_max, d.r_max);
    std::fprintf(o, "Atoms # sphere\n\n");
    for (std::size_t i = 0; i < st.balls.size(); ++i) {
        const PackBall& b = st.balls[i];
        std::fprintf(o, "%zu 1 %.17g %.17g %.17g %.17g 0\n", i + 1, 2.0 * b.radius, d.density, b.x,
                     b.y);
    }
    std::fprintf(o, "\nVelocities\n\n");
    for (std::size_t i = 0; i < st.balls.size(); ++i) {
        const PackBall& b = st.balls[i];
        std::fprintf(o, "%zu %.17g %.17g 0 0 0 %.17g\n", i + 1, b.vx, b.vy, b.spin);
    }
    if (std::fflush(o) != 0 || std::ferror(o)) throw InputError("error writing '" + path + "'");
}

}  // namespace talus
