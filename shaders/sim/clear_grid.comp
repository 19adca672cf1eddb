#version 430 core
// Clear grid: one invocation per node of the active box. Zeroes the accumulators P2G adds into.
// Writes: gridMomentumMass (and gridImpulse for PIC/FLIP).
#include "common/bindings.glsl"
#include "common/active_region.glsl"
#include "common/grid.glsl"

layout(FIRN_GRID_GROUP_SIZE) in;

void main() {
  ivec3 local = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(local, region.boxSize.xyz))) return;
  uint node = nodeIndex(region.boxMin.xyz + local);
  gridMomentumMass[node] = GridVector(0);
#ifndef FIRN_TRANSFER_APIC
  gridImpulse[node] = GridVector(0);
#endif
}
