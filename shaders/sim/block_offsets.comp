#version 430 core
// Block offsets: one work group (common/blocks.glsl). Each active block's first particle in the sorted order: an
// exclusive prefix sum of the blocks' particle counts, in slot order. Each invocation sums a run of slots, the
// group scans the runs' sums, then each invocation writes its run's offsets. Also each bucket of tile fill's
// first entry in the tile order, and the transfers' dispatch.
// Reads: blockTable (blockCounts and slots[].particles and tileBuckets: each bucket's tiles).
// Writes: blockTable (slots[].firstParticle and tileBuckets: first entries and tileCounts and tileDispatch).
#include "common/bindings.glsl"
#include "common/blocks.glsl"

#define SCAN_INVOCATIONS 256u
layout(local_size_x = 256) in;  // SCAN_INVOCATIONS

shared uint runTotals[SCAN_INVOCATIONS];

void main() {
  uint blocks = activeBlocks();
  uint runLength = (blocks + SCAN_INVOCATIONS - 1u) / SCAN_INVOCATIONS;
  uint first = gl_LocalInvocationIndex * runLength;
  uint last = min(first + runLength, blocks);
  uint total = 0u;
  for (uint s = first; s < last; ++s) total += slots[s].particles;
  runTotals[gl_LocalInvocationIndex] = total;
  barrier();
  for (uint stride = 1u; stride < SCAN_INVOCATIONS; stride *= 2u) {
    uint addend = gl_LocalInvocationIndex >= stride ? runTotals[gl_LocalInvocationIndex - stride] : 0u;
    barrier();
    runTotals[gl_LocalInvocationIndex] += addend;
    barrier();
  }
  uint offset = runTotals[gl_LocalInvocationIndex] - total;
  for (uint s = first; s < last; ++s) {
    slots[s].firstParticle = offset;
    offset += slots[s].particles;
  }
  if (gl_LocalInvocationIndex == 0u) {
    uint tiles = 0u;
    for (int bucket = 0; bucket < TILE_BUCKETS; ++bucket) {
      uint bucketTiles = tileBuckets[bucket];
      tileBuckets[bucket] = tiles;
      tiles += bucketTiles;
    }
    tileCounts.x = tiles;
    tileCounts.y = runTotals[SCAN_INVOCATIONS - 1u];  // the particles of the sorted order
    tileDispatch = tileWorkGroups(tiles);
  }
}
