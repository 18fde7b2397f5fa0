// SPDX-License-Identifier: MIT
//
// The force loop on threads (docs/architecture.md, "Threads"): how many a step takes, the
// threads' scratch, and the gather of the pairs' actions onto the balls in pair order, which
// makes the result the same bit for bit for any thread count.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "force/force.hpp"
#include "talus/errors.hpp"

namespace talus {

namespace {
bool g_single_threaded_process = false;  // Model::singleThreadedProcess
}  // namespace

void setSingleThreadedProcess() { g_single_threaded_process = true; }

void gatherPairActions(World& world, int nthreads, bool automatic) {
    auto& b = world.bodies.balls;
    const ForceScratch& s = world.contacts.force_scratch;
    const PairAction* actions = s.actions.data();
    const PairStiffness* stiffness = s.stiffness.data();
    const uint32_t* start = s.incidence_start.data();
    const uint32_t* incidence = s.incidence.data();
    Vec2* force = b.force.data();
    double* moment = b.moment.data();
    double* k_tran = b.k_tran.data();
    double* k_rot = b.k_rot.data();
    const auto nballs = static_cast<std::ptrdiff_t>(b.size());
    (void)nthreads;
    // Each ball's sums start from zero and take its pairs in pair order: the additions one
    // thread makes (finishContact), in its order (PairAction).
    TALUS_OMP(omp parallel for num_threads(nthreads) schedule(static))
    for (std::ptrdiff_t k = 0; k < nballs; ++k) {
        double fx = 0.0, fy = 0.0, m = 0.0;
        for (uint32_t q = start[k]; q < start[k + 1]; ++q) {
            const uint32_t code = incidence[q];
            const double* add = actions[code >> 1].add[code & 1u];
            fx += add[0];
            fy += add[1];
            m += add[2];
        }
        force[k] = Vec2(fx, fy);
        moment[k] = m;
        if (automatic) {
            double kt = 0.0, kr = 0.0;
            for (uint32_t q = start[k]; q < start[k + 1]; ++q) {
                const uint32_t code = incidence[q];
                const double* add = stiffness[code >> 1].add[code & 1u];
                kt += add[0];
                kr += add[1];
            }
            k_tran[k] = kt, k_rot[k] = kr;
        }
    }
}

void buildIncidence(World& world) {
    ForceScratch& s = world.contacts.force_scratch;
    const auto& pairs = world.contacts.pairs;
    const std::size_t nballs = world.bodies.balls.size();
    if (s.incidence_version == world.contacts.pairs_version &&
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
    s.incidence_version = world.contacts.pairs_version;
}

int forceThreads(const World& world, std::size_t npairs) {
#ifdef TALUS_HAVE_OPENMP
    const int wanted = world.facade.threads();
    if (wanted <= 1 || g_single_threaded_process) return 1;
    const std::size_t by_grain = npairs / static_cast<std::size_t>(world.facade.threadGrain());
    const int n =
        static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(wanted), by_grain));
    if (n < 2) return 1;
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

void prepareForceScratch(World& world, int nthreads, const FdBlock& tmpl) {
    ForceScratch& s = world.contacts.force_scratch;
    s.parts.resize(static_cast<std::size_t>(nthreads));
    for (auto& part : s.parts) {
        part.fd = tmpl;
        part.items.clear();
        part.apart.clear();
        part.limits = StepLimits{};
        part.finite_check = 0.0;
        part.batched = 0;
        part.failure = nullptr;
        part.failure_pair = SIZE_MAX;
        part.lane_entries.clear();
        part.lane_releases.clear();
        part.lane_steps = part.lane_declined = 0;
        part.kernel_steps = part.kernel_declined = 0;
    }
    // (pairs a vertex hand-over adds in this step are not processed in it: npairs is enough)
    s.actions.resize(world.contacts.pairs.size());
    if (world.settings.timestep.automatic) s.stiffness.resize(world.contacts.pairs.size());
    if (world.books.on) s.energies.resize(world.contacts.pairs.size());
    for (auto& part : s.parts) part.contracts.clear();
    buildIncidence(world);
}

}  // namespace talus
