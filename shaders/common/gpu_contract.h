// The GPU contract: everything the host and the shaders share — binding points, work-group and block sizes,
// enum codes, the watchdog's overflow channels and the layout of every struct both sides read — written once,
// in the part of the preprocessor and of declarations that C++17 and GLSL 4.30 have in common.
//
// C++ reads it through engine/sim/GpuLayout.h, inside namespace firn::gpu with glm's vector types; GLSL through
// common/bindings.glsl. Each struct is described once, as a member list (an "X-macro": a macro that applies its
// argument to every member), from which FIRN_STRUCT declares the struct in either language, a shader block can
// declare the members loose (FIRN_MEMBERS), and tests/gl/GpuContractTest.cpp checks every member's offset, as
// the driver reports it, against the C++ layout. Buffers are std430, the step's uniform block std140; members
// are vec4-sized so that both rules give the C++ layout.
//
// Binding points and work-group sizes are macros because GLSL 4.30 takes only literals in layout qualifiers.
#ifndef FIRN_GPU_CONTRACT_H
#define FIRN_GPU_CONTRACT_H

#ifdef __cplusplus
#define FIRN_CONSTANT(type, name, value) constexpr type name = value;
#else
#define FIRN_CONSTANT(type, name, value) const type name = value;
#endif

#define FIRN_DECLARE_MEMBER(type, name) type name;
#define FIRN_DECLARE_ARRAY(type, name, count) type name[count];
#define FIRN_MEMBERS(list) list(FIRN_DECLARE_MEMBER, FIRN_DECLARE_ARRAY)
#define FIRN_STRUCT(name, list) struct name { FIRN_MEMBERS(list) };

// Shader storage binding points, one buffer each.
#define FIRN_BINDING_POSITION_MASS 0        // vec4 per particle: x (m), mass (kg)
#define FIRN_BINDING_VELOCITY_VOLUME 1      // vec4 per particle: v (m/s), initial volume V0 (m³)
#define FIRN_BINDING_ELASTIC_DEFORMATION 2  // mat3 per particle: F (F_E for snow and sand)
#define FIRN_BINDING_KIRCHHOFF_STRESS 3     // mat3 per particle: τ = (∂Ψ/∂F_E) F_Eᵀ (Pa) of the last update
#define FIRN_BINDING_AFFINE 4               // mat3 per particle: APIC's C
#define FIRN_BINDING_PLASTIC_STATE 5        // ParticlePlasticState per particle
#define FIRN_BINDING_GRID_MOMENTUM_MASS 6   // per node: momentum and mass sums, then velocity and mass
#define FIRN_BINDING_GRID_IMPULSE 7         // per node (PIC/FLIP): impulse sums, then the velocity before forces
#define FIRN_BINDING_MATERIALS 8            // MaterialParams[]
#define FIRN_BINDING_COLLIDERS 9            // ColliderParams[]
#define FIRN_BINDING_ACTIVE_REGION 10       // ActiveRegionData
#define FIRN_BINDING_WATCHDOG 11            // WatchdogStatus
#define FIRN_BINDING_BLOCKS 12              // BlockTableHeader, then a bin per block (solver.atomics "none")
#define FIRN_BINDING_PARTICLE_SLOTS 13      // uint per particle: its place within its block's bin
#define FIRN_BINDING_BLOCK_PARTICLES 14     // uint per particle: particle indices, bin after bin
#define FIRN_BINDING_BLOCK_ORDER 15         // uint per block: each colour's non-empty blocks, fullest first
// Uniform block binding point.
#define FIRN_BINDING_STEP_UNIFORMS 0        // StepUniforms

// Invocations per work group of the passes that run one invocation per particle.
#define FIRN_PARTICLE_GROUP_SIZE 128

// Material models (MaterialParams.model.x).
FIRN_CONSTANT(int, MODEL_SNOW, 0)
FIRN_CONSTANT(int, MODEL_FIXED_COROTATED, 1)
FIRN_CONSTANT(int, MODEL_NEO_HOOKEAN, 2)
FIRN_CONSTANT(int, MODEL_WATER, 3)
FIRN_CONSTANT(int, MODEL_DRUCKER_PRAGER, 4)

