#pragma once
// Everything the host shares with the shaders: binding points (injected into GLSL as FIRN_BINDING_* defines,
// so they are written once) and the std140/std430 structs, whose sizes are pinned by static_assert.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec4.hpp>

namespace firn::gpu {

// Shader storage binding points (one SSBO each).
enum StorageBinding : std::uint32_t {
  PositionMass = 0,    // vec4: x (m), mass (kg)
  VelocityVolume = 1,  // vec4: v (m/s), initial volume V0 (m³)
  ElasticDeformation = 2,  // mat3 F_E
  KirchhoffStress = 3,     // mat3 τ = (∂Ψ/∂F_E) F_Eᵀ (Pa), from the last deformation update
  Affine = 4,              // mat3 C (APIC only)
  PlasticState = 5,        // ParticlePlasticState
  GridMomentumMass = 6,    // per node: momentum and mass sums, then velocity and mass
  GridImpulse = 7,         // per node (PIC/FLIP only): impulse sums, then the velocity before forces
  Materials = 8,           // MaterialParams[]
  Colliders = 9,           // ColliderParams[]
  ActiveRegion = 10,       // ActiveRegion
  Watchdog = 11,           // WatchdogStatus
  Blocks = 12,             // BlockTable (solver.atomics "none"): the particle bins of the coloured P2G
  ParticleSlots = 13,      // uint per particle: its place within its block's bin
  BlockParticles = 14,     // uint per particle: particle indices, bin after bin
  BlockOrder = 15,         // uint per block: each colour's non-empty blocks, fullest first
};

// Uniform block binding point.
enum UniformBinding : std::uint32_t { StepUniformsBlock = 0 };

inline std::vector<std::pair<std::string, std::string>> bindingDefines() {
  return {
      {"FIRN_BINDING_POSITION_MASS", std::to_string(PositionMass)},
      {"FIRN_BINDING_VELOCITY_VOLUME", std::to_string(VelocityVolume)},
      {"FIRN_BINDING_ELASTIC_DEFORMATION", std::to_string(ElasticDeformation)},
      {"FIRN_BINDING_KIRCHHOFF_STRESS", std::to_string(KirchhoffStress)},
      {"FIRN_BINDING_AFFINE", std::to_string(Affine)},
      {"FIRN_BINDING_PLASTIC_STATE", std::to_string(PlasticState)},
      {"FIRN_BINDING_GRID_MOMENTUM_MASS", std::to_string(GridMomentumMass)},
      {"FIRN_BINDING_GRID_IMPULSE", std::to_string(GridImpulse)},
      {"FIRN_BINDING_MATERIALS", std::to_string(Materials)},
      {"FIRN_BINDING_COLLIDERS", std::to_string(Colliders)},
      {"FIRN_BINDING_ACTIVE_REGION", std::to_string(ActiveRegion)},
      {"FIRN_BINDING_WATCHDOG", std::to_string(Watchdog)},
      {"FIRN_BINDING_BLOCKS", std::to_string(Blocks)},
      {"FIRN_BINDING_PARTICLE_SLOTS", std::to_string(ParticleSlots)},
      {"FIRN_BINDING_BLOCK_PARTICLES", std::to_string(BlockParticles)},
      {"FIRN_BINDING_BLOCK_ORDER", std::to_string(BlockOrder)},
      {"FIRN_BINDING_STEP_UNIFORMS", std::to_string(StepUniformsBlock)},
  };
}

// std430 mat3: three columns padded to vec4.
struct Mat3x4 {
  glm::vec4 columns[3];
};
static_assert(sizeof(Mat3x4) == 48, "std430 mat3 is 48 bytes");

// The scalar state each material keeps besides F (materials.glsl): snow J_P = det F_P; water J = det F; sand
// its hardening state q and log-volume correction V_c (Klár 2016). 1 for what a material does not use.
struct ParticlePlasticState {
  float plasticJ;               // snow: J_P; water: J; sand: q
  std::uint32_t materialIndex;  // into the material table (sim/Materials.h)
  float volumeCorrection;       // sand: V_c
  float unused;
};
static_assert(sizeof(ParticlePlasticState) == 16, "std430 ParticlePlasticState");

enum class MaterialModelCode : std::int32_t { Snow = 0, FixedCorotated = 1, NeoHookean = 2, Water = 3, DruckerPrager = 4 };

struct MaterialParams {
  glm::vec4 elastic;  // μ0 (Pa), λ0 (Pa), snow hardening ξ, density (kg/m³)
  glm::vec4 plastic;  // snow: 1 − θc, 1 + θs; sand: h0, h1 (rad), h2, h3 (rad)
  glm::vec4 fluid;    // water: bulk modulus k (Pa), γ, viscosity (Pa·s)
  glm::ivec4 model;   // x: MaterialModelCode
};
static_assert(sizeof(MaterialParams) == 64, "std430 MaterialParams");

enum class ColliderShapeCode : std::int32_t { Plane = 0, Sphere = 1, Box = 2 };
enum class BoundaryCode : std::int32_t { Sticky = 0, Slip = 1, Separate = 2 };

struct ColliderParams {
  glm::vec4 geometryA;           // plane: point; sphere: centre, w = radius; box: min corner (at t = 0)
  glm::vec4 geometryB;           // plane: unit normal; box: max corner (at t = 0)
  glm::vec4 velocityFriction;    // xyz velocity (m/s), w Coulomb μ
  glm::ivec4 shapeBoundary;      // x ColliderShapeCode, y BoundaryCode
};
static_assert(sizeof(ColliderParams) == 64, "std430 ColliderParams");

// The grid region the particles occupy: accumulated by G2P, turned into this step's node box and the
// indirect dispatch of the grid passes by prepare_grid.comp. Particles added between steps (emitters, the
// viewer's snowballs) did not take part in the last G2P: the host writes their cell bounds to `added…`,
// which prepare_grid merges in, so adding particles needs no readback.
struct ActiveRegionData {
  glm::ivec4 particleCellMin;  // atomicMin of particle cells
  glm::ivec4 particleCellMax;  // atomicMax of particle cells
  glm::ivec4 boxMin;           // first node of the box
  glm::ivec4 boxSize;          // nodes per axis; w = node count
  glm::uvec4 gridDispatch;     // work groups for the grid passes (glDispatchComputeIndirect reads xyz)
  glm::ivec4 addedCellMin;     // cells of the particles added since the last step (host-written)
  glm::ivec4 addedCellMax;
};
static_assert(sizeof(ActiveRegionData) == 112, "std430 ActiveRegion");
constexpr std::size_t kAddedCellsOffset = offsetof(ActiveRegionData, addedCellMin);
constexpr std::size_t kGridDispatchOffset = offsetof(ActiveRegionData, gridDispatch);

// P2G without atomics (solver.atomics "none", shaders/common/blocks.glsl): particles are binned into blocks of
// kBlockCells³ cells; the blocks of one colour (the parities of their coordinates) are far enough apart that no
// two of them reach the same node, so one colour at a time, each block's particles are scattered by one
// invocation with plain additions. bin_scan.comp writes the header; the bins follow it, one per block of the
// domain. The block order lists each colour's non-empty blocks.
constexpr int kBlockCells = 4;  // > 2: a particle in cell c reaches nodes c − 1 … c + 2 with either kernel
constexpr int kBlockColors = 8;
struct BlockColor {
  glm::uvec4 dispatch;  // xyz: work groups of this colour's pass (glDispatchComputeIndirect), w unused
  glm::ivec4 first;     // x: the colour's first entry in the block order
  glm::ivec4 count;     // w: its non-empty blocks
};
struct BlockTableHeader {
  BlockColor colors[kBlockColors];
  glm::ivec4 blocksPerAxis;  // xyz: blocks over the domain's nodes
};
static_assert(sizeof(BlockTableHeader) == kBlockColors * 48 + 16, "std430 BlockTable header");
constexpr std::size_t kBlockColorStride = sizeof(BlockColor);
// p2g_blocks.comp spends 1 + 4² loop iterations per particle, and llvmpipe ends a shader invocation's loops
// after 65,535 iterations in all (3,855 particles), so bin_scan.comp reports a fuller bin on watchdog overflow
// channel 7: 60 particles per cell of the block.
constexpr int kMaxBinParticles = 60 * kBlockCells * kBlockCells * kBlockCells;
constexpr std::uint32_t kBinOverflowChannel = 7;
// Per block after the header: uvec2 (first entry in BlockParticles, particle count).

// What the GPU watchdog saw; first events are recorded by the invocation that flips `...Where` from −1.
struct WatchdogStatus {
  std::uint32_t overflowCount;
  std::int32_t overflowNode;     // linear node index of the first overflow, −1 if none
  std::uint32_t overflowStep;
  std::uint32_t overflowChannel; // 0 mass, 1–3 momentum x/y/z, 4–6 impulse x/y/z
  std::uint32_t nonFiniteCount;
  std::int32_t nonFiniteParticle;
  std::uint32_t nonFiniteStep;
  std::uint32_t cflCount;
  std::int32_t cflParticle;
  std::uint32_t cflStep;
  float cflCellsPerStep;         // how far the first offending particle moved, in cells
  std::uint32_t maxSpeedBits;    // adaptive dt: the largest |v| + c (speed plus wave speed, m/s) this step, as float bits
};
static_assert(sizeof(WatchdogStatus) == 48, "std430 WatchdogStatus");

// std140 uniform block, rewritten before every step.
struct StepUniforms {
  glm::vec4 gridOriginCellSize;   // origin (m), h (m)
  glm::ivec4 gridNodes;           // nodes per axis, w unused
  glm::vec4 gravityDt;            // g (m/s²), Δt of this step (s)
  glm::vec4 fixedPoint;           // m_ref (kg), momentum unit m_ref·h/Δt_ref (kg·m/s), scale 2^k, 1/2^k
  glm::vec4 transfer;             // FLIP ratio α, simulated time at the start of the step (s), APIC D⁻¹ (1/m²), unused
  glm::uvec4 counts;              // particles, colliders, step index, unused
};
static_assert(sizeof(StepUniforms) == 96, "std140 StepUniforms");

}  // namespace firn::gpu
