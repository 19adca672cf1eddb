// The GPU contract: everything the host and the shaders share — binding points, work-group and block sizes,
// enum codes, the watchdog's overflow channels and the layout of every struct both sides read — written once,
// in the part of the preprocessor and of declarations that C++17 and GLSL 4.30 have in common.
//
// C++ reads it through engine/gpu/GpuLayout.h, inside namespace firn::gpu with glm's vector types; GLSL through
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

// What Firn requires of the driver (docs/platform.md, Limits). Each comment begins with the GL limit the number is
// held to: engine/gl/Limits.cpp reads these lines as plain numbers and refuses a driver with less (exit 4) when the
// context is made, before any program is built. Those beyond OpenGL 4.3's minimums can fall short on a conforming
// driver; those at the minimum are what every program must stay within. The binding ranges below must end within
// FIRN_REQUIRED_STORAGE_BINDINGS, and tests/gl/PortabilityTest.cpp holds every program Firn builds (as compiled by
// glslang) to the storage blocks, bindings, shared memory and work-group size stated here.
#define FIRN_REQUIRED_STORAGE_BINDINGS 32         // GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS (GL 4.3 guarantees 8)
#define FIRN_REQUIRED_COMPUTE_STORAGE_BLOCKS 16   // GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS (GL 4.3 guarantees 8)
#define FIRN_REQUIRED_VERTEX_STORAGE_BLOCKS 4     // GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS (GL 4.3 guarantees 0)
#define FIRN_REQUIRED_FRAGMENT_STORAGE_BLOCKS 0   // GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS (GL 4.3 guarantees 8)
#define FIRN_REQUIRED_COMPUTE_SHARED_MEMORY_BYTES 32768  // GL_MAX_COMPUTE_SHARED_MEMORY_SIZE (GL 4.3's minimum)
#define FIRN_REQUIRED_COMPUTE_INVOCATIONS 1024    // GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS (GL 4.3's minimum)

// Shader storage binding points, one buffer each. Each part of the GPU state owns a range of them, [FIRST, END),
// and publishes its buffers there (engine/sim/ParticleBuffers.h, BlockGrid.h, SolverState.h, GpuState.h; the
// surface's, shaders/surface/surface_contract.h); a program binds the blocks it declares before it runs
// (engine/gl/BufferBindings.h). engine/gpu/GpuLayout.h does not compile if two ranges overlap, a binding lies
// outside its part's range or shares a number with another, or the last range ends past
// FIRN_REQUIRED_STORAGE_BINDINGS.
// The particles (common/particles.glsl; the renderer reads them too).
#define FIRN_PARTICLE_BINDINGS_FIRST 0
#define FIRN_BINDING_POSITION_MASS 0        // vec4 per particle: x (m), mass (kg)
#define FIRN_BINDING_VELOCITY_VOLUME 1      // vec4 per particle: v (m/s), initial volume V0 (m³)
#define FIRN_BINDING_ELASTIC_DEFORMATION 2  // mat3 per particle: F (F_E for snow and sand)
#define FIRN_BINDING_KIRCHHOFF_STRESS 3     // mat3 per particle: τ = (∂Ψ/∂F_E) F_Eᵀ (Pa) of the last update
#define FIRN_BINDING_AFFINE 4               // mat3 per particle: APIC's C
#define FIRN_BINDING_PLASTIC_STATE 5        // ParticlePlasticState per particle
#define FIRN_PARTICLE_BINDINGS_END 6
// The block grid (common/blocks.glsl, common/grid.glsl): the pool of blocks, the map over the domain, and the
// particles sorted into the blocks' bins.
#define FIRN_GRID_BINDINGS_FIRST 6
#define FIRN_BINDING_GRID_MOMENTUM_MASS 6   // per node of the pool: momentum and mass sums, then velocity and mass
#define FIRN_BINDING_GRID_IMPULSE 7         // per node of the pool (PIC/FLIP): impulse sums, then velocity before forces
#define FIRN_BINDING_BLOCK_TABLE 8          // BlockTableHeader, then a BlockSlot per block of the pool
#define FIRN_BINDING_BLOCK_MAP 9            // uint per block of the domain: its slot in the pool + 1, or 0
#define FIRN_BINDING_BINS 10                // uvec2 per base node of each active block: particles, first (in block)
#define FIRN_BINDING_SORTED_PARTICLES 11    // uint per particle: particle indices, block after block, bin after bin
#define FIRN_BINDING_PARTICLE_RANKS 12      // uint per particle: its place in its bin; after the sort, the particles
                                            // whose stress mirror_stress.comp mirrors into a rigid body
