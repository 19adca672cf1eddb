// What every reconstruction pass shares (engine/surface/SurfaceReconstruction.h, docs/surfaces.md): the uniform
// block, the grid of this frame and the conversions between its nodes, the lattice and metres. The grid is a box
// of nodes of the lattice origin + h_r (i, j, k) that every frame shares; the box follows the particles' kernels
// with one node to spare on every side, so that its outer nodes are outside the snow and the surface is closed.
#include "surface/surface_contract.h"

layout(std140, binding = FIRN_BINDING_SURFACE_UNIFORMS) uniform SurfaceUniformsBlock {
  FIRN_MEMBERS(FIRN_SURFACE_UNIFORMS)
};

#include "common/invocation.glsl"

bool withColors() { return (sumsCarried & SURFACE_SUMS_COLOR) != 0u; }
bool withVelocities() { return (sumsCarried & SURFACE_SUMS_VELOCITY) != 0u; }

// A node of this frame's grid: its index in the box per axis, and its address in the per-node buffers.
uint nodeAddress(ivec3 node) { return uint(node.x + boxNodes.x * (node.y + boxNodes.y * node.z)); }
ivec3 nodeOfAddress(uint address) {
  int i = int(address);
  return ivec3(i % boxNodes.x, (i / boxNodes.x) % boxNodes.y, i / (boxNodes.x * boxNodes.y));
}
vec3 nodePositionM(ivec3 node) { return latticeOriginM + vec3(firstNode + node) * nodeSpacingM; }

// The fixed-point volume fraction as a number.
float fieldValue(int units) { return float(units) * (1.0 / SURFACE_UNITS_PER_VALUE); }
