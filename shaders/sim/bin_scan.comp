#version 430 core
// Bin scan: a work group per active block, an invocation per bin (common/blocks.glsl). The bins' first particles
// within the block (an exclusive prefix sum of the counts), the block's particle count, each row's bucket of fill
// counted, and a report of any row fuller than a transfer can take (maxRowParticles: llvmpipe's loop limit).
// Reads: bins[].x. Writes: bins[].y, slots[].particles, rowBuckets, the watchdog.
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
  // Rows are ROW_NODES consecutive bins; the row's last bin sees the row's total.
  if (bin % uint(ROW_NODES) == uint(ROW_NODES - 1)) {
    uint rowFirst = bin + 1u - uint(ROW_NODES);
    uint rowParticles = scanned[bin] - (rowFirst == 0u ? 0u : scanned[rowFirst - 1u]);
    if (rowParticles > 0u) atomicAdd(rowBuckets[rowBucket(rowParticles)], 1u);
    if (rowParticles > maxRowParticles(KERNEL_NODES)) {
      reportOverflow(nodeIndex(nodeOfBlock(blockCoordinates(slots[slot].block), rowFirst)), CHANNEL_ROW);
    }
  }
}