#define FIRN_BINDING_TILE_ORDER 13          // uint per tile of the pool: the tiles holding particles, fullest first
#define FIRN_GRID_BINDINGS_END 14
// The scene's tables and the watchdog.
#define FIRN_TABLE_BINDINGS_FIRST 14
#define FIRN_BINDING_MATERIALS 14           // MaterialParams[]
#define FIRN_BINDING_COLLIDERS 15           // ColliderParams[]
#define FIRN_BINDING_WATCHDOG 16            // WatchdogStatus
#define FIRN_TABLE_BINDINGS_END 17
// The semi-implicit solve's (solver.integrator "semi_implicit" only; common/solver.glsl).
#define FIRN_SOLVER_BINDINGS_FIRST 17
#define FIRN_BINDING_SOLVER_NODES 17        // SolverNode per node of the pool: the conjugate residual method's vectors
#define FIRN_BINDING_SOLVER_PARTICLES 18    // SolverParticle per particle: its stiffness in the frame of F's SVD
#define FIRN_BINDING_SOLVER_STATUS 19       // SolverStatus, then a vec4 per slot of the pool: the blocks' partial sums
#define FIRN_BINDING_SOLVER_PRECONDITIONER 20  // SolverPreconditioner per node of the pool: P⁻¹'s 3×3 block there
#define FIRN_SOLVER_BINDINGS_END 21
// The rigid bodies' (scenes with rigid bodies; common/body_blocks.glsl).
#define FIRN_BODY_BINDINGS_FIRST 21
#define FIRN_BINDING_BODIES 21              // BodyContact per contact slot, then a BodyRecord per rigid body
#define FIRN_BODY_BINDINGS_END 22
// The snow's surface (shaders/surface/surface_contract.h declares its bindings).
#define FIRN_SURFACE_BINDINGS_FIRST 22
#define FIRN_SURFACE_BINDINGS_END 32
// Texture units: the mesh colliders' and bodies' distance fields and the bodies' contact probes, one float per
// texel of a buffer texture (common/colliders.glsl): a texture, so that the passes that meet colliders need no
// storage block more (llvmpipe holds a shader to 16, docs/platform.md).
#define FIRN_TEXTURE_UNIT_COLLIDER_FIELDS 0
// Uniform block binding points.
#define FIRN_BINDING_STEP_UNIFORMS 0        // StepUniforms
#define FIRN_BINDING_SURFACE_UNIFORMS 1     // SurfaceUniforms (surface_contract.h)
#define FIRN_BINDING_SURFACE_CASES 2        // the marching-cubes cases (surface_contract.h)

// Invocations per work group of the passes that run one invocation per particle, of those that run one per
// node of a block (BLOCK_NODES), and of the transfers, which run one per tile of base nodes (tiles of alike fill
// side by side: common/blocks.glsl).
#define FIRN_PARTICLE_GROUP_SIZE 128
#define FIRN_BLOCK_GROUP_SIZE 64  // BLOCK_NODES
#define FIRN_BLOCK_TILES 16       // BLOCK_TILES: order_tiles.comp takes a block's tiles
#define FIRN_TILE_GROUP_SIZE 16
// P2G by blocks (p2g_block.comp) runs 64, 128 or 256 invocations per work group, as the run's timing chose
// (engine/sim/TransferShape.h), given as a define; 256 where none is, the largest, for the checks of every program.
#ifndef FIRN_P2G_BLOCK_GROUP_SIZE
#define FIRN_P2G_BLOCK_GROUP_SIZE 256
#endif
// Invocations of the single work group that sums the blocks' partial sums of a dot product (solver_reduce.comp).
#define FIRN_REDUCTION_GROUP_SIZE 256

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
FIRN_CONSTANT(int, SHAPE_MESH, 3)  // a signed distance field baked from a triangle mesh (ColliderParams.field)
// A mesh's triangle in the field buffer: its corners a, b, c (from the pivot, m), the outward unit normals of its
// face, its edges ab, bc, ca and its corners a, b, c (ten vec3s), and the triangles beyond ab, bc, ca (−1: none).
FIRN_CONSTANT(int, FIELD_TRIANGLE_FLOATS, 33)
FIRN_CONSTANT(int, BOUNDARY_STICKY, 0)
FIRN_CONSTANT(int, BOUNDARY_SLIP, 1)
FIRN_CONSTANT(int, BOUNDARY_SEPARATE, 2)

// The P2G sums the watchdog names when one overflows (WatchdogStatus.overflowChannel): mass, momentum x/y/z,
// impulse x/y/z (PIC/FLIP), and a row of base nodes holding more particles than a transfer can take.
FIRN_CONSTANT(uint, CHANNEL_MASS, 0u)
FIRN_CONSTANT(uint, CHANNEL_MOMENTUM, 1u)
FIRN_CONSTANT(uint, CHANNEL_IMPULSE, 4u)
FIRN_CONSTANT(uint, CHANNEL_TILE, 7u)
FIRN_CONSTANT(uint, CHANNEL_SOLVER, 8u)  // the semi-implicit solve's Hessian product sums
FIRN_CONSTANT(uint, CHANNEL_COUNT, 9u)

