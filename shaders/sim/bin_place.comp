#version 430 core
// Bin place: one invocation per particle (common/blocks.glsl). Writes each particle's index at its place in the
// sorted order: its block's first particle, plus its bin's first within the block, plus its rank in the bin.
// Reads: positionMass (xyz), blockMap, blockTable (slots[].firstParticle), bins (y: each bin's first particle),
//        particleRanks.
// Writes: sortedParticles.
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/watchdog.glsl"
#include "common/blocks.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void main() {
  uint p = invocationIndex();
  if (p >= particleCount) return;
  vec3 x = positionMass[p].xyz;
  if (!allFinite(x)) return;
  ivec3 base = stencilBaseNode(cellCoordinates(x));
  int slot = blockSlot(base / BLOCK_WIDTH);
  if (slot < 0) return;
  uint bin = binIndex(uint(slot), base);
  sortedParticles[slots[slot].firstParticle + bins[bin].y + particleRanks[p]] = p;
}
