#version 430 core
// Grid to particle: one invocation per particle, in the sorted order (common/blocks.glsl), so that the invocations
// side by side read the same nodes; each looks its stencil's nodes up in the blocks it reaches and updates its
// particle (common/g2p_particle.glsl). The shape for CPU renderers; g2p_block.comp is the GPUs' (sim/TransferShape.h).
// Reads: grid velocities, the block map, sortedParticles, particle state, materials, colliders.
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

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

// The stencil's nodes: the slots of the blocks it reaches, looked up once.
#define StencilNodes StencilBlocks
StencilNodes stencilNodes(ivec3 baseNode) { return stencilBlocks(baseNode); }
vec3 stencilNodeVelocity(StencilNodes blocks, ivec3 k) {
  int address = stencilNodeAddress(blocks, k);
  return address < 0 ? vec3(0.0) : nodeVelocity(uint(address));
}
#ifndef FIRN_TRANSFER_APIC
vec3 stencilNodeVelocityBeforeForces(StencilNodes blocks, ivec3 k) {
  int address = stencilNodeAddress(blocks, k);
  return address < 0 ? vec3(0.0) : nodeVelocityBeforeForces(uint(address));
}
#endif

#include "common/g2p_particle.glsl"

void main() {
  uint i = invocationIndex();
  if (i < sortedParticleCount()) advanceParticle(sortedParticles[i]);
}
