#version 430 core
// Release blocks: a work group per block active last step (striding over them: common/blocks.glsl,
// FIRN_STRIDE_OVER_BLOCKS), an invocation per node of it.
// Empties what the block held — its nodes' sums and velocities, its bins — and takes it off the block map, so
// that every slot of the pool is clean when the step claims it again.
// Reads: blockTable (blockCounts.z and last step's slots[].block and the releaseDispatch record).
// Writes: gridMomentumMass, gridImpulse (PIC/FLIP or semi-implicit), bins, blockMap, blockTable (slots[].particles).
#include "common/bindings.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

void releaseBlock(uint slot) {
  uint address = slot * uint(BLOCK_NODES) + gl_LocalInvocationIndex;
  gridMomentumMass[address] = GridVector(0);
#ifdef FIRN_GRID_IMPULSE
  gridImpulse[address] = GridVector(0);
#endif
  bins[address] = uvec2(0u);
  if (gl_LocalInvocationIndex == 0u) {
    blockMap[slots[slot].block] = 0u;
    slots[slot].particles = 0u;
  }
}

void main() {
#ifdef FIRN_STRIDE_OVER_BLOCKS
  for (uint slot = workGroupSlot(); slot < blockCounts.z; slot += workGroupCount()) releaseBlock(slot);
#else
  uint slot = workGroupSlot();
  if (slot < blockCounts.z) releaseBlock(slot);
#endif
}