// Collider shapes (ColliderParams.shapeBoundary.x) and boundary conditions (.y).
FIRN_CONSTANT(int, SHAPE_PLANE, 0)
FIRN_CONSTANT(int, SHAPE_SPHERE, 1)
FIRN_CONSTANT(int, SHAPE_BOX, 2)
FIRN_CONSTANT(int, BOUNDARY_STICKY, 0)
FIRN_CONSTANT(int, BOUNDARY_SLIP, 1)
FIRN_CONSTANT(int, BOUNDARY_SEPARATE, 2)

// The P2G sums the watchdog names when one overflows (WatchdogStatus.overflowChannel): mass, momentum x/y/z,
// impulse x/y/z (PIC/FLIP), and a bin too full for P2G without atomics.
FIRN_CONSTANT(uint, CHANNEL_MASS, 0u)
FIRN_CONSTANT(uint, CHANNEL_MOMENTUM, 1u)
FIRN_CONSTANT(uint, CHANNEL_IMPULSE, 4u)
FIRN_CONSTANT(uint, CHANNEL_BIN, 7u)
FIRN_CONSTANT(uint, CHANNEL_COUNT, 8u)

// P2G without atomics (solver.atomics "none", common/blocks.glsl): particles are binned into blocks of
// BLOCK_CELLS³ cells, and the blocks of one colour (the parities of their coordinates, BLOCK_COLORS of them) lie
// too far apart to reach one node. BLOCK_CELLS > 2: a particle in cell c reaches nodes c − 1 … c + 2 with either
// kernel. p2g_blocks.comp spends 1 + 4² loop iterations per particle, and llvmpipe ends a shader invocation's
// loops after 65,535 iterations in all (docs/platform.md), so a fuller bin than MAX_BIN_PARTICLES (60 per cell)
// is reported on CHANNEL_BIN.
FIRN_CONSTANT(int, BLOCK_CELLS, 4)
FIRN_CONSTANT(int, BLOCK_COLORS, 8)
FIRN_CONSTANT(int, MAX_BIN_PARTICLES, 60 * BLOCK_CELLS * BLOCK_CELLS * BLOCK_CELLS)

// ParticlePlasticState: the scalar state each material keeps besides F (common/materials.glsl); 1 for what a
// material does not use.
//   plasticJ          snow: J_P = det F_P; water: J = det F; sand: the hardening state q
//   materialIndex     into the material table (engine/sim/Materials.h)
//   volumeCorrection  sand: the log-volume correction V_c (Klár et al. 2016)
#define FIRN_PARTICLE_PLASTIC_STATE(member, array) \
  member(float, plasticJ)                          \
  member(uint, materialIndex)                      \
  member(float, volumeCorrection)                  \
  member(float, unused)
FIRN_STRUCT(ParticlePlasticState, FIRN_PARTICLE_PLASTIC_STATE)

// MaterialParams: one entry of the material table.
//   elastic  μ0 (Pa), λ0 (Pa), snow's hardening ξ, density ρ (kg/m³)
//   plastic  snow: 1 − θc, 1 + θs; sand: h0, h1 (rad), h2, h3 (rad)
//   fluid    water: bulk modulus k (Pa), γ, viscosity (Pa·s)
//   model    x: MODEL_*
#define FIRN_MATERIAL_PARAMS(member, array) \
  member(vec4, elastic)                     \
  member(vec4, plastic)                     \
  member(vec4, fluid)                       \
  member(ivec4, model)
FIRN_STRUCT(MaterialParams, FIRN_MATERIAL_PARAMS)

// ColliderParams: one collider, translating at its velocity (common/colliders.glsl).
//   geometryA         plane: a point; sphere: the centre, w the radius (m); box: the min corner (m), at t = 0
//   geometryB         plane: the unit normal; box: the max corner (m), at t = 0
//   velocityFriction  xyz the velocity (m/s), w Coulomb's μ
//   shapeBoundary     x SHAPE_*, y BOUNDARY_*
#define FIRN_COLLIDER_PARAMS(member, array) \
  member(vec4, geometryA)                   \
  member(vec4, geometryB)                   \
  member(vec4, velocityFriction)            \
  member(ivec4, shapeBoundary)
FIRN_STRUCT(ColliderParams, FIRN_COLLIDER_PARAMS)

