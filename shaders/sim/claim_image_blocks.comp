#version 430 core
// Claim image blocks: over several processes with rigid bodies only, one invocation per particle after
// mark_blocks.comp. A particle whose stress is mirrored (a fluid's: common/mirror.glsl) within a kernel's reach of a
// body's surface claims the blocks its image's stencil
// reaches (mirror_stress.comp). The image pushes only nodes that hold snow, and in one process some particle's own
// stencil claimed their blocks; over several processes that particle may be another process's, and the image's
// process must hold the node too, for its push to be summed there and exchanged (docs/distributed.md). The blocks
// this pass claims are marked as the images' (BlockSlot.claimedForImages), so that the blocks the particles reach
// are counted as one process counts them.
// Reads: positionMass (xyz), plasticState (materialIndex), materials (model),
//        blockMap (the entries and the claim's old value),
//        blockTable (blockCounts: the old value of x and the capacity y), colliders (the bodies' entries).
// Writes: blockMap, blockTable (blockCounts.x and slots[].block and .auditedElsewhere and .claimedForImages).
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/blocks.glsl"
#include "common/claim_blocks.glsl"
#include "common/colliders.glsl"
#include "common/mirror.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

// Claims every block that holds a node from `firstNode` to `lastNode` (per axis, within the domain).
void claimNodes(ivec3 firstNode, ivec3 lastNode) {
  ivec3 first = max(firstNode, ivec3(0)) / BLOCK_WIDTH;
  ivec3 last = min(lastNode, gridNodes - 1) / BLOCK_WIDTH;
  for (int z = first.z; z <= last.z; ++z) {
    for (int y = first.y; y <= last.y; ++y) {
      for (int x = first.x; x <= last.x; ++x) claimBlock(ivec3(x, y, z), 1u);
    }
  }
}

void main() {
  uint p = invocationIndex();
  if (p >= particleCount || !stressMirrored(p)) return;
  vec3 x = positionMass[p].xyz;
  if (!allFinite(x)) return;  // reported by mark_blocks.comp
  // The images x − 2 φ n as mirror_stress.comp finds them (common/mirror.glsl), give or take a node on each side and
  // 1% of a cell of reach: the rounding of that pass's own arithmetic cannot take an image past the blocks claimed.
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
