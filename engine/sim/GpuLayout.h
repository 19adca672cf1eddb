#pragma once
// The GPU contract (shaders/common/gpu_contract.h) as C++: its structs, codes and sizes in namespace firn::gpu,
// with glm's vectors standing in for GLSL's. Sizes are pinned here; every member's offset is checked against
// the driver's by tests/gl/GpuContractTest.cpp.
#include <cstddef>
#include <cstdint>

#include <glm/vec4.hpp>

namespace firn::gpu {

using uint = std::uint32_t;
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
using uvec4 = glm::uvec4;

// std430 mat3 (particle buffers): three columns padded to vec4.
struct Mat3x4 {
  vec4 columns[3];
};
using mat3 = Mat3x4;

#include "common/gpu_contract.h"

static_assert(FIRN_BLOCK_GROUP_SIZE == BLOCK_NODES, "a per-block pass takes an invocation per node");
static_assert(FIRN_BLOCK_TILES == BLOCK_TILES, "order_tiles.comp takes an invocation per row");
static_assert(sizeof(Mat3x4) == 48, "std430 mat3 is 48 bytes");
static_assert(sizeof(ParticlePlasticState) == 16, "std430 ParticlePlasticState");
static_assert(sizeof(MaterialParams) == 64, "std430 MaterialParams");
static_assert(sizeof(ColliderParams) == 64, "std430 ColliderParams");
static_assert(sizeof(BlockTableHeader) == 96 + TILE_BUCKETS * sizeof(uint), "std430 BlockTableHeader");
static_assert(sizeof(BlockSlot) == 16, "std430 BlockSlot");
static_assert(sizeof(WatchdogStatus) == 48, "std430 WatchdogStatus");
static_assert(sizeof(StepUniforms) == 112, "std140 StepUniforms");
static_assert(sizeof(SolverNode) == 192, "std430 SolverNode");
static_assert(sizeof(SolverPreconditioner) == 32, "std430 SolverPreconditioner");
static_assert(sizeof(SolverParticle) == 144, "std430 SolverParticle");
static_assert(sizeof(SolverStatus) == 80 + SOLVER_REGISTERS * sizeof(vec4), "std430 SolverStatus");

}  // namespace firn::gpu