// The block-sparse grid (common/blocks.glsl, docs/numerics.md): nodes are stored by blocks of BLOCK_WIDTH³,
// allocated each step where particles' stencils reach, from a pool of slots; a block's nodes are contiguous.
// Particles are sorted by the block and then the node their stencil starts at (their base node, its "bin").
// The transfers give each invocation a tile of TILE_WIDTH × TILE_HEIGHT base nodes (x, y: a block has
// BLOCK_TILES); a tile holds at most maxTileParticles (common/shared_functions.h), and a fuller one is reported on
// CHANNEL_TILE.
FIRN_CONSTANT(int, BLOCK_WIDTH, 4)
FIRN_CONSTANT(int, BLOCK_NODES, BLOCK_WIDTH * BLOCK_WIDTH * BLOCK_WIDTH)
FIRN_CONSTANT(int, TILE_WIDTH, BLOCK_WIDTH)
FIRN_CONSTANT(int, TILE_HEIGHT, 1)
FIRN_CONSTANT(int, TILE_BASE_NODES, TILE_WIDTH * TILE_HEIGHT)
FIRN_CONSTANT(int, BLOCK_TILES, BLOCK_NODES / TILE_BASE_NODES)  // FIRN_BLOCK_TILES
// The transfers take the tiles in order of fill, fullest first, in buckets of TILE_BUCKET_PARTICLES.
FIRN_CONSTANT(int, TILE_BUCKETS, 64)
FIRN_CONSTANT(uint, TILE_BUCKET_PARTICLES, 4u)

// ParticlePlasticState: the scalar state each material keeps besides F (common/materials.glsl); 1 for what a
// material does not use.
//   plasticJ          snow: J_P = det F_P; water: J = det F; sand: the hardening state q
//   materialIndex     into the material table (engine/gpu/Materials.h)
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

// The solves' sums over the nodes a body holds (BodyRecord.blockLow/High): 21 + 6 values in 7 vec4s, 2^−20 their
// unit.
#define COUPLING_WORDS 7
FIRN_CONSTANT(int, COUPLING_SUMS, 27)
FIRN_CONSTANT(int, COUPLING_FRACTION_BITS, 20)

// ColliderParams: one collider, a rigid motion of its shape at rest (common/colliders.glsl; docs/algorithm.md,
// Colliders). The host writes its pose at the start of the segment of motion that holds the step (for a collider
// without keyframes, at t = 0 for good); colliderDistance advances it rigidly by v and ω to the time it probes.
// The table holds the scene's colliders, then an entry per rigid body (docs/algorithm.md, Rigid bodies): the snow's
// passes meet a body as they meet a collider, by its entry, whose pose integrate_bodies.comp writes at the end of
// every step: its pivot is the body's centre of mass, its shape at rest is in the body's own frame. (The body's
// dynamics are its BodyRecord.)
//   shapeA            the shape at rest, from its pivot (m): plane: a point; sphere: the centre, w the radius;
//                     box: the centre; a rigid body's mesh: w the steepest slope of its field's interpolation
//                     within the lattice (|∇φ| ≤ w, from the samples; colliderSlope), a collider's 0
//   shapeB            plane: the unit normal; box: the half extents (m)
//   pivotTime         xyz where the pivot is (m) at the time w (s)
//   rotation          the turn from rest about the pivot at that time, a unit quaternion (xyz its vector part)
//   velocity          xyz the pivot's velocity v (m/s)
//   angularVelocity   xyz ω (rad/s), about the pivot
//   shapeBoundary     x SHAPE_*, y BOUNDARY_*, z: a rigid body's entry 1, else 0; w: a body that takes part 1, a
//                     parked one (the viewer's spare balls, out of the domain until thrown) 0
//   field             SHAPE_MESH: x the first of its samples in the field buffer, yzw the samples per axis; after
//                     the samples' φ, as many floats naming each sample's nearest triangle, then a record of
//                     FIELD_TRIANGLE_FLOATS per triangle (common/shared_functions.h, meshRestDistance)
//   fieldOrigin       SHAPE_MESH: xyz where sample (0, 0, 0) lies at rest, from the pivot (m); w the spacing (m)
//   contact           x Coulomb's μ; y the reach (m): the radius of a sphere about the pivot that holds the whole
//                     shape (a mesh's field lattice), or −1 for a plane (colliderWithinReach); z 1 where the object's
//                     load goes to bodies.csv (a rigid body, or a collider that moves: scene/SceneObjects.h,
//                     colliderMoves; gpu::ObjectLoad)
// A rigid body's entry also gathers the snow's push on it this step, which the passes that meet the snow's particles
// add to (G2P holds as many storage blocks as a pass may, 16, so the sums lie where it already reads the body's shape):
//   impulseLow/High   xyz Σ of the impulses the snow gave the body this step, 64-bit fixed point in units of
//                     momentumUnitKgMPerS · 2^−k, P2G's momentum units (common/fixed64.glsl)
//   angularLow/High   xyz Σ of their moments about the centre of mass, in units of momentumUnitKgMPerS · 2^−k · h
#define FIRN_COLLIDER_PARAMS(member, array) \
  member(vec4, shapeA)                      \
  member(vec4, shapeB)                      \
  member(vec4, pivotTime)                   \
  member(vec4, rotation)                    \
  member(vec4, velocity)                    \
  member(vec4, angularVelocity)             \
  member(ivec4, shapeBoundary)              \
  member(ivec4, field)                      \
  member(vec4, fieldOrigin)                 \
  member(vec4, contact)                     \
  member(uvec4, impulseLow)                 \
  member(ivec4, impulseHigh)                \
  member(uvec4, angularLow)                 \
  member(ivec4, angularHigh)
