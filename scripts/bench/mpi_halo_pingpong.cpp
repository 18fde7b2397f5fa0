// SPDX-License-Identifier: MIT
//
// Halo-exchange latency and bandwidth between two MPI ranks on one machine (docs/scaling.md):
// a ping-pong of the message sizes a Talus rank would exchange per step (ghost x, v, spin at
// 40 bytes per ghost; per-contact forces back), and an MPI_Allreduce(MIN) of one double (the
// automatic time step). Shared memory between two local processes is the best case an
// interconnect can approach, so these numbers are lower bounds for a cluster.
//
//   mpicxx -O2 -std=c++17 -o mpi_halo_pingpong scripts/bench/mpi_halo_pingpong.cpp
//   mpirun -np 2 ./mpi_halo_pingpong      (as root: OMPI_ALLOW_RUN_AS_ROOT=1
//                                          OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1, --oversubscribe)
// The C API only (as the project builds it: MPI_CXX_SKIP_MPICXX in CMakeLists.txt).
#define OMPI_SKIP_MPICXX 1
#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <vector>

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    int rank = 0, size = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    if (size != 2) {
        if (rank == 0) std::fprintf(stderr, "run with exactly 2 ranks\n");
        MPI_Finalize();
        return 1;
    }
    const int other = 1 - rank;
    // 8 B (one double), then 40 B x {1, 100, 1000, 4000, 8000} ghosts.
    const std::vector<long> sizes = {8, 40, 4000, 40000, 160000, 320000};
    std::vector<char> buf(320000, 1);
    if (rank == 0)
        std::printf(
            "| bytes | one-way time, min [us] | median [us] | bandwidth at min [GB/s] |\n"
            "|---|---|---|---|\n");
    for (long bytes : sizes) {
        const int reps = bytes > 100000 ? 200 : 1000;
        std::vector<double> t(reps);
        for (int warm = 0; warm < 20; ++warm) {
            if (rank == 0) {
                MPI_Send(buf.data(), int(bytes), MPI_CHAR, other, 0, MPI_COMM_WORLD);
                MPI_Recv(buf.data(), int(bytes), MPI_CHAR, other, 0, MPI_COMM_WORLD,
                         MPI_STATUS_IGNORE);
            } else {
                MPI_Recv(buf.data(), int(bytes), MPI_CHAR, other, 0, MPI_COMM_WORLD,
                         MPI_STATUS_IGNORE);
                MPI_Send(buf.data(), int(bytes), MPI_CHAR, other, 0, MPI_COMM_WORLD);
            }
        }
        for (int k = 0; k < reps; ++k) {
            const double t0 = MPI_Wtime();
            if (rank == 0) {
                MPI_Send(buf.data(), int(bytes), MPI_CHAR, other, 0, MPI_COMM_WORLD);
                MPI_Recv(buf.data(), int(bytes), MPI_CHAR, other, 0, MPI_COMM_WORLD,
                         MPI_STATUS_IGNORE);
            } else {
                MPI_Recv(buf.data(), int(bytes), MPI_CHAR, other, 0, MPI_COMM_WORLD,
                         MPI_STATUS_IGNORE);
                MPI_Send(buf.data(), int(bytes), MPI_CHAR, other, 0, MPI_COMM_WORLD);
            }
            t[k] = (MPI_Wtime() - t0) / 2;  // one way
        }
        std::sort(t.begin(), t.end());
        if (rank == 0)
            std::printf("| %ld | %.2f | %.2f | %.3f |\n", bytes, t[0] * 1e6, t[reps / 2] * 1e6,
                        double(bytes) / t[0] * 1e-9);
    }
    // The automatic step: one global minimum per step.
    std::vector<double> t(1000);
    double dt = 1e-5 * (1 + rank), out = 0;
    for (int k = 0; k < 20; ++k) MPI_Allreduce(&dt, &out, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
    for (double& tk : t) {
        const double t0 = MPI_Wtime();
        MPI_Allreduce(&dt, &out, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
        tk = MPI_Wtime() - t0;
    }
    std::sort(t.begin(), t.end());
    if (rank == 0)
        std::printf("\nMPI_Allreduce(MIN, 1 double), 2 ranks: min %.2f us, median %.2f us\n",
                    t[0] * 1e6, t[t.size() / 2] * 1e6);
    MPI_Finalize();
    return 0;
}
