#version 430 core
// Order rows: a work group per active block, an invocation per row of it (common/blocks.glsl). Files each row
// that holds particles in the row order, in its bucket of fill (fullest first); within a bucket, in whatever
// order the atomics give, which changes no result.
// Reads: bins[].x, rowBuckets (first entries). Writes: rowOrder, rowBuckets (next free entries).
#include "common/bindings.glsl"
#include "common/blocks.glsl"

layout(local_size_x = FIRN_BLOCK_ROWS) in;

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;
  uint row = gl_LocalInvocationIndex;
  uint particles = 0u;
  for (int bx = 0; bx < ROW_NODES; ++bx) particles += bins[slot * uint(BLOCK_NODES) + row * uint(ROW_NODES) + uint(bx)].x;
  if (particles == 0u) return;
  rowOrder[atomicAdd(rowBuckets[rowBucket(particles)], 1u)] = slot * uint(BLOCK_ROWS) + row;
}