FIRN_STRUCT(ColliderParams, FIRN_COLLIDER_PARAMS)

// BlockTableHeader: the pool of blocks and this step's active ones (common/blocks.glsl); a BlockSlot per slot
// of the pool follows it.
//   blockCounts      x: blocks claimed this step (may exceed the capacity), y: the pool's capacity (host-written),
//                    z: blocks claimed last step, released at the start of this one, w: the most claimed in a step
//   blockDispatch    xyz: work groups of the per-block passes, one per active block (glDispatchComputeIndirect), but
//                    those of a step sorted for blocks, dispatched directly (common/blocks.glsl, workGroupCount)
//   blockRunDispatch xyz: work groups of the passes that take an invocation per active block, BLOCK_NODES each
//   releaseDispatch  xyz: work groups of the pass releasing last step's blocks, where the step sorts for tiles
//   tileCounts       x: tiles holding particles this step, y: particles in the sorted order
//   tileDispatch     xyz: work groups of the transfers, FIRN_TILE_GROUP_SIZE tiles each
//   mirrorBlocks     xyz: work groups of list_mirrored.comp, one per block list_mirror_blocks.comp listed (those
//                    whose particles may lie within a kernel's reach of a rigid body's surface); w: their number
//   mirrorDispatch   xyz: work groups of mirror_stress.comp, FIRN_PARTICLE_GROUP_SIZE invocations each; w: the
//                    particles within a kernel's reach of a rigid body's surface (listed in particleRanks)
//   migration        x: the particles list_leavers.comp listed (in particleRanks) as outside this process's slab
//   tileBuckets      per bucket of fill: its tiles, then its first entry in the tile order, then its next free one
#define FIRN_BLOCK_TABLE_HEADER(member, array) \
  member(uvec4, blockCounts)                   \
  member(uvec4, blockDispatch)                 \
  member(uvec4, blockRunDispatch)              \
  member(uvec4, releaseDispatch)               \
  member(uvec4, tileCounts)                    \
  member(uvec4, tileDispatch)                  \
  member(uvec4, mirrorBlocks)                  \
  member(uvec4, mirrorDispatch)                \
  member(uvec4, migration)                     \
  array(uint, tileBuckets, TILE_BUCKETS)
FIRN_STRUCT(BlockTableHeader, FIRN_BLOCK_TABLE_HEADER)

// BlockSlot: one slot of the pool, in use this step.
//   block            the block's linear index in the domain
//   firstParticle    its first particle in the sorted order
//   particles        its particles
//   mirrorBlock      the k-th slot's: the slot of the k-th block list_mirror_blocks.comp listed this step
//                    (k < BlockTableHeader.mirrorBlocks.w)
//   auditedElsewhere 1 where a share of the domain of a lower rank holds the block too (docs/distributed.md), which
//                    then counts what its nodes' collisions move: energy, the objects' loads, the rigid bodies' sums
//                    (common/energy.glsl, countedHere); 0 from its claim
//   claimedForImages 1 where no particle's stencil reached the block, only a particle's image in a rigid body
//                    (claim_image_blocks.comp: over several processes); 0 where a particle's stencil claimed it
#define FIRN_BLOCK_SLOT(member, array) \
  member(uint, block)                  \
  member(uint, firstParticle)          \
  member(uint, particles)              \
  member(uint, mirrorBlock)            \
  member(uint, auditedElsewhere)       \
  member(uint, claimedForImages)
