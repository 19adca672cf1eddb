#pragma once
// MPI for `firn run` under mpirun (docs/distributed.md): started only when a launcher started this process, so that
// `firn` on its own never touches MPI. Open MPI's, MPICH's and PMIx's launchers say so in the environment.
#include <cstdint>

#include <mpi.h>

namespace firn::mpi {

// Whether an MPI launcher (mpirun, mpiexec, srun) started this process.
bool launchedByMpi();

class MpiWorld {
 public:
  // MPI_Init. Before any GL context: on a CPU renderer (llvmpipe) the ranks on one machine share its cores, so each
  // gets its share of renderer threads (LP_NUM_THREADS) unless the user set them.
  MpiWorld(int& argc, char**& argv);
  ~MpiWorld();  // MPI_Finalize
  MpiWorld(const MpiWorld&) = delete;
  MpiWorld& operator=(const MpiWorld&) = delete;

  MPI_Comm comm() const { return MPI_COMM_WORLD; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  // The rank among those on this machine: which of its GPUs the rank takes.
  int localRank() const { return localRank_; }

  // Ends every rank of the run at once with `exitCode` (MPI_Abort): what a rank does when it fails, so that no
  // other rank waits for it.
  [[noreturn]] void abort(int exitCode) const;

  // The step this rank is in: when mpirun ends the rank because another one ended (SIGTERM), the rank says at which
  // step, which the launcher's own message (naming the rank that ended and why) cannot.
  static void noteStep(std::uint64_t step);

 private:
  int rank_ = 0;
  int size_ = 1;
  int localRank_ = 0;
};

}  // namespace firn::mpi
