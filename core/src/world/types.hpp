// SPDX-License-Identifier: MIT
//
// The world's record types: a broadphase pair (hot Pair, cold PairCold), a contact-model rule,
// wall segments and chains, the balls' arrays, a clump, the time-step limits. Not installed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "talus/clump_mass.hpp"
#include "talus/model.hpp"
#include "talus/plugin_registry.hpp"
#include "world/contact_lanes.hpp"

namespace talus {

/// An OpenMP directive where the build has OpenMP (core/CMakeLists.txt, TALUS_OPENMP), else
/// nothing: TALUS_OMP(omp parallel for ...) in place of the #pragma.
#ifdef TALUS_HAVE_OPENMP
#define TALUS_OMP(directive) _Pragma(#directive)
#else
#define TALUS_OMP(directive)
#endif

/// Limits gathered by the force loop for the next automatic step (timestep.cpp): each the
/// smallest over the pairs, the lowest pair index on a tie (`*_pair`, not saved), so that
/// threads' partial limits merge to what one thread finds in pair order.
struct StepLimits {
    double stability = std::numeric_limits<double>::infinity();
    double resolution = std::numeric_limits<double>::infinity();
    double approach = std::numeric_limits<double>::infinity();
    uint64_t stability_key = 0, resolution_key = 0, approach_key = 0;
    uint32_t stability_pair = UINT32_MAX, resolution_pair = UINT32_MAX, approach_pair = UINT32_MAX;
    void merge(const StepLimits& o);
};

/// Steps in contact the guard follows a contact for (docs/physics/guard.md).
constexpr uint32_t kGuardWatch = 400;

constexpr uint32_t kDeadSlot = 0xffffffffu;
constexpr uint32_t kNoWatch = 0xffffffffu;  // PairCold::watch of a contact the guard does not watch
constexpr uint32_t kNoClump = 0xffffffffu;  // BallArrays::clump of a free ball

constexpr uint32_t kWallBit = 0x80000000u;  // in ContactKey: end 2 is a wall segment

/// Fixed-size blocks for per-contact model objects (one pool per rule), so that a contact's
/// model is placed by Clone without a heap allocation of its own.
class ObjectPool {
public:
    explicit ObjectPool(std::size_t block_size);
    void* allocate();
    void release(void* p);
    std::size_t blockSize() const { return m_block; }
    /// The memory it holds [bytes] (its chunks and free list).
    std::size_t bytes() const {
        return m_chunks.size() * m_block * kPerChunk + m_free.capacity() * sizeof(void*);
    }
    static constexpr std::size_t kPerChunk = 256;  // objects per chunk

