#include "mpi/MpiWorld.h"

#include <algorithm>
#include <cstdlib>
#include <string>
#include <thread>

namespace firn::mpi {

bool launchedByMpi() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(variable) != nullptr) return true;
  }
  return false;
}

MpiWorld::MpiWorld(int& argc, char**& argv) {
  MPI_Init(&argc, &argv);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  // The ranks on this machine (MPI-3's shared-memory split): a rank's place among them picks its GPU, and their
  // number divides a CPU renderer's cores.
  MPI_Comm local;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &local);
  int localSize = 1;
  MPI_Comm_rank(local, &localRank_);
  MPI_Comm_size(local, &localSize);
  MPI_Comm_free(&local);
  if (std::getenv("LP_NUM_THREADS") == nullptr) {
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    setenv("LP_NUM_THREADS", std::to_string(std::max(1, cores / localSize)).c_str(), 0);
  }
}

MpiWorld::~MpiWorld() { MPI_Finalize(); }

void MpiWorld::abort(int exitCode) const {
  MPI_Abort(MPI_COMM_WORLD, exitCode);
  std::_Exit(exitCode);  // MPI_Abort does not return; should it, the rank still ends
}

}  // namespace firn::mpi
