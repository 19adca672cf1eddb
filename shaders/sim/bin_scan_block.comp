#version 430 core
// Bin scan, shaped for GPUs: work groups over the active blocks, an invocation per bin of a block (common/blocks.glsl,
// workGroupCount). The bins' first particles within the block (an exclusive prefix sum of the counts, in shared
// memory) and the block's particle count: bin_scan.comp's sums, which it takes block by block in one invocation,
// reading a block's bins one after another, and without the tiles' buckets of fill, which only the tile passes read
// (the sort files tiles only where one runs: sim/BlockGrid.h).
// Reads: bins (x: the counts), blockTable (blockCounts).
// Writes: bins (y: each bin's first particle within the block), blockTable (slots[].particles).
#include "common/bindings.glsl"
#include "common/blocks.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;  // BLOCK_NODES: a bin per invocation

shared uint partialSums[BLOCK_NODES];

void scanBlock(uint slot) {
  uint bin = gl_LocalInvocationIndex;
  uint count = bins[slot * uint(BLOCK_NODES) + bin].x;
  partialSums[bin] = count;
  barrier();
  // Inclusive scan by doubling strides (Hillis and Steele): log2(BLOCK_NODES) rounds.
  for (uint stride = 1u; stride < uint(BLOCK_NODES); stride *= 2u) {
    uint addend = bin >= stride ? partialSums[bin - stride] : 0u;
    barrier();
    partialSums[bin] += addend;
    barrier();
  }
  bins[slot * uint(BLOCK_NODES) + bin].y = partialSums[bin] - count;
  if (bin == uint(BLOCK_NODES) - 1u) slots[slot].particles = partialSums[bin];
}

void main() {
  // The slots are the group's alike: every invocation meets every barrier.
  for (uint slot = workGroupSlot(); slot < activeBlocks(); slot += workGroupCount()) {
    scanBlock(slot);
    barrier();  // the sums read before the next block's counts replace them
  }
}