FIRN_STRUCT(BlockSlot, FIRN_BLOCK_SLOT)

// The semi-implicit solve (common/solver.glsl, docs/numerics.md "The semi-implicit solve"): how a grid node's
// velocity is held by a collider or a domain wall, as bits of SolverNode.constraint.w. A wall holds one axis; a
// slip or separating collider the component along its normal; a sticky one, or a node without mass, all three.
FIRN_CONSTANT(int, CONSTRAINT_WALL_X, 1)
FIRN_CONSTANT(int, CONSTRAINT_NORMAL, 8)
FIRN_CONSTANT(int, CONSTRAINT_FIXED, 16)
// A node that one rigid body alone holds is an unknown of that body's in the solve: the body's index + 1 in the bits
// from CONSTRAINT_BODY_SHIFT up (0: no body's unknown).
FIRN_CONSTANT(int, CONSTRAINT_BODY_SHIFT, 5)
// The most conjugate residual iterations a step may take (solver.max_iterations), and the registers that hold
// each iteration's dot products.
FIRN_CONSTANT(int, SOLVER_MAX_ITERATIONS, 1000)
FIRN_CONSTANT(int, SOLVER_REGISTERS, SOLVER_MAX_ITERATIONS + 1)

// SolverNode: one node's vectors of the conjugate residual method (solver_*.comp), in its storage of the pool.
// The solution x, the node's velocity, stays in the grid's own storage (common/grid.glsl).
//   residual             xyz: r = S (M v* − A x) (kg·m/s), S the constraints' projection; w, at a node a collider
//                        holds along its normal n: the collider's normal impulse over the node's mass (m/s), the
//                        approach of v* it removed plus n·(A x − M v*) / m, the push the held component takes in the
//                        solve (solver_finish.comp's Coulomb friction)
//   preconditioned       z = P⁻¹ r (m/s), P the block Jacobi preconditioner (common/solver.glsl); before the first
//                        iteration v* − x₀, the first iteration's direction
//   product              xyz: A z (kg·m/s); w: n·(A z) before the projection, at a node held along n
//   direction            p (m/s); before the first iteration the start x₀, which the initial residual's product takes
//   directionProduct     xyz: A p (kg·m/s); w: n·(A p) before the projection, at a node held along n
//   constraint           xyz: the collider's unit normal (CONSTRAINT_NORMAL), w: CONSTRAINT_* bits
//   productLow/High      a Hessian product's sums, x y z as 64-bit integers (low and high words) in units of 2^−k_H
//                        of the momentum unit (StepUniforms.solver): exact, so the same whatever the order of the
//                        additions
//   diagonalLow/High     the first product's sums of β Δt² Hᵢᵢ, the Hessian's 3×3 block at the node: its diagonal
//                        (xyz), in units of 2^−k_H reference masses
//   offDiagonalLow/High  its entries yz, zx, xy
#define FIRN_SOLVER_NODE(member, array) \
  member(vec4, residual)                \
  member(vec4, preconditioned)          \
  member(vec4, product)                 \
  member(vec4, direction)               \
  member(vec4, directionProduct)        \
  member(vec4, constraint)              \
  member(uvec4, productLow)             \
  member(ivec4, productHigh)            \
  member(uvec4, diagonalLow)            \
  member(ivec4, diagonalHigh)           \
  member(uvec4, offDiagonalLow)         \
  member(ivec4, offDiagonalHigh)
FIRN_STRUCT(SolverNode, FIRN_SOLVER_NODE)

// SolverPreconditioner: P⁻¹'s 3×3 block at a node (common/solver.glsl), in a buffer of its own: the iterations' node
// passes read it with the first 128 bytes of the node's SolverNode, and no more.
//   inverseDiagonal      xyz: its diagonal (1/kg)
//   inverseOffDiagonal   xyz: its entries yz, zx, xy (1/kg)
#define FIRN_SOLVER_PRECONDITIONER(member, array) \
  member(vec4, inverseDiagonal)                   \
  member(vec4, inverseOffDiagonal)
FIRN_STRUCT(SolverPreconditioner, FIRN_SOLVER_PRECONDITIONER)

// BodyContact: a contact after the semi-implicit solve of a rigid body that held nodes in it with one that held none,
// as the last step left it: the next step's start (its warm start: docs/algorithm.md, Rigid bodies in the semi-implicit
// step; meet_bodies.comp, predict_bodies.comp, common/body_contacts.glsl). A slot per contact meet_bodies.comp visits,
// CONTACT_SLOTS of them, numbered in the order it visits them.
//   impulse   xyz the friction's total, w the normal's (kg·m/s), on the first body (the other takes the opposite)
//   normal    xyz the other body's outward unit normal there
//   key       x the first body's entry in the collider table, y its probe, z the other body's entry; w 1 where the
//             slot holds a contact, 0 where it holds none
FIRN_CONSTANT(int, CONTACT_SLOTS, 128)
#define FIRN_BODY_CONTACT(member, array) \
  member(vec4, impulse)                  \
  member(vec4, normal)                   \
  member(ivec4, key)
