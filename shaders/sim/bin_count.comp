#version 430 core
// Bin count (solver.atomics "none"): one invocation per particle. Claims the particle's place in its block's
// bin: one atomic per particle, where atomic P2G makes 7 per particle and node (common/blocks.glsl).
// Reads: positionMass. Writes: bins[].y (counts, cleared by clear_grid.comp), particleSlots.
#include "common/bindings.glsl"
#include "common/watchdog.glsl"
#include "common/blocks.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void main() {
  uint p = particleInvocationIndex();
  if (p >= particleCount()) return;
  vec3 x = positionMass[p].xyz;
  // G2P never stores a non-finite position, so one here came from outside (an upload): report it, bin nothing.
  if (!allFinite(x)) {
    reportNonFinite(p);
    particleSlots[p] = NOT_BINNED;
    return;
  }
  particleSlots[p] = atomicAdd(bins[blockIndex(particleBlock(x))].y, 1u);
}
