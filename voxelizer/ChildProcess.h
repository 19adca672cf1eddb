#pragma once
// Running untrusted work (a third-party file parser) where it cannot take the caller down: in a child process
// with limits on its memory, CPU time and wall-clock time, whose result comes back over a pipe. Whatever the
// work does — abort, exhaust memory, crash, loop for ever — the caller gets an outcome in words, within the
// limits. POSIX (fork, setrlimit, poll).
#include <cstdint>
#include <functional>
#include <string>

namespace firn::voxelizer {

struct ChildLimits {
  std::uint64_t memoryBytes = 0;  // address space the child may map beyond what it inherits (RLIMIT_AS)
  double cpuS = 0;                // CPU seconds (RLIMIT_CPU, rounded up)
  double wallS = 0;               // after this the child is killed
};

struct ChildOutcome {
  bool succeeded = false;  // the work returned and the child exited normally
  std::string result;      // what the work returned
  std::string failure;     // otherwise why, in words: "was killed by signal 6 (Aborted)", "ran out of …"
  std::string lastWords;   // the last line the child wrote to stderr (an assertion's text, say), or empty
};

// Forks; the child sets the limits, runs `work` and sends back what it returns; the parent waits for it at
// most limits.wallS. Before a GL context exists is the safest time to call it: the child never touches what
// it inherited beyond the memory `work` reads, and leaves with _exit, so no destructor or atexit handler runs
// twice. A child stuck on a lock another thread held at the fork is killed at the wall-clock limit like any
// other. Throws std::system_error if the pipes or the fork cannot be made.
ChildOutcome runInChildProcess(const std::function<std::string()>& work, const ChildLimits& limits);

}  // namespace firn::voxelizer
