// SPDX-License-Identifier: MIT
#include "mpi_world.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#ifdef TALUS_HAVE_MPI
#include <mpi.h>

#include <algorithm>
#include <climits>
#endif

namespace talus::mpi {

namespace {
bool g_active = false;
int g_rank = 0;
int g_size = 1;

/// mpirun (OpenMPI's or any PMIx launcher) leaves these in the environment of its processes.
bool launchedByMpirun() {
    return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr;
}
}  // namespace

#ifdef TALUS_HAVE_MPI

bool built() { return true; }

void start() {
    if (g_active || !launchedByMpirun()) return;
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised && MPI_Init(nullptr, nullptr) != MPI_SUCCESS) return;
    // Errors come back as codes (turned into Lua errors) instead of aborting the job.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &g_size);
    g_active = true;
}

void finish(bool failed) {
    if (!g_active) return;
    g_active = false;
    if (failed && g_size > 1) MPI_Abort(MPI_COMM_WORLD, 1);
    MPI_Finalize();
}

std::vector<std::string> allgather(const std::string& mine) {
    std::vector<std::string> all(static_cast<std::size_t>(g_size));
    if (!g_active || g_size == 1) {
        all[0] = mine;
        return all;
    }
    auto check = [](int rc, const char* what) {
        if (rc != MPI_SUCCESS) {
            char text[MPI_MAX_ERROR_STRING];
            int len = 0;
            MPI_Error_string(rc, text, &len);
            throw std::runtime_error(std::string("map: ") + what + " failed: " +
                                     std::string(text, static_cast<std::size_t>(len)));
        }
    };
    const uint64_t my_len = mine.size();
    std::vector<uint64_t> lens(all.size());
    check(MPI_Allgather(&my_len, 1, MPI_UINT64_T, lens.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD),
          "MPI_Allgather of the result sizes");
    for (std::size_t r = 0; r < all.size(); ++r) all[r].resize(lens[r]);
    // MPI counts and displacements are ints: send in rounds of at most INT_MAX / size bytes per
    // rank, so that one round's total fits in an int whatever the result sizes.
    const uint64_t chunk = static_cast<uint64_t>(INT_MAX) / all.size();
    std::vector<int> counts(all.size()), displs(all.size());
    std::string buf;
    for (uint64_t done = 0;; done += chunk) {
        int total = 0;
        for (std::size_t r = 0; r < all.size(); ++r) {
            counts[r] = static_cast<int>(lens[r] > done ? std::min(chunk, lens[r] - done) : 0);
            displs[r] = total;
            total += counts[r];
        }
        if (total == 0) break;
        buf.resize(static_cast<std::size_t>(total));
        const int mine_count = counts[static_cast<std::size_t>(g_rank)];
        check(MPI_Allgatherv(mine_count ? mine.data() + done : nullptr, mine_count, MPI_BYTE,
                             buf.data(), counts.data(), displs.data(), MPI_BYTE, MPI_COMM_WORLD),
              "MPI_Allgatherv of the results");
        for (std::size_t r = 0; r < all.size(); ++r)
            if (counts[r])
                all[r].replace(done, static_cast<std::size_t>(counts[r]), buf.data() + displs[r],
                               static_cast<std::size_t>(counts[r]));
    }
    return all;
}

#else  // built without MPI: one rank

bool built() { return false; }
void start() {
    // Every rank would run the whole script on its own and write the same files: say so.
    if (launchedByMpirun())
        std::fputs(
            "talus: warning: launched by mpirun, but this talus was built without MPI: every "
            "process runs the whole script as rank 0 of 1\n",
            stderr);
}
void finish(bool) {}
std::vector<std::string> allgather(const std::string& mine) { return {mine}; }

#endif

bool active() { return g_active; }
int rank() { return g_rank; }
int size() { return g_size; }

}  // namespace talus::mpi
