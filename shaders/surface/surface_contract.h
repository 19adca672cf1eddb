// The surface reconstruction's GPU contract (engine/surface, docs/surfaces.md): binding points, sizes, the structs
// the host and the shaders share, and the functions both evaluate — the kernel and the numbering of a cell's
// corners and edges — written once in the part of C++17 and GLSL 4.30 they have in common, as the simulation's
// common/gpu_contract.h and common/shared_functions.h are. C++ reads it through engine/surface/SurfaceLayout.h;
// tests/gl/SurfaceTest.cpp checks the structs' offsets against the driver's.
#ifndef FIRN_SURFACE_CONTRACT_H
#define FIRN_SURFACE_CONTRACT_H

#include "common/shared_functions.h"

// Shader storage binding points, in the surface's range of the GPU contract (common/gpu_contract.h:
// FIRN_SURFACE_BINDINGS_FIRST to _END); engine/surface/SurfaceLayout.h holds them to it.
#define FIRN_BINDING_SURFACE_HEADER 22           // SurfaceHeader: the particles' kernel bounds
#define FIRN_BINDING_SURFACE_DENSITY 23          // int per node: the volume fraction, fixed point
#define FIRN_BINDING_SURFACE_SUMS 24             // SurfaceNodeSums per node: Σ weight · albedo, Σ weight · v
#define FIRN_BINDING_SURFACE_CELLS 25            // uint per node: its cell's case, the crossings of its own edges
#define FIRN_BINDING_SURFACE_COUNTS 26           // uvec2 per node (+1): vertices and triangles, then their offsets
#define FIRN_BINDING_SURFACE_VERTICES 27         // SurfaceVertex per vertex of the mesh
#define FIRN_BINDING_SURFACE_INDICES 28          // uint per triangle corner
#define FIRN_BINDING_SURFACE_MATERIALS 29        // vec4 per entry of the material table: x 1 / rest density (m³/kg)
#define FIRN_BINDING_SURFACE_PARTICLE_COLORS 30  // vec4 per particle: the linear albedo to carry onto the surface
// The prefix scan's (PrefixScan): it scans the counts in place, so its values are bound where the counts are (the
// levels above them too, for its own passes).
#define FIRN_BINDING_SCAN_VALUES FIRN_BINDING_SURFACE_COUNTS  // uvec2 per element: an exclusive prefix sum, in place
#define FIRN_BINDING_SCAN_SUMS 31                // uvec2 per chunk of SCAN_CHUNK elements
// The marching-cubes cases (uvec4 per case, engine/surface/MarchingCubes.h) are a uniform block, at
// FIRN_BINDING_SURFACE_CASES: 4 KiB, read by every cell, and one storage binding fewer.
FIRN_CONSTANT(int, MARCHING_CUBES_CASES, 256)

// The volume fraction is summed in fixed point with 2^20 units per unit, as the simulation's P2G sums are
// (docs/numerics.md, Fixed-point atomics): integer sums do not depend on the order of the additions, so the
// field, and the mesh made from it, are the same bytes from run to run. A node's sum overflows at 2^31 / 2^20 =
// 2048, a compaction snow never reaches; one particle adds at most 8 / (π smoothing³) ≤ 0.32 (smoothing ≥ 2).
FIRN_CONSTANT(float, SURFACE_UNITS_PER_VALUE, 1048576.0f)
// A prefix scan sums chunks of this many elements per invocation (engine/surface/PrefixScan.h).
FIRN_CONSTANT(uint, SCAN_CHUNK, 64u)
// The widest kernel, in reconstruction cells (radius): a particle's splat visits (2 · 12 + 1)³ = 15,625 nodes,
// well inside llvmpipe's 65,535 loop iterations per invocation (docs/platform.md, The loop limit).
FIRN_CONSTANT(float, MAX_KERNEL_RADIUS_CELLS, 12.0f)
// The most triangles marching cubes makes in one cell (MarchingCubes.cpp builds its table within it): a case's
// edges, 3 per triangle, are packed as 4-bit nibbles, 8 per uint, into the y and z of its uvec4.
FIRN_CONSTANT(int, MAX_CELL_TRIANGLES, 5)

