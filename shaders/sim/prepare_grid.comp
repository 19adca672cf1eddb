#version 430 core
// Prepare grid: one invocation. Turns the particle cell bounds that the previous particle pass accumulated,
// and those of particles added since, into this step's node box (every node a particle's stencil can touch),
// writes the indirect dispatch of the grid passes, and resets the bounds for the next accumulation.
// Reads: region.particleCellMin/Max, region.addedCellMin/Max. Writes: region (box, dispatch, reset bounds), and
// resets the watchdog's maxSpeedBits.
#include "common/bindings.glsl"
#include "common/active_region.glsl"
#include "common/watchdog.glsl"

layout(local_size_x = 1) in;

void main() {
  // Both kernels' stencils lie within [cell − 1, cell + 2] on each axis (kernel.glsl).
  ivec3 cellMin = min(region.particleCellMin.xyz, region.addedCellMin.xyz);
  ivec3 cellMax = max(region.particleCellMax.xyz, region.addedCellMax.xyz);
  ivec3 first = max(cellMin - 1, ivec3(0));
  ivec3 last = min(cellMax + 2, gridNodes.xyz - 1);
  ivec3 size = max(last - first + 1, ivec3(0));
  region.boxMin = ivec4(first, 0);
  region.boxSize = ivec4(size, size.x * size.y * size.z);
  region.gridDispatch = uvec4(uvec3((size + GRID_GROUP_SIZE - 1) / GRID_GROUP_SIZE), 0u);
  region.particleCellMin = ivec4(INT_MAX);
  region.particleCellMax = ivec4(INT_MIN);
  region.addedCellMin = ivec4(INT_MAX);
  region.addedCellMax = ivec4(INT_MIN);
  maxSpeedBits = 0u;  // this step's G2P finds the fastest signal afresh (adaptive dt)
}
