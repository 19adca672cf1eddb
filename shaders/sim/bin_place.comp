#version 430 core
// Bin place (solver.atomics "none"): one invocation per particle. Files the particle's index in its block's bin
// at the place bin_count.comp claimed (common/blocks.glsl).
// Reads: positionMass, bins[].x, particleSlots. Writes: blockParticles.
#include "common/bindings.glsl"
#include "common/blocks.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void main() {
  uint p = particleInvocationIndex();
  if (p >= particleCount() || particleSlots[p] == NOT_BINNED) return;
  blockParticles[bins[blockIndex(particleBlock(positionMass[p].xyz))].x + particleSlots[p]] = p;
}
