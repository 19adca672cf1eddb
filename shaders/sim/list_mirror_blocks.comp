#version 430 core
// Lists the active blocks whose particles may have an image in a rigid body (common/mirror.glsl), after P2G: an
// invocation per active block. A block's particles have their base nodes in it, so they lie in a ball about the
// centre of the block's region of BLOCK_REGION_WIDTH³ nodes; the block is listed unless every body's φ, over that
// ball, stays at or below 0 or at or beyond the kernel's reach. Only the
// listed blocks' particles then take the bodies' distances in list_mirrored.comp: on llvmpipe every invocation of a
// pass pays for the distance, taken or not (docs/platform.md, Timing on llvmpipe), and most particles lie far from
// every body.
// Reads: blockTable (blockCounts and slots[].block and mirrorBlocks.w's old value and the blockRunDispatch record),
//        colliders.
// Writes: blockTable (mirrorBlocks and slots[].mirrorBlock).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/blocks.glsl"
#include "common/colliders.glsl"
#include "common/mirror.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

void main() {
  uint slot = workGroupSlot() * uint(BLOCK_NODES) + gl_LocalInvocationIndex;
  if (slot >= activeBlocks()) return;
  // A particle lies (K − 1)/2 ± 1/2 cells from its base node along each axis (K the kernel's width), and the
  // block's base nodes span BLOCK_WIDTH cells from its first: its particles fill a cube BLOCK_WIDTH cells wide
  // about the region's centre. 1% of a cell more than that cube's half diagonal: the particles' base nodes are
  // found by rounded arithmetic.
  const float REGION_HALF_WIDTH = 0.5 * float(BLOCK_REGION_WIDTH - 1);
  ivec3 firstNode = blockCoordinates(slots[slot].block) * BLOCK_WIDTH;
  vec3 centreM = gridOriginM + (vec3(firstNode) + REGION_HALF_WIDTH) * cellSizeM;
  float radiusM = (sqrt(3.0) * 0.5 * float(BLOCK_WIDTH) + 0.01) * cellSizeM;
  float reachM = mirrorReachM();
  bool listed = false;
  for (uint i = 0u; i < colliderCount; ++i) listed = listed || mayHoldMirrored(i, centreM, radiusM, reachM);
  if (!listed) return;
  uint k = atomicAdd(mirrorBlocks.w, 1u);
  slots[k].mirrorBlock = slot;
  uvec4 groups = blockWorkGroups(k + 1u);
  atomicMax(mirrorBlocks.x, groups.x);
  atomicMax(mirrorBlocks.y, groups.y);
}