    /// Blocks held, counted in chunk order (free or not), and the k-th of them.
    std::size_t blockCount() const { return m_chunks.size() * kPerChunk; }
    void* block(std::size_t k) const {
        return m_chunks[k / kPerChunk].get() + (k % kPerChunk) * m_block;
    }
    /// The index (as block() counts) of each of the pool's blocks given.
    std::vector<uint32_t> blockIndices(const std::vector<const void*>& blocks) const;
    /// After the objects were moved to the first `used` blocks: the chunks beyond them freed, the
    /// rest of the last one free.
    void keepFirst(std::size_t used);

private:
    std::size_t m_block;
    std::vector<std::unique_ptr<unsigned char[]>> m_chunks;
    std::vector<void*> m_free;
};

/// An SDK law the host runs itself on a model's kernel rows (force/runners.hpp, the runner
/// table; docs/plugin-abi.md, "Kernels"); None: the model's FDlaw.
enum class Kernel : uint8_t { None, Linear, ContactBond };

/// A contact-model assignment: which model, with which properties, for which groups.
struct Rule {
    std::string model_name;
    const ModelFactory* factory = nullptr;
    /// How its contacts' law runs, chosen once when the rule is made (kernelOf): a kernel on
    /// their rows, or the model's FDlaw.
    Kernel kernel = Kernel::None;
    PluginRegistry::PrototypePtr prototype;
    int group_a = -1;  // -1 = any
    int group_b = -1;
    int specificity = 0;  // number of groups named
    int order = 0;        // later rules win ties
    double activity = 0.0;
    std::unique_ptr<ObjectPool> pool;
    /// The state of its contacts that its kernel runs, one row each in the model's lane layout
    /// (made at the first; none without a kernel).
    std::unique_ptr<LaneTable> lanes;
    bool warned_no_stiffness = false;          // activate warns once per rule
    bool warned_negative_dissipation = false;  // the force loop warns once per rule
    /// Made by m:bond for the objects it installs (api/bonds.cpp): never matched by ruleFor;
    /// a pair whose contact ends goes back to the ordinary rules (resetPair).
    bool installed = false;
};

struct Segment {
    uint32_t wall;      // index into m_walls
    uint32_t a, b;      // vertex indices into m_vertices
    int32_t prev = -1;  // neighbouring segment sharing vertex a (-1: none)
    int32_t next = -1;  // neighbouring segment sharing vertex b (-1: none)
    int32_t proxy = -1;
    Box fat;
};

struct WallData {
    uint32_t generation = 1;
    bool alive = true;
    bool closed = false;
    uint32_t first_segment = 0, segment_count = 0;
    uint32_t first_vertex = 0, vertex_count = 0;
    Vec2 vel{0.0, 0.0};
    double spin = 0.0;
    Vec2 center{0.0, 0.0};
    uint64_t groups = 0;
    double kn = kNotSet, ks = kNotSet, fric = kNotSet;
    Vec2 force{0.0, 0.0};  // force the balls exert on the wall, last step [N]
    double moment = 0.0;   // about `center` [N m]
    double knest = 0.0;    // sum of the contacts' knest, last step [N/m] (the servo's gain)
    bool has_servo = false;
    WallServoState servo;  // wall_servo.cpp (used when has_servo)
};

/// A broadphase candidate pair. Every pair owns a model object (cloned from its rule's
/// prototype, with the ends' properties) so that its stiffness and expected contact duration
/// are known before touch; the pair is a *contact* while `active`. On separation the object is
/// replaced by a fresh clone, so a new touch starts from a fresh state. A wall contact that runs
/// over a convex vertex of its chain moves, object and state, to the next segment's pair
/// (step/detection.cpp, "wall vertices").
///
/// The force loop streams through all pairs every step and is limited by memory traffic, so a
/// pair is split in two records of the same index: `Pair`, what the loop reads for every pair at
/// every step (48 bytes), and `PairCold`, what the law through FDlaw, the time step, the guard,
/// the queries and the bookkeeping need; the energy books' `PairStored` is a third. A contact
/// whose law the host runs itself (a kernel, force/kernels.hpp) keeps its model's state in its
/// rule's lanes and reads its cold record only while the guard watches it and with the automatic
/// step.
struct Pair {
    uint32_t end1 = 0;  // ball slot
    uint32_t end2 = 0;  // ball slot, or segment index when `wall`
    // The contact's row in its rule's lanes (contact_lanes.hpp): while it has one, that row
    // holds the model's state and the object is out of date (syncLane).
    uint32_t lane = kNoLane;
    uint16_t rule = 0;  // index into ContactStore::rules
    bool wall : 1;
    bool active : 1;
    bool sliding : 1;
    bool bonded : 1;
    bool loading : 1;  // guard: the overlap grew at the last step
    bool watched : 1;  // guard: within its first kGuardWatch steps in contact (PairCold::watch)
    ContactModel* model = nullptr;
    double n_force = 0.0, s_force = 0.0, moment = 0.0;  // the law's, of the last step

