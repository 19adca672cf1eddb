#pragma once
// The GPU contract (shaders/common/gpu_contract.h) as C++: its structs, codes and sizes in namespace firn::gpu,
// with glm's vectors standing in for GLSL's. Sizes are pinned here; every member's offset is checked against
// the driver's by tests/gl/GpuContractTest.cpp.
#include <cstddef>
#include <cstdint>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace firn::gpu {

using uint = std::uint32_t;
using vec3 = glm::vec3;
using ivec3 = glm::ivec3;
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
using uvec4 = glm::uvec4;

// std430 mat3 (particle buffers): three columns padded to vec4.
struct Mat3x4 {
  vec4 columns[3];
};
using mat3 = Mat3x4;

#include "common/gpu_contract.h"

// The binding ranges: each part's bindings lie in its range, no two share a number, and the ranges, in order, end
// within what Firn requires of a driver.
struct BindingRange {
  int first;
  int end;
};
template <std::size_t N>
constexpr bool bindingsWithin(const int (&bindings)[N], BindingRange range) {
  for (std::size_t i = 0; i < N; ++i) {
    if (bindings[i] < range.first || bindings[i] >= range.end) return false;
    for (std::size_t j = 0; j < i; ++j) {
      if (bindings[i] == bindings[j]) return false;
    }
  }
  return true;
}
constexpr BindingRange kParticleBindings{FIRN_PARTICLE_BINDINGS_FIRST, FIRN_PARTICLE_BINDINGS_END};
constexpr BindingRange kGridBindings{FIRN_GRID_BINDINGS_FIRST, FIRN_GRID_BINDINGS_END};
constexpr BindingRange kTableBindings{FIRN_TABLE_BINDINGS_FIRST, FIRN_TABLE_BINDINGS_END};
constexpr BindingRange kSolverBindings{FIRN_SOLVER_BINDINGS_FIRST, FIRN_SOLVER_BINDINGS_END};
constexpr BindingRange kBodyBindings{FIRN_BODY_BINDINGS_FIRST, FIRN_BODY_BINDINGS_END};
constexpr BindingRange kSurfaceBindings{FIRN_SURFACE_BINDINGS_FIRST, FIRN_SURFACE_BINDINGS_END};
constexpr BindingRange kBindingRanges[] = {kParticleBindings, kGridBindings,  kTableBindings,
                                           kSolverBindings,   kBodyBindings, kSurfaceBindings};
template <std::size_t N>
constexpr bool rangesInOrder(const BindingRange (&ranges)[N], int bindingLimit) {
  int end = 0;
  for (std::size_t i = 0; i < N; ++i) {
    if (ranges[i].first < end || ranges[i].end < ranges[i].first) return false;
    end = ranges[i].end;
  }
  return end <= bindingLimit;
}
static_assert(rangesInOrder(kBindingRanges, FIRN_REQUIRED_STORAGE_BINDINGS),
              "binding ranges overlap, or end past FIRN_REQUIRED_STORAGE_BINDINGS");
constexpr int kParticleBindingPoints[] = {FIRN_BINDING_POSITION_MASS, FIRN_BINDING_VELOCITY_VOLUME,
                                          FIRN_BINDING_ELASTIC_DEFORMATION, FIRN_BINDING_KIRCHHOFF_STRESS,
                                          FIRN_BINDING_AFFINE, FIRN_BINDING_PLASTIC_STATE};
static_assert(bindingsWithin(kParticleBindingPoints, kParticleBindings), "a particle binding outside its range");
constexpr int kGridBindingPoints[] = {FIRN_BINDING_GRID_MOMENTUM_MASS, FIRN_BINDING_GRID_IMPULSE,
                                      FIRN_BINDING_BLOCK_TABLE,         FIRN_BINDING_BLOCK_MAP,
                                      FIRN_BINDING_BINS,                FIRN_BINDING_SORTED_PARTICLES,
                                      FIRN_BINDING_PARTICLE_RANKS,      FIRN_BINDING_TILE_ORDER};
static_assert(bindingsWithin(kGridBindingPoints, kGridBindings), "a block grid binding outside its range");
constexpr int kTableBindingPoints[] = {FIRN_BINDING_MATERIALS, FIRN_BINDING_COLLIDERS, FIRN_BINDING_WATCHDOG};
static_assert(bindingsWithin(kTableBindingPoints, kTableBindings), "a table binding outside its range");
constexpr int kSolverBindingPoints[] = {FIRN_BINDING_SOLVER_NODES, FIRN_BINDING_SOLVER_PARTICLES,
                                        FIRN_BINDING_SOLVER_STATUS, FIRN_BINDING_SOLVER_PRECONDITIONER};
static_assert(bindingsWithin(kSolverBindingPoints, kSolverBindings), "a solver binding outside its range");
constexpr int kBodyBindingPoints[] = {FIRN_BINDING_BODIES};
static_assert(bindingsWithin(kBodyBindingPoints, kBodyBindings), "a body binding outside its range");
constexpr int kUniformBindingPoints[] = {FIRN_BINDING_STEP_UNIFORMS, FIRN_BINDING_SURFACE_UNIFORMS,
                                         FIRN_BINDING_SURFACE_CASES};
static_assert(bindingsWithin(kUniformBindingPoints, {0, 3}), "uniform binding points must be distinct");

static_assert(FIRN_BLOCK_GROUP_SIZE == BLOCK_NODES, "a per-block pass takes an invocation per node");
static_assert(FIRN_BLOCK_TILES == BLOCK_TILES, "order_tiles.comp takes an invocation per row");
static_assert(sizeof(Mat3x4) == 48, "std430 mat3 is 48 bytes");
static_assert(sizeof(ParticlePlasticState) == 16, "std430 ParticlePlasticState");
static_assert(sizeof(MaterialParams) == 64, "std430 MaterialParams");
static_assert(sizeof(ColliderParams) == 224, "std430 ColliderParams");
static_assert(sizeof(BlockTableHeader) == 144 + TILE_BUCKETS * sizeof(uint), "std430 BlockTableHeader");
static_assert(sizeof(BlockSlot) == 24, "std430 BlockSlot");
static_assert(sizeof(WatchdogStatus) == 48, "std430 WatchdogStatus");
static_assert(sizeof(EnergyLedger) == 80, "std430 EnergyLedger");
static_assert(sizeof(ObjectLoad) == 32, "std430 ObjectLoad");
static_assert(sizeof(StepUniforms) == 144, "std140 StepUniforms");
static_assert(sizeof(SolverNode) == 192, "std430 SolverNode");
static_assert(sizeof(SolverPreconditioner) == 32, "std430 SolverPreconditioner");
static_assert(sizeof(BodyRecord) == 752, "std430 BodyRecord");
static_assert(sizeof(BodyContact) == 48, "std430 BodyContact");
static_assert(sizeof(SolverParticle) == 144, "std430 SolverParticle");
static_assert(sizeof(SolverStatus) == 80 + SOLVER_REGISTERS * sizeof(vec4), "std430 SolverStatus");

}  // namespace firn::gpu