FIRN_STRUCT(BodyContact, FIRN_BODY_CONTACT)

// BodyRecord: a rigid body's dynamics (docs/algorithm.md, Rigid bodies; common/body_blocks.glsl) — its shape and
// pose are its entry of the collider table, which the snow's passes meet — and its six velocities u = (V, ω) as
// unknowns of the solves.
//   massRadius       x the mass (kg), y the contact radius of its probes (m: a sphere's radius, else 0)
//   probes           x the first of its contact probes in the field buffer (3 floats each, in its own frame, m),
//                    y their number
//   angularMomentum  xyz L about the centre of mass (kg·m²/s, world axes)
//   inverseInertia   the columns of I⁻¹ in the body's own frame (1/(kg·m²))
//   freeVelocity     xyz the body's velocity before the explicit step's coupled solve, V* (m/s), or the semi-implicit
//                    solve's u (solver_bodies_finish.comp), which the snow's impulses after the solve add to
//                    (predict_bodies.comp, integrate_bodies.comp)
//   freeAngularVelocity  xyz its ω* before the solve (rad/s): a separating body's nodes are held where they approach
//                    its surface moving so
// The semi-implicit solve's vectors, as a node's (SolverNode; common/solver_bodies.glsl; docs/algorithm.md, Rigid
// bodies in the semi-implicit step): [0] the linear part, [1] the angular part.
//   velocity, direction, preconditioned   x_b (the solution), p, z = P_b⁻¹ r: V (m/s) and ω (rad/s)
//   residual, product, directionProduct   r, A z, A p: force-like (kg·m/s) and moment-like (kg·m²/s) parts
//   inverse          P_b⁻¹, the inverse of the body's 6×6 preconditioner block, row after row (36 values); in the
//                    explicit step K⁻¹ of its coupled solve (common/body_blocks.glsl), the only solve member that step
//                    uses with velocity[0].w: 1 where the body holds a node (solve_coupling.comp; in the semi-implicit
//                    step solver_bodies_residual.comp), else 0
//   sumsLow/High     Σ Gᵢᵀ Pᵢ wᵢ over the nodes it holds, wᵢ a product's held part ([0] the force, [1] its moment
//                    about the centre of mass), 64-bit fixed point in 2^−k_H of the momentum unit (× h for [1])
//   blockLow/High    the solve's sums over the nodes it holds, 64-bit fixed point in 2^−COUPLING_FRACTION_BITS of
//                    P2G's nondimensional units (mass m_ref, length h, time Δt_ref): the upper triangle of its block,
//                    row by row (21 values), Σ Gᵢᵀ Pᵢ (mᵢ + β Δt² Hᵢᵢ) Pᵢ Gᵢ in the semi-implicit step
//                    (solver_bodies_residual.comp) and Σ m Gᵀ P G in the explicit step's coupled solve, which then also
//                    sums Σ m Gᵀ P v (6: docs/algorithm.md, eq. 39; update_grid.comp, solve_coupling.comp)
#define FIRN_BODY_RECORD(member, array) \
  member(vec4, massRadius)              \
  member(ivec4, probes)                 \
  member(vec4, angularMomentum)         \
  array(vec4, inverseInertia, 3)        \
  member(vec4, freeVelocity)            \
  member(vec4, freeAngularVelocity)     \
  array(vec4, velocity, 2)              \
  array(vec4, residual, 2)              \
  array(vec4, preconditioned, 2)        \
  array(vec4, product, 2)               \
  array(vec4, direction, 2)             \
  array(vec4, directionProduct, 2)      \
  array(vec4, inverse, 9)               \
  array(uvec4, sumsLow, 2)              \
  array(ivec4, sumsHigh, 2)             \
  array(uvec4, blockLow, COUPLING_WORDS) \
  array(ivec4, blockHigh, COUPLING_WORDS)
FIRN_STRUCT(BodyRecord, FIRN_BODY_RECORD)

