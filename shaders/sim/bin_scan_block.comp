#version 430 core
// Bin scan, shaped for GPUs: a work group per active block, an invocation per bin of it (common/blocks.glsl). The
// bins' first particles within the block (an exclusive prefix sum of the counts, in shared memory) and the block's
// particle count: bin_scan.comp's sums, which it takes block by block in one invocation, reading a block's bins one
// after another, and without the tiles' buckets of fill, which only the tile passes read (the sort files tiles
// only where one runs: sim/BlockGrid.h).
// Reads: bins[].x. Writes: bins[].y, slots[].particles.
#include "common/bindings.glsl"
#include "common/blocks.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;  // BLOCK_NODES: a bin per invocation

shared uint partialSums[BLOCK_NODES];

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;  // the whole group: no barrier is left waiting
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
