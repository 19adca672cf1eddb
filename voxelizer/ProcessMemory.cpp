#include "voxelizer/ProcessMemory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <thread>

namespace firn::voxelizer {

std::uint64_t mappedBytes() {
  // /proc/self/statm: the first field is the size of the address space in pages.
  std::ifstream statm("/proc/self/statm");
  std::uint64_t pages = 0;
  statm >> pages;
  return pages * std::uint64_t(sysconf(_SC_PAGESIZE));
}

std::uint64_t allocatableBytes() {
  std::uint64_t available = std::numeric_limits<std::uint64_t>::max();
  std::ifstream meminfo("/proc/meminfo");
  std::string line;
  while (std::getline(meminfo, line)) {
    // "MemAvailable:   21474836 kB"
    if (line.rfind("MemAvailable:", 0) == 0) {
      available = std::strtoull(line.c_str() + std::strlen("MemAvailable:"), nullptr, 10) * 1024;
      break;
    }
  }
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    // Address space is also taken by what is not memory in use: the stacks (8 MiB each) of the threads yet to
    // start, the sampler's one per hardware thread, and a malloc arena (64 MiB reserved) or two.
    const std::uint64_t threads = std::max(1u, std::thread::hardware_concurrency());
    const std::uint64_t reserve = (threads * 8 + 2 * 64) * (std::uint64_t{1} << 20);
    const std::uint64_t taken = mappedBytes() + reserve;
    available = std::min<std::uint64_t>(available, limit.rlim_cur > taken ? limit.rlim_cur - taken : 0);
  }
  return available;
}

}  // namespace firn::voxelizer