// SolverParticle: a particle's stiffness ∂²Ψ/∂F² in the frame of its F = U Σ Vᵀ, made positive semi-definite
// (material_hessians.glsl), so that the iterations' products need no SVD. Computed once per step
// (solver_prepare.comp).
//   left                 U
//   singularValues       xyz: σ (signed: σ₃ < 0 for an inverted F)
//   scalingDiagonal      xyz: ∂²Ψ/∂σᵢ² (projected with the off-diagonal: the 3×3 block of δF̂'s diagonal)
//   scalingOffDiagonal   xyz: ∂²Ψ/∂σ₂∂σ₃, ∂²Ψ/∂σ₃∂σ₁, ∂²Ψ/∂σ₁∂σ₂
//   pairSame, pairCross  xyz, for the pairs of axes other than 1, 2, 3: the 2×2 block [[a, b], [b, a]] on
//                        (δF̂ᵢⱼ, δF̂ⱼᵢ), a and b
//   blockCoupling        xyz: ∂²Ψ/∂σⱼ∂σₖ + b of the pair (j, k), for (2, 3), (3, 1), (1, 2): what couples two
//                        axes in the particle's share of H's 3×3 block at a node (stiffnessBlock); w: 2μ + λ (Pa),
//                        the scale of its stress's rounding
#define FIRN_SOLVER_PARTICLE(member, array) \
  member(mat3, left)                        \
  member(vec4, singularValues)              \
  member(vec4, scalingDiagonal)             \
  member(vec4, scalingOffDiagonal)          \
  member(vec4, pairSame)                    \
  member(vec4, pairCross)                   \
  member(vec4, blockCoupling)
FIRN_STRUCT(SolverParticle, FIRN_SOLVER_PARTICLE)

// SolverStatus: the solve's progress in this step. The passes of an iteration are dispatched from here, and once
// the residual is below the tolerance their records hold no work groups: what is left of the iterations the host
// dispatched before its next look costs nothing.
//   solveBlockDispatch    xyz: work groups of the per-node passes (the block table's, or none)
//   solveProductDispatch  xyz: of the Hessian product, a transfer over tiles
//   solveReduceDispatch   xyz: of the dot products' sums (one group, or none)
//   solveEnd              x: 1 + the register whose residual ended the solve (met the tolerance, or was NaN); 0
//                         while it runs
//   roundingStiffness     x: the least V⁰ (2μ + λ) of the step's particles (N·m), as float bits: the scale of the
//                         rounding floor under the tolerance (solver_residual.comp)
//   registers             per iteration k: x (z, A z)_k, y (A p, P⁻¹ A p)_k, z (r, P⁻¹ r)_k after k iterations,
//                         w (M v*, (M + β Δt² Hᵢᵢ)⁻¹ M v*) (k = 0 only): the tolerance's reference
//                         (solver_residual.comp, solver_reduce.comp)
#define FIRN_SOLVER_STATUS(member, array) \
  member(uvec4, solveBlockDispatch)       \
  member(uvec4, solveProductDispatch)     \
  member(uvec4, solveReduceDispatch)      \
  member(uvec4, solveEnd)                 \
  member(uvec4, roundingStiffness)        \
  array(vec4, registers, SOLVER_REGISTERS)
FIRN_STRUCT(SolverStatus, FIRN_SOLVER_STATUS)

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

// EnergyLedger: the energy audit's sums (common/energy.glsl, docs/numerics.md "The energy audit"), in the watchdog's
// buffer after its WatchdogStatus: the passes that collide nodes and particles have that buffer bound already, and
// llvmpipe holds a shader to 16 storage blocks (docs/platform.md). Each sum is a 64-bit integer (low, high words:
// common/fixed64.glsl), exact and so independent of the order of the GPU's additions; energies are in units of
// 1 / StepUniforms.energyUnitsPerJ. The host empties the ledger at the end of every frame it accepts
// (Simulation::checkWatchdog).
//   stateLow/High   what audit_energy.comp summed over the particles: x kinetic (APIC: with its affine part),
//                   y gravitational potential above the domain's floor, z elastic strain energy Σ V⁰ ψ(F_E),
//                   w the explicit step's energy term −(Δt/2) Σ V⁰ τ : ∇v, what the energy shown at a step's end
//                   differs by from the modified energy symplectic Euler keeps (docs/numerics.md)
//   counts          x the values left out of any sum for passing StepUniforms.particleEnergyLimit
//   flowLow/High    what the frame's steps moved in and out of the snow: x the work of moving colliders on the snow and
//                   on the rigid bodies, y the kinetic energy the domain walls removed from particles, z the energy the
//                   rigid bodies' explicit coupling made (the push's second order, the images' work: mirror_stress.comp),
//                   w the energy snow's hardening gave the strain it holds
//                   (docs/numerics.md): summed at the nodes and particles the collisions changed, the particles whose
//                   J_P changed, and by integrate_bodies.comp
#define FIRN_ENERGY_LEDGER(member, array) \
  member(uvec4, stateLow)                 \
  member(ivec4, stateHigh)                \
  member(uvec4, flowLow)                  \
  member(ivec4, flowHigh)                 \
  member(uvec4, counts)
