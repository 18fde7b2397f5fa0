// SPDX-License-Identifier: MIT
//
// The MPI world of a `talus run` launched by mpirun (talus.rank, talus.ranks, and the gather
// step of talus.map). MPI is optional at build time (TALUS_HAVE_MPI) and at run time: it is
// initialised only when the process was started by mpirun (OpenMPI sets OMPI_COMM_WORLD_SIZE,
// PMIx launchers PMIX_RANK), so a plain `talus run` never touches it. Without it the world is
// one rank, rank 0.
#pragma once

#include <string>
#include <vector>

namespace talus::mpi {

/// Initialises MPI if the process was launched by mpirun and Talus was built with MPI.
void start();
/// Ends MPI: MPI_Finalize, or MPI_Abort when this rank failed and there are other ranks (they
/// may wait for it in a collective call and would otherwise hang).
void finish(bool failed);
/// True when MPI was initialised (even for mpirun -n 1).
bool active();
/// This process's rank (0-based) and the number of ranks; 0 and 1 without MPI.
int rank();
int size();
/// Collective: every rank passes its bytes and receives every rank's bytes, in rank order.
/// Throws std::runtime_error on an MPI failure.
std::vector<std::string> allgather(const std::string& mine);
/// Whether this build can use MPI at all.
bool built();

}  // namespace talus::mpi
