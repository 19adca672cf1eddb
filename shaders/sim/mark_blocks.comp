#version 430 core
// Mark blocks: one invocation per particle (common/blocks.glsl). Claims a slot of the pool for every block the
// particle's stencil reaches (at most two per axis) that no other particle has claimed yet: the first to swap the
// block's map entry from 0 takes the next slot and lists the block there. Blocks past the pool's capacity stay
// unlisted: their particles are left out of this step, and the host sees the count and grows the pool.
// Reads: positionMass (xyz), blockMap (the entries and the claim's old value),
//        blockTable (blockCounts: the old value of x and the capacity y), watchdog (the reports' atomics' old values).
// Writes: blockMap, blockTable (blockCounts.x and slots[].block and .auditedElsewhere and .claimedForImages),
//         watchdog (non-finite positions).
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/watchdog.glsl"
#include "common/blocks.glsl"
#include "common/claim_blocks.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void main() {
  uint p = invocationIndex();
  if (p >= particleCount) return;
  vec3 x = positionMass[p].xyz;
  if (!allFinite(x)) {
    reportNonFinite(p);
    return;
  }
  ivec3 base = stencilBaseNode(cellCoordinates(x));
  ivec3 first = base / BLOCK_WIDTH;
  ivec3 reach = (base + KERNEL_WIDTH - 1) / BLOCK_WIDTH - first;  // 0 or 1 more block per axis
  for (int k = 0; k < 8; ++k) {
    ivec3 offset = ivec3(k & 1, (k >> 1) & 1, k >> 2);
    if (all(lessThanEqual(offset, reach))) claimBlock(first + offset, 0u);
  }
}
