// SPDX-License-Identifier: MIT
//
// The force loop on threads (docs/architecture.md, "Threads"): how many a step takes, the
// threads' scratch, which thread adds onto which ball (the routes), and the gather of the pairs'
// actions onto the balls no one thread owns, in pair order: the result is the same bit for bit
// for any thread count.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "force/force.hpp"
#include "force/scratch.hpp"
#include "talus/errors.hpp"

namespace talus {

namespace {
bool g_single_threaded_process = false;  // Model::singleThreadedProcess
}  // namespace

void setSingleThreadedProcess() { g_single_threaded_process = true; }

namespace {

/// The thread whose range holds pair i.
int pairThread(std::size_t npairs, int nthreads, std::size_t i) {
    int t = static_cast<int>(i * static_cast<std::size_t>(nthreads) / npairs);
    while (t + 1 < nthreads && threadRangeStart(npairs, nthreads, t + 1) <= i) ++t;
    while (t > 0 && threadRangeStart(npairs, nthreads, t) > i) --t;
    return t;
}

/// A ball's sums: force, moment, and the automatic step's stiffness sums.
struct BallSums {
    double fx, fy, m, kt, kr;
};
/// Adds the actions of a ball's incidence entries [from, to) onto its sums, in pair order.
inline void addActions(const ForceScratch& s, uint32_t from, uint32_t to, bool automatic,
                       BallSums& sum) {
    for (uint32_t q = from; q < to; ++q) {
        const uint32_t code = s.incidence[q];
        const double* add = s.actions[code >> 1].add[code & 1u];
        sum.fx += add[0];
        sum.fy += add[1];
        sum.m += add[2];
    }
    if (automatic)
        for (uint32_t q = from; q < to; ++q) {
            const uint32_t code = s.incidence[q];
            const double* add = s.stiffness[code >> 1].add[code & 1u];
            sum.kt += add[0];
            sum.kr += add[1];
        }
}

}  // namespace

void gatherPairActions(World& world, bool automatic) {
    auto& b = world.bodies.balls;
    ForceScratch& s = forceScratch(world);
    const uint32_t* start = s.incidence_start.data();
    const auto store = [&](uint32_t k, const BallSums& sum) {
        b.force[k] = Vec2(sum.fx, sum.fy);
        b.moment[k] = sum.m;
        if (automatic) b.k_tran[k] = sum.kt, b.k_rot[k] = sum.kr;
    };
    // A shared ball's sums start from zero and take its pairs in pair order: the additions one
    // thread makes (finishContact), in its order (PairAction).
    for (const uint32_t k : s.shared) {
        BallSums sum{0.0, 0.0, 0.0, 0.0, 0.0};
        addActions(s, start[k], start[k + 1], automatic, sum);
        store(k, sum);
    }
    // A diverted ball holds what its thread added before the deferred pair: the rest follows.
    for (auto& part : s.parts) {
        for (const auto& [k, first] : part.diverted) {
            BallSums sum{b.force[k].x(), b.force[k].y(), b.moment[k], 0.0, 0.0};
            if (automatic) sum.kt = b.k_tran[k], sum.kr = b.k_rot[k];
            uint32_t q = start[k];
            while (q < start[k + 1] && (s.incidence[q] >> 1) < first) ++q;
            addActions(s, q, start[k + 1], automatic, sum);
            store(k, sum);
            s.route[k] = part.index;
        }
        part.diverted.clear();
    }
}

void buildIncidence(World& world, int nthreads) {
    ForceScratch& s = forceScratch(world);
    const auto& pairs = world.contacts.pairs;
    const std::size_t nballs = world.bodies.balls.size();
    if (s.incidence_version == world.contacts.pairs_version && s.route_threads == nthreads &&
        s.incidence_start.size() == nballs + 1)
        return;
    if (pairs.size() >= (std::size_t{1} << 31))
        throw InputError("threads: more than 2^31 pairs (run on one thread)");
    auto& start = s.incidence_start;
    start.assign(nballs + 1, 0u);
    for (const Pair& p : pairs) {
        ++start[p.end1 + 1];
        if (!p.wall) ++start[p.end2 + 1];
    }
    for (std::size_t k = 0; k < nballs; ++k) start[k + 1] += start[k];
    s.incidence.resize(start[nballs]);
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        const auto code = static_cast<uint32_t>(i << 1);
        s.incidence[fill[pairs[i].end1]++] = code;
        if (!pairs[i].wall) s.incidence[fill[pairs[i].end2]++] = code | 1u;
    }
    // A ball whose first and last pair fall in one thread's range is that thread's alone.
    s.route.assign(nballs, 0);
    s.shared.clear();
    const std::size_t npairs = pairs.size();
    for (std::size_t k = 0; k < nballs; ++k) {
        if (start[k] == start[k + 1]) continue;
        const int t = pairThread(npairs, nthreads, s.incidence[start[k]] >> 1);
        if (t == pairThread(npairs, nthreads, s.incidence[start[k + 1] - 1] >> 1)) {
            s.route[k] = static_cast<uint16_t>(t);
        } else {
            s.route[k] = kRouteShared;
            s.shared.push_back(static_cast<uint32_t>(k));
        }
    }
    s.incidence_version = world.contacts.pairs_version;
    s.route_threads = nthreads;
}

int forceThreads(const World& world, std::size_t npairs) {
#ifdef TALUS_HAVE_OPENMP
    const int wanted = world.facade.threads();
    if (wanted <= 1 || g_single_threaded_process) return 1;
    const std::size_t by_grain = npairs / static_cast<std::size_t>(world.facade.threadGrain());
    int n = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(wanted), by_grain));
    if (n < 2) return 1;
    if (n > kMaxRoutedThreads) n = kMaxRoutedThreads;
    // Energy per group books every contact into its groups' sums and border records as it
    // goes: one thread (docs/architecture.md, "Threads").
    if (world.books.on && world.books.groups.on) return 1;
    for (const auto& rule : world.contacts.rules)
        if (rule->prototype && !(rule->prototype->Traits() & kTraitThreadSafe)) return 1;
    return n;
#else
    (void)world;
    (void)npairs;
    return 1;
#endif
}

void prepareThreadScratch(World& world, int nthreads) {
    ForceScratch& s = forceScratch(world);
    // (pairs a vertex hand-over adds in this step are not processed in it: npairs is enough)
    s.actions.resize(world.contacts.pairs.size());
    if (world.settings.timestep.automatic) s.stiffness.resize(world.contacts.pairs.size());
    if (world.books.on) s.energies.resize(world.contacts.pairs.size());
    buildIncidence(world, nthreads);
}

}  // namespace talus