// ActiveRegionData: the grid region the particles occupy. G2P accumulates the particles' cell bounds;
// prepare_grid.comp turns them into this step's node box and the indirect dispatch of the grid passes.
// Particles added between steps (emitters, the viewer's snowballs) took no part in the last G2P: the host
// writes their cell bounds to `added…`, which prepare_grid merges in, so adding particles needs no readback.
//   particleCellMin/Max  atomicMin/atomicMax of the particles' cells
//   boxMin, boxSize      the first node of the box; nodes per axis, w the node count
//   gridDispatch         work groups of the grid passes (glDispatchComputeIndirect reads xyz)
//   addedCellMin/Max     cells of the particles added since the last step
#define FIRN_ACTIVE_REGION_DATA(member, array) \
  member(ivec4, particleCellMin)               \
  member(ivec4, particleCellMax)               \
  member(ivec4, boxMin)                        \
  member(ivec4, boxSize)                       \
  member(uvec4, gridDispatch)                  \
  member(ivec4, addedCellMin)                  \
  member(ivec4, addedCellMax)
FIRN_STRUCT(ActiveRegionData, FIRN_ACTIVE_REGION_DATA)

// BlockColor: one colour's pass of P2G without atomics.
//   dispatch  xyz work groups (glDispatchComputeIndirect)
//   first     x the colour's first entry in the block order
//   count     w its non-empty blocks
#define FIRN_BLOCK_COLOR(member, array) \
  member(uvec4, dispatch)               \
  member(ivec4, first)                  \
  member(ivec4, count)
FIRN_STRUCT(BlockColor, FIRN_BLOCK_COLOR)

// The head of the block table (bin_scan.comp writes it); a bin per block of the domain follows, uvec2 (first
// entry in the block particles, particle count).
//   blockColors    each colour's pass
//   blocksPerAxis  xyz blocks over the domain's nodes
#define FIRN_BLOCK_TABLE_HEADER(member, array) \
  array(BlockColor, blockColors, BLOCK_COLORS) \
  member(ivec4, blocksPerAxis)
FIRN_STRUCT(BlockTableHeader, FIRN_BLOCK_TABLE_HEADER)

// WatchdogStatus: what the GPU watchdog saw (common/watchdog.glsl). The first event of each kind is recorded by
// the invocation that flips its `…Node`/`…Particle` field from −1.
//   overflow…      fixed-point overflows: count, linear node index, step, CHANNEL_*
//   nonFinite…     particles that became NaN or Inf: count, particle, step
//   cfl…           particles that moved more than a cell in a step: count, particle, step, cells moved
//   maxSpeedBits   adaptive steps: the largest |v| + c of the step (m/s), as float bits
#define FIRN_WATCHDOG_STATUS(member, array) \
  member(uint, overflowCount)               \
  member(int, overflowNode)                 \
  member(uint, overflowStep)                \
  member(uint, overflowChannel)             \
  member(uint, nonFiniteCount)              \
  member(int, nonFiniteParticle)            \
  member(uint, nonFiniteStep)               \
  member(uint, cflCount)                    \
  member(int, cflParticle)                  \
  member(uint, cflStep)                     \
  member(float, cflCellsPerStep)            \
  member(uint, maxSpeedBits)
FIRN_STRUCT(WatchdogStatus, FIRN_WATCHDOG_STATUS)

// StepUniforms: the uniform block written before every step.
//   gridOriginCellSize  origin (m), h (m)
//   gridNodes           nodes per axis
//   gravityDt           g (m/s²), Δt of this step (s)
//   fixedPoint          m_ref (kg), the momentum unit m_ref·h/Δt_ref (kg·m/s), 2^k, 2^−k (docs/numerics.md)
//   transfer            FLIP ratio α, the simulated time at the start of the step (s), APIC's D⁻¹ (1/m²)
//   counts              particles, colliders, step index
#define FIRN_STEP_UNIFORMS(member, array) \
  member(vec4, gridOriginCellSize)        \
  member(ivec4, gridNodes)                \
  member(vec4, gravityDt)                 \
  member(vec4, fixedPoint)                \
  member(vec4, transfer)                  \
  member(uvec4, counts)
FIRN_STRUCT(StepUniforms, FIRN_STEP_UNIFORMS)

#endif
