// What every reconstruction pass shares (engine/surface/SurfaceReconstruction.h, docs/surfaces.md): the uniform
// block, the grid of this frame and the conversions between its nodes, the lattice and metres. The grid is a box
// of nodes of the lattice origin + h_r (i, j, k) that every frame shares; the box follows the particles' kernels
// with one node to spare on every side, so that its outer nodes are outside the snow and the surface is closed.
#include "surface/surface_contract.h"

layout(std140, binding = FIRN_BINDING_SURFACE_UNIFORMS) uniform SurfaceUniformsBlock {
  FIRN_MEMBERS(FIRN_SURFACE_UNIFORMS)
};

// Passes over particles or nodes run in groups of FIRN_PARTICLE_GROUP_SIZE, folded into a second dimension of
// work groups beyond 65,535 groups (as the simulation's particle passes are: common/bindings.glsl).
uint itemIndex() {
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * uint(FIRN_PARTICLE_GROUP_SIZE);
}

vec3 latticeOrigin() { return latticeOriginSpacing.xyz; }
float nodeSpacing() { return latticeOriginSpacing.w; }
uint reconstructedParticles() { return particles.x; }
bool withColors() { return particles.y != 0u; }
bool withVelocities() { return particles.z != 0u; }
uint nodeCount() { return uint(nodeCounts.w); }
float smoothing() { return kernel.x; }
float isoLevel() { return kernel.y; }
int isoUnits() { return int(kernel.z); }

// A node of this frame's grid: its index in the box per axis, and its address in the per-node buffers.
uint nodeAddress(ivec3 node) { return uint(node.x + nodeCounts.x * (node.y + nodeCounts.y * node.z)); }
ivec3 nodeOfAddress(uint address) {
  int i = int(address);
  return ivec3(i % nodeCounts.x, (i / nodeCounts.x) % nodeCounts.y, i / (nodeCounts.x * nodeCounts.y));
}
vec3 nodePositionM(ivec3 node) { return latticeOrigin() + vec3(firstNode.xyz + node) * nodeSpacing(); }

// The fixed-point volume fraction as a number.
float fieldValue(int units) { return float(units) * (1.0 / SURFACE_UNITS_PER_VALUE); }
