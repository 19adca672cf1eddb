#version 430 core
// Clear grid: one invocation per node of the active box. Zeroes the accumulators P2G adds into, and for P2G
// without atomics the bins of the blocks the box overlaps (each by the box's first node in that block).
// Writes: gridMomentumMass (and gridImpulse for PIC/FLIP), bins (solver.atomics "none").
#include "common/bindings.glsl"
#include "common/active_region.glsl"
#include "common/grid.glsl"
#ifdef FIRN_P2G_BLOCKS
#include "common/blocks.glsl"
#endif

layout(FIRN_GRID_GROUP_SIZE) in;

void main() {
  ivec3 local = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(local, region.boxSize.xyz))) return;
  uint node = nodeIndex(region.boxMin.xyz + local);
  gridMomentumMass[node] = GridVector(0);
#ifndef FIRN_TRANSFER_APIC
  gridImpulse[node] = GridVector(0);
#endif
#ifdef FIRN_P2G_BLOCKS
  ivec3 n = region.boxMin.xyz + local;
  ivec3 block = n / BLOCK_CELLS;
  if (all(equal(n, max(block * BLOCK_CELLS, region.boxMin.xyz)))) bins[blockIndex(block)] = uvec2(0u);
#endif
}
