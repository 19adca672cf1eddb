#pragma once
// What this process has mapped and what it may still allocate: the memory the importer's child process is held to
// (voxelizer/ChildProcess.h, voxelizer/Mesh.h) and that the engine's budget and `firn voxelize` set particles
// against. Linux (/proc), POSIX (getrlimit).
#include <cstdint>

namespace firn::voxelizer {

// The size of this process's address space (/proc/self/statm), what RLIMIT_AS counts.
std::uint64_t mappedBytes();

// What this process may still allocate, in bytes: the smaller of the memory the system has available
// (/proc/meminfo's MemAvailable) and what the address-space limit (RLIMIT_AS, `ulimit -v`) leaves beyond what is
// mapped and what threads' stacks and malloc arenas will reserve.
std::uint64_t allocatableBytes();

}  // namespace firn::voxelizer
