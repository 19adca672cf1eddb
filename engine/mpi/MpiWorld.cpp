#include "mpi/MpiWorld.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdlib>
#include <string>
#include <thread>

namespace firn::mpi {

namespace {

std::atomic<std::uint64_t> currentStep{0};  // lock-free: read in a signal handler
int worldRank = 0;
int worldSize = 1;

// Appends `value` in decimal at `out` (async-signal-safe, unlike snprintf).
char* appendNumber(char* out, std::uint64_t value) {
  char digits[24];
  int count = 0;
  do {
    digits[count++] = char('0' + value % 10);
    value /= 10;
  } while (value > 0);
  while (count > 0) *out++ = digits[--count];
  return out;
}

char* appendText(char* out, const char* text) {
  while (*text != '\0') *out++ = *text++;
  return out;
}

// mpirun ends the other ranks (SIGTERM) when one dies: say where this one was, then end.
extern "C" void onStoppedByLauncher(int signal) {
  char text[256];
  char* out = appendText(text, "\nfirn: rank ");
  out = appendNumber(out, std::uint64_t(worldRank));
  out = appendText(out, " of ");
  out = appendNumber(out, std::uint64_t(worldSize));
  out = appendText(out, ": stopped by mpirun at step ");
  out = appendNumber(out, currentStep.load(std::memory_order_relaxed));
  out = appendText(out, ", after another rank of the run ended (mpirun names it and why)\n");
  [[maybe_unused]] const ssize_t written = write(STDERR_FILENO, text, std::size_t(out - text));
  _exit(128 + signal);
}

}  // namespace

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
  worldRank = rank_;
  worldSize = size_;
  static_assert(std::atomic<std::uint64_t>::is_always_lock_free, "the step is read in a signal handler");
  if (size_ > 1) std::signal(SIGTERM, onStoppedByLauncher);
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

void MpiWorld::noteStep(std::uint64_t step) { currentStep.store(step, std::memory_order_relaxed); }

void MpiWorld::abort(int exitCode) const {
  std::signal(SIGTERM, SIG_DFL);  // this rank said why it ends; mpirun's SIGTERM is then no news
  MPI_Abort(MPI_COMM_WORLD, exitCode);
  std::_Exit(exitCode);  // MPI_Abort does not return; should it, the rank still ends
}

}  // namespace firn::mpi
