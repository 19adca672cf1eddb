#version 430 core
// Prepare blocks: one invocation, first in the step (common/blocks.glsl). Last step's active blocks become the
// ones to release, their count the release pass's dispatch; this step's counts of blocks and rows start at zero.
// Resets the watchdog's fastest signal, which this step's G2P finds afresh (adaptive steps).
// Reads: blockTable (blockCounts).
// Writes: watchdog (maxSpeedBits),
//   blockTable (blockCounts and releaseDispatch and tileCounts and mirrorBlocks and mirrorDispatch and tileBuckets).
#include "common/bindings.glsl"
#include "common/watchdog.glsl"
#include "common/blocks.glsl"

layout(local_size_x = 1) in;

void main() {
  uint previous = activeBlocks();
  blockCounts.z = previous;
  blockCounts.w = max(blockCounts.w, blockCounts.x);
  blockCounts.x = 0u;
  releaseDispatch = blockWorkGroups(previous);
  tileCounts = uvec4(0u);
  mirrorBlocks = uvec4(0u, 1u, 1u, 0u);
  mirrorDispatch = uvec4(0u, 1u, 1u, 0u);
  for (int bucket = 0; bucket < TILE_BUCKETS; ++bucket) tileBuckets[bucket] = 0u;
  maxSpeedBits = 0u;
}
