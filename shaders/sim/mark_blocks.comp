#version 430 core
// Mark blocks: one invocation per particle (common/blocks.glsl). Claims a slot of the pool for every block the
// particle's stencil reaches (at most two per axis) that no other particle has claimed yet: the first to swap the
// block's map entry from 0 takes the next slot and lists the block there. Blocks past the pool's capacity stay
// unlisted: their particles are left out of this step, and the host sees the count and grows the pool.
// With rigid bodies a particle within a kernel's reach of a body's surface also claims the blocks its image's stencil
// reaches (mirror_stress.comp): the image pushes only nodes that hold snow, whose blocks some particle claimed, but
// over several processes that particle may be another process's, and the image's process must hold the node too to
// push it (docs/distributed.md). One process claims them alike, so that both count the same blocks.
// Reads: positionMass (xyz), blockMap (the entries and the claim's old value),
//        blockTable (blockCounts: the old value of x and the capacity y), watchdog (the reports' atomics' old values),
//        colliders (with rigid bodies: their entries).
// Writes: blockMap, blockTable (blockCounts.x and slots[].block and .auditedElsewhere),
//         watchdog (non-finite positions).
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/watchdog.glsl"
#include "common/blocks.glsl"
#ifdef FIRN_HAS_RIGID_BODIES
#include "common/colliders.glsl"
#include "common/mirror.glsl"
#endif

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void claimBlock(ivec3 block) {
  uint index = blockIndex(block);
  if (blockMap[index] != 0u || atomicCompSwap(blockMap[index], 0u, CLAIMED) != 0u) return;
  uint slot = atomicAdd(blockCounts.x, 1u);
  if (slot >= blockCounts.y) return;
  slots[slot].block = index;
  slots[slot].auditedElsewhere = 0u;  // a share of the domain marks it after summing (DomainShare::sumSharedNodes)
  blockMap[index] = slot + 1u;
}

// Claims every block that holds a node from `firstNode` to `lastNode` (per axis, within the domain).
void claimNodes(ivec3 firstNode, ivec3 lastNode) {
  ivec3 first = max(firstNode, ivec3(0)) / BLOCK_WIDTH;
  ivec3 last = min(lastNode, gridNodes - 1) / BLOCK_WIDTH;
  for (int z = first.z; z <= last.z; ++z) {
    for (int y = first.y; y <= last.y; ++y) {
      for (int x = first.x; x <= last.x; ++x) claimBlock(ivec3(x, y, z));
    }
  }
}

#ifdef FIRN_HAS_RIGID_BODIES
// The blocks of the stencils of the particle's images x − 2 φ n in the bodies whose reach it lies within
// (common/mirror.glsl), as mirror_stress.comp finds them: a node more on each side and 1% of a cell more of reach,
// so that the rounding of that pass's own arithmetic cannot take an image past the blocks claimed here.
void claimImageBlocks(vec3 x) {
  float marginM = 0.01 * cellSizeM;
  float reachM = mirrorReachM() + marginM;
  for (uint i = 0u; i < colliderCount; ++i) {
    vec3 normal;
    float distanceM = mirroredDistance(i, x, reachM, normal);
    if (distanceM <= -marginM || distanceM >= reachM) continue;
    ivec3 base = stencilBaseNode(cellCoordinates(x - 2.0 * max(distanceM, 0.0) * normal));
    claimNodes(base - 1, base + KERNEL_WIDTH);
  }
}
#endif

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
    if (all(lessThanEqual(offset, reach))) claimBlock(first + offset);
  }
#ifdef FIRN_HAS_RIGID_BODIES
  claimImageBlocks(x);
#endif
}
