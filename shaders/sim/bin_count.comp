#version 430 core
// Bin count: one invocation per particle (common/blocks.glsl). Counts the particles of each bin (base node) and
// gives each its rank within its bin.
// Reads: positionMass (xyz), blockMap, bins (x: the count's old value is the particle's rank).
// Writes: bins (x: each bin's count), particleRanks.
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/watchdog.glsl"
#include "common/blocks.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void main() {
  uint p = invocationIndex();
  if (p >= particleCount) return;
  vec3 x = positionMass[p].xyz;
  if (!allFinite(x)) return;  // reported by mark_blocks.comp
  ivec3 base = stencilBaseNode(cellCoordinates(x));
  int slot = blockSlot(base / BLOCK_WIDTH);
  if (slot < 0) return;  // past the pool's capacity: the host grows it
  particleRanks[p] = atomicAdd(bins[binIndex(uint(slot), base)].x, 1u);
}
