#version 430 core
// Order tiles: a work group per active block, an invocation per tile of it (common/blocks.glsl). Files each tile
// that holds particles in the tile order, in its bucket of fill (fullest first); within a bucket, in whatever
// order the atomics give, which changes no result.
// Reads: bins (x: the counts), blockTable (blockCounts and the blockDispatch record and tileBuckets: first entries).
// Writes: tileOrder, blockTable (tileBuckets: next free entries).
#include "common/bindings.glsl"
#include "common/blocks.glsl"

layout(local_size_x = FIRN_BLOCK_TILES) in;

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;
  uint tile = gl_LocalInvocationIndex;
  uint particles = 0u;
  for (int b = 0; b < TILE_BASE_NODES; ++b) particles += bins[slot * uint(BLOCK_NODES) + tileFirstBin(tile) + uint(b)].x;
  if (particles == 0u) return;
  tileOrder[atomicAdd(tileBuckets[tileBucket(particles)], 1u)] = slot * uint(BLOCK_TILES) + tile;
}