    Pair()
        : wall(false),
          active(false),
          sliding(false),
          bonded(false),
          loading(false),
          watched(false) {}
};
static_assert(sizeof(Pair) == 48,
              "Pair is 48 bytes: the force loop reads one per candidate pair per step "
              "(docs/architecture.md quotes it)");

struct PairCold {
    // The law through FDlaw (first cache line).
    double mass_eff = 0.0;
    double inv_mass_eff_s = 0.0;  // FdBlock::inv_mass_eff_s, with the radii as lever arms
    // Gap within which the contact is active [m], >= 0: its rule's before touch (the loop reads
    // it there), its object's while active (a bond formed at a gap).
    double activity = 0.0;
    double knest = 0.0, ksest = 0.0, krest = 0.0;  // the law's estimates, of the last step
    double duration = 0.0;  // expected contact duration from the model at touch [s]
    double overlap = 0.0;   // at the last step that noted it (the guard's watch, the estimates)
    uint64_t key = 0;
    uint32_t rules_version = 0;
    uint32_t watch = kNoWatch;  // its GuardWatch in ContactStore::watches while watched
};
static_assert(sizeof(PairCold) == 80, "PairCold is 80 bytes (docs/architecture.md quotes it)");

/// The guard's watch of a young contact (docs/physics/guard.md): what it needs of the contact's
/// first kGuardWatch steps in contact, kept only while they last (ContactStore::watches, named by
/// PairCold::watch and Pair::watched), so that a contact of a packing carries none of it.
struct GuardWatch {
    uint16_t steps = 0;  // steps with positive overlap in this life, up to kGuardWatch + 1
    uint16_t apart = 0;  // watched steps active without overlap, up to kGuardWatch + 1
    bool born_overlapped = false;        // first touched with more overlap than one step's approach
    double work = 0.0, work_peak = 0.0;  // energy the contact took in this life [J]
    // ... written at touch and at the deepest overlap (when the overlap stops growing).
    double overlap_max = 0.0;    // deepest overlap in this life [m]
    double force_at_max = 0.0;   // normal force there [N]
    double rate_at_max = 0.0;    // overlap rate just after it [m/s]
    double knest_at_max = 0.0;   // reported normal stiffness there [N/m]
    double dt_at_max = 0.0;      // step taken there [s]
    double approach_rate = 0.0;  // u_dot_n at touch [m/s]
    double closure = 0.0;        // overlap the step's motion could create at touch [m]
};
static_assert(sizeof(GuardWatch) == 80, "GuardWatch is 80 bytes (docs/architecture.md quotes it)");

/// Energy tracing: a pair's stored energies as its law last reported them [J], same index as
/// Pair. Written for every contact at every traced step, so kept apart from PairCold (16 bytes
/// here, in pair order, against a line of the cold record per contact and step).
struct PairStored {
    double strain = 0.0, bond = 0.0;
    double total() const { return strain + bond; }  // what the contact releases if it ends now
};

struct BallArrays {
    std::vector<Vec2> pos, vel, force, fapp;
    std::vector<double> angle, spin, moment, mapp;
    std::vector<double> radius, mass, inv_mass, inertia, inv_inertia, density;
    std::vector<uint8_t> fixity;
    std::vector<uint32_t> handle;  // slot -> handle index (1-based)
    std::vector<int32_t> proxy;    // broadphase proxy id
    std::vector<Box> fat;          // fat box as the broadphase holds it
    std::vector<uint64_t> groups;
    std::vector<double> kn, ks, fric;
    std::vector<double> k_tran, k_rot;  // time-step accumulators (automatic mode)
    /// Index of the clump (ClumpData, handle - 1) a pebble belongs to; kNoClump for a free ball.
    /// Pebbles are balls to the detection and the force loop, but not to the user.
    std::vector<uint32_t> clump;

    std::size_t size() const { return pos.size(); }
    void resize(std::size_t n);
    /// Gives back the arrays' spare capacity (trimCapacity), one array at a time.
    void trim();
    /// Moves slot `from` into slot `to` (all arrays).
    void move(std::size_t to, std::size_t from);
    void permute(const std::vector<uint32_t>& new_to_old);
};

/// A rigid clump (docs/physics/clumps.md). Its pebbles are balls (BallArrays slots, named here by
/// their handles so that sorting and deletion of balls need no update) whose mass and inertia
/// fields hold the clump's, so a pair's effective mass is the clump's. The law of motion
/// integrates the clump and places its pebbles rigidly (law_of_motion.cpp, moveClumps).
struct ClumpData {
    uint32_t generation = 1;
    bool alive = true;
    Vec2 pos{0.0, 0.0};  // centroid [m]
    Vec2 vel{0.0, 0.0};  // at the half step, like a ball's
    double angle = 0.0, spin = 0.0;
    double mass = 0.0, inv_mass = 0.0, inertia = 0.0, inv_inertia = 0.0;  // about the centroid
    double density = 0.0;                                                 // 0 in direct mode
    ClumpMassMode mode = ClumpMassMode::Union;
    Vec2 force{0.0, 0.0};  // contact force summed to the centroid, last step [N]
    double moment = 0.0;   // contact moment about the centroid, last step [N m]
    Vec2 fapp{0.0, 0.0};
    double mapp = 0.0;
    uint8_t fixity = 0;
    uint64_t groups = 0;
    double kn = kNotSet, ks = kNotSet, fric = kNotSet;
    std::vector<uint32_t> pebbles;     // ball handles
    std::vector<Vec2> offset;          // pebble centre - centroid, in the clump frame (angle 0)
    std::vector<double> angle_offset;  // pebble angle - clump angle
};

}  // namespace talus