// SurfaceUniforms: one reconstruction, written before its passes (std140, 64 bytes).
//   latticeOriginM, nodeSpacingM   the point of node (0, 0, 0) of the lattice all frames share (the domain's origin,
//                                  m), and the node spacing h_r = h / surface.resolution (m)
//   firstNode, nodeCount           the lattice index of this frame's first node (its box follows the particles); all
//                                  of its nodes
//   boxNodes, reconstructedParticles   its nodes per axis; the particles it is built from
//   smoothing, isoLevel, isoUnits  surface.smoothing (in particle spacings), surface.iso, iso in fixed-point units
//   sumsCarried                    what the nodes sum besides the field: SURFACE_SUMS_COLOR, SURFACE_SUMS_VELOCITY
#define FIRN_SURFACE_UNIFORMS(member, array) \
  member(vec3, latticeOriginM)               \
  member(float, nodeSpacingM)                \
  member(ivec3, firstNode)                   \
  member(uint, nodeCount)                    \
  member(ivec3, boxNodes)                    \
  member(uint, reconstructedParticles)       \
  member(float, smoothing)                   \
  member(float, isoLevel)                    \
  member(int, isoUnits)                      \
  member(uint, sumsCarried)
FIRN_STRUCT(SurfaceUniforms, FIRN_SURFACE_UNIFORMS)

// SurfaceHeader: what the bounds pass finds (std430): the lowest and highest lattice node any particle's kernel
// reaches (host-initialised to the extremes of int).
#define FIRN_SURFACE_HEADER(member, array) \
  member(ivec4, kernelNodesMin)            \
  member(ivec4, kernelNodesMax)
FIRN_STRUCT(SurfaceHeader, FIRN_SURFACE_HEADER)

// What a node sums besides the volume fraction, as bits of SurfaceUniforms.sumsCarried.
FIRN_CONSTANT(uint, SURFACE_SUMS_COLOR, 1u)
FIRN_CONSTANT(uint, SURFACE_SUMS_VELOCITY, 2u)

// SurfaceNodeSums: what a node sums besides the volume fraction (std430), fixed point as it is, each only when the
// reconstruction asks for it (SurfaceUniforms.sumsCarried).
//   color     xyz Σ_p V_p W · albedo_p (the particles' linear albedo), w unused
//   velocity  xyz Σ_p V_p W · v_p (m/s): divided by f, the snow's velocity there; w unused. A node's sum
//             overflows at |Σ V W v| = 2048 m/s, f times the speed: beyond any snow the simulation's CFL bound
//             lets run (a particle crossing more than a cell per step stops the run)
#define FIRN_SURFACE_NODE_SUMS(member, array) \
  member(ivec4, color)                        \
  member(ivec4, velocity)
FIRN_STRUCT(SurfaceNodeSums, FIRN_SURFACE_NODE_SUMS)

// SurfaceVertex: one vertex of the mesh (std430), on an edge of the grid where the field crosses the iso level.
//   positionM  xyz (m), w 1
//   normal     xyz unit, out of the snow (down the field's gradient), w 0
//   albedo     xyz the linear albedo interpolated from the particles' colours (1 without them), w 1
//   velocity   xyz the snow's velocity (m/s) interpolated from the particles' (0 without them), w 0
#define FIRN_SURFACE_VERTEX(member, array) \
  member(vec4, positionM)                  \
  member(vec4, normal)                     \
  member(vec4, albedo)                     \
  member(vec4, velocity)
FIRN_STRUCT(SurfaceVertex, FIRN_SURFACE_VERTEX)

// The smoothing kernel: Monaghan's cubic spline (M4) with support radius 1, normalised over the unit ball,
// w(q) = 8/π (1 − 6q² + 6q³) for q ≤ ½, 16/π (1 − q)³ for ½ < q ≤ 1, 0 beyond (Monaghan 2005, "Smoothed particle
// hydrodynamics", eq. 2.6 with h = ½). A particle's kernel of radius R is w(r / R) / R³.
FIRN_FUNCTION float smoothingKernel(float q) {
  const float normalisation = 2.546479089f;  // 8 / π
  if (q <= 0.5f) return normalisation * (1.0f - 6.0f * q * q + 6.0f * q * q * q);
  if (q < 1.0f) return normalisation * 2.0f * (1.0f - q) * (1.0f - q) * (1.0f - q);
  return 0.0f;
}

// A cell's corners and edges. Corner c sits at (c & 1, (c >> 1) & 1, (c >> 2) & 1) from the cell's first node.
// Edge e runs along axis e / 4 from the corner whose other two coordinates (in axis order) are the bits of e % 4;
// it belongs to the cell whose first node that corner is, as that cell's edge along the axis (each node owns the
// three edges leaving it towards +x, +y, +z).
FIRN_FUNCTION ivec3 cellCorner(int corner) { return ivec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1); }
FIRN_FUNCTION int edgeAxis(int edge) { return edge / 4; }
FIRN_FUNCTION ivec3 edgeStart(int edge) {
  int axis = edge / 4;
  int first = axis == 0 ? 1 : 0;   // the other two axes, in order
  int second = axis == 2 ? 1 : 2;
  ivec3 start = ivec3(0);
  start[first] = edge & 1;
  start[second] = (edge >> 1) & 1;
  return start;
}

#endif
