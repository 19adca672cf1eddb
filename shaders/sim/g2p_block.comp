#version 430 core
// Grid to particle, shaped for GPUs: a work group per active block. The group reads the velocities of the block's
// region (common/blocks.glsl: the nodes its particles' stencils reach) into shared memory once, then each invocation
// updates the block's particles one at a time, in the sorted order, reading its stencil's nodes from there
// (common/g2p_particle.glsl, the same update as g2p.comp's, so both write the same bytes).
// Reads: grid velocities, the block table and map, sortedParticles, particle state, materials, colliders.
// Writes: the particles (common/g2p_particle.glsl).
#ifdef FIRN_TRANSFER_APIC
#define FIRN_WITHOUT_GRID_IMPULSE  // APIC reads no velocity before forces (common/grid.glsl)
#endif
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/colliders.glsl"
#include "common/materials.glsl"

layout(local_size_x = FIRN_TRANSFER_BLOCK_GROUP_SIZE) in;

// The region's velocities after forces (m/s), 0 at nodes with no block; and before forces (PIC/FLIP).
shared vec3 regionVelocity[BLOCK_REGION_NODES];
#ifndef FIRN_TRANSFER_APIC
shared vec3 regionVelocityBeforeForces[BLOCK_REGION_NODES];
#endif

// The stencil's nodes: its base node's place in the region.
#define StencilNodes ivec3
ivec3 regionFirstNode;
StencilNodes stencilNodes(ivec3 baseNode) { return baseNode - regionFirstNode; }
vec3 stencilNodeVelocity(StencilNodes baseInRegion, ivec3 k) { return regionVelocity[blockRegionIndex(baseInRegion + k)]; }
#ifndef FIRN_TRANSFER_APIC
vec3 stencilNodeVelocityBeforeForces(StencilNodes baseInRegion, ivec3 k) {
  return regionVelocityBeforeForces[blockRegionIndex(baseInRegion + k)];
}
#endif

#include "common/g2p_particle.glsl"

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;  // the whole group: no barrier is left waiting
  uint local = gl_LocalInvocationIndex;
  regionFirstNode = blockFirstNode(slot);
  StencilBlocks blocks = stencilBlocks(regionFirstNode);
  for (uint i = local; i < uint(BLOCK_REGION_NODES); i += uint(FIRN_TRANSFER_BLOCK_GROUP_SIZE)) {
    int address = stencilNodeAddress(blocks, blockRegionOffset(int(i)));
    regionVelocity[i] = address < 0 ? vec3(0.0) : nodeVelocity(uint(address));
#ifndef FIRN_TRANSFER_APIC
    regionVelocityBeforeForces[i] = address < 0 ? vec3(0.0) : nodeVelocityBeforeForces(uint(address));
#endif
  }
  barrier();
  uint first = slots[slot].firstParticle;
  uint count = slots[slot].particles;
  for (uint j = local; j < count; j += uint(FIRN_TRANSFER_BLOCK_GROUP_SIZE)) advanceParticle(sortedParticles[first + j]);
}