FIRN_STRUCT(EnergyLedger, FIRN_ENERGY_LEDGER)

// ObjectLoad: what one moving collider or rigid body did to the snow since the frame began (bodies.csv's force and
// work), one per entry of the collider table, after the ledger in the watchdog's buffer (common/energy.glsl). 64-bit
// integers, summed at every node and particle the object's response changed.
//   low/high   xyz the impulse the object gave the snow, in units of 2^−24 m_ref h / s, w the work it did on the snow,
//              in the energy ledger's units
#define FIRN_OBJECT_LOAD(member, array) \
  member(uvec4, low)                    \
  member(ivec4, high)
FIRN_STRUCT(ObjectLoad, FIRN_OBJECT_LOAD)

// StepUniforms: the uniform block written before every step (std140, 144 bytes: each 16 bytes a vec3 and a scalar, or
// four scalars, so that std140 and C++ place every member alike).
//   gridOriginM, cellSizeM         the grid's origin and cell size h (m)
//   gridNodes, particleCount       nodes per axis; the live particles
//   gravityMPerS2, dtS             g (m/s²); Δt of this step (s)
//   timeS                          the simulated time at the start of the step (s)
//   flipRatio                      PIC/FLIP's α
//   apicInverseInertiaPerM2        APIC's D⁻¹ (1/m²)
//   stepIndex                      the steps taken before this one
//   referenceMassKg                the fixed-point mass unit m_ref (docs/numerics.md)
//   momentumUnitKgMPerS            the fixed-point momentum unit m_ref·h/Δt_ref: Δt_ref is the scene's dt, or with
//                                  adaptive steps this step's (sim/StepPipeline.cpp)
//   fixedPointFractionBits         k: a nondimensional 1 is stored as 2^k (common/grid.glsl takes 2^±k by ldexp)
//   colliderCount                  the collider table's entries: the scene's colliders, then rigidBodyCount bodies
//   implicitRatio, solverToleranceSquared   semi-implicit: β and the tolerance²
//   solverFractionBits             semi-implicit: k_H, the units 2^−k_H of SolverNode.productLow/High
//   rigidBodyCount                 the rigid bodies, the collider table's last entries
//   cellsPerM, massUnitsPerKg, momentumUnitsPerKgMPerS, impulseUnitsPerPaM3
//                                  1 / h, 1 / m_ref, 1 / the momentum unit and −Δt / the momentum unit, divided on
//                                  the host: a GLSL division may be 2.5 ulp off and need not round alike in two
//                                  programs (an NVIDIA driver's did not), where a product is exact to the ulp; every
//                                  pass then finds a particle in the same cell, and P2G's two shapes add the same bits
//   potentialFloorM                the point of the domain lowest along gravity, from which the energy audit
//                                  measures the gravitational potential −m g·(x − floor) (common/energy.glsl)
//   energyUnitsPerJ                the energy ledger's units per joule (EnergyLedger), 2^54 / the scene's energy bound
//                                  (sim/EnergyAudit.cpp)
//   particleEnergyLimit            the most energy units one particle may hold in a sum: 2^62 over the particle
//                                  capacity, so that no sum of all particles leaves 64 bits
//   apicInertiaM2                  APIC's D (m²), the inverse of apicInverseInertiaPerM2, for the affine kinetic energy
#define FIRN_STEP_UNIFORMS(member, array)  \
  member(vec3, gridOriginM)                \
  member(float, cellSizeM)                 \
  member(ivec3, gridNodes)                 \
  member(uint, particleCount)              \
  member(vec3, gravityMPerS2)              \
  member(float, dtS)                       \
  member(float, timeS)                     \
  member(float, flipRatio)                 \
  member(float, apicInverseInertiaPerM2)   \
  member(uint, stepIndex)                  \
  member(float, referenceMassKg)           \
  member(float, momentumUnitKgMPerS)       \
  member(int, fixedPointFractionBits)      \
  member(uint, colliderCount)              \
  member(float, implicitRatio)             \
  member(float, solverToleranceSquared)    \
  member(int, solverFractionBits)          \
  member(uint, rigidBodyCount)             \
  member(float, cellsPerM)                 \
  member(float, massUnitsPerKg)            \
  member(float, momentumUnitsPerKgMPerS)   \
  member(float, impulseUnitsPerPaM3)      \
  member(vec3, potentialFloorM)            \
  member(float, energyUnitsPerJ)           \
  member(float, particleEnergyLimit)       \
  member(float, apicInertiaM2)             \
  member(uint, unusedUniform0)             \
  member(uint, unusedUniform1)
FIRN_STRUCT(StepUniforms, FIRN_STEP_UNIFORMS)

#endif
