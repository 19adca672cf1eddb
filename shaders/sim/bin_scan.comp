#version 430 core
// Bin scan: a work group per active block, an invocation per bin (common/blocks.glsl). The bins' first particles
// within the block (an exclusive prefix sum of the counts), the block's particle count, each tile's bucket of fill
// counted, and a report of any tile fuller than a transfer can take (maxTileParticles: llvmpipe's loop limit).
// Reads: bins[].x. Writes: bins[].y, slots[].particles, tileBuckets, the watchdog.
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/shared_functions.h"
#include "common/watchdog.glsl"
#include "common/blocks.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

shared uint scanned[BLOCK_NODES];

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;
  uint bin = gl_LocalInvocationIndex;
  uint count = bins[slot * uint(BLOCK_NODES) + bin].x;
  scanned[bin] = count;
  barrier();
  // Hillis–Steele inclusive scan: log2(BLOCK_NODES) rounds.
  for (uint stride = 1u; stride < uint(BLOCK_NODES); stride *= 2u) {
    uint addend = bin >= stride ? scanned[bin - stride] : 0u;
    barrier();
    scanned[bin] += addend;
    barrier();
  }
  bins[slot * uint(BLOCK_NODES) + bin].y = scanned[bin] - count;
  if (bin == uint(BLOCK_NODES - 1)) slots[slot].particles = scanned[bin];
  // A tile's bins are consecutive; its last bin sees the tile's total.
  if (bin % uint(TILE_BASE_NODES) == uint(TILE_BASE_NODES - 1)) {
    uint tileFirst = bin + 1u - uint(TILE_BASE_NODES);
    uint tileParticles = scanned[bin] - (tileFirst == 0u ? 0u : scanned[tileFirst - 1u]);
    if (tileParticles > 0u) atomicAdd(tileBuckets[tileBucket(tileParticles)], 1u);
    if (tileParticles > maxTileParticles(KERNEL_WIDTH)) {
      reportOverflow(nodeIndex(nodeOfBlock(blockCoordinates(slots[slot].block), tileFirst)), CHANNEL_TILE);
    }
  }
}
