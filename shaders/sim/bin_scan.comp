#version 430 core
// Bin scan: an invocation per active block (common/blocks.glsl). The bins' first particles within the block (an
// exclusive prefix sum of the counts), the block's particle count, each tile's bucket of fill counted, and a report
// of any tile fuller than a transfer can take (maxTileParticles: llvmpipe's loop limit).
// Reads: bins (x: the counts), blockTable (blockCounts and slots[].block and the blockRunDispatch record),
//        watchdog (the reports' atomics' old values).
// Writes: bins (y: each bin's first particle within the block), blockTable (slots[].particles and tileBuckets),
//         watchdog (a tile fuller than a transfer can take).
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/shared_functions.h"
#include "common/watchdog.glsl"
#include "common/blocks.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

void main() {
  uint slot = workGroupSlot() * uint(BLOCK_NODES) + gl_LocalInvocationIndex;
  if (slot >= activeBlocks()) return;
  // One block per invocation, its bins in order: no barriers, which cost a CPU renderer a switch of every lane.
  uint first = 0u;
  for (uint tile = 0u; tile < uint(BLOCK_TILES); ++tile) {
    uint tileFirst = first;
    for (uint b = 0u; b < uint(TILE_BASE_NODES); ++b) {
      uint bin = slot * uint(BLOCK_NODES) + tileFirstBin(tile) + b;
      bins[bin].y = first;
      first += bins[bin].x;
    }
    uint tileParticles = first - tileFirst;
    if (tileParticles > 0u) atomicAdd(tileBuckets[tileBucket(tileParticles)], 1u);
    if (tileParticles > maxTileParticles(KERNEL_WIDTH)) {
      reportOverflow(nodeIndex(nodeOfBlock(blockCoordinates(slots[slot].block), tileFirstBin(tile))), CHANNEL_TILE);
    }
  }
  slots[slot].particles = first;
}
