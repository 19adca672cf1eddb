#version 430 core
// Bin scan (solver.atomics "none"): one work group, after bin_count.comp (common/blocks.glsl).
// 1. Turns the block counts of the active box into bin offsets: an exclusive prefix sum in box order. Each
//    invocation sums a run of blocks, the group scans the runs' sums in shared memory, then each invocation
//    writes its run's offsets.
// 2. Lists each colour's non-empty blocks, fullest first, grouped by fill (buckets of BUCKET_PARTICLES), and
//    writes the colour's dispatch: p2g_blocks.comp gives each SIMD lane a block, so lanes whose bins are alike
//    finish together (in box order, a body's surface puts nearly empty blocks beside full ones, and a row of
//    lanes runs as long as its fullest).
// 3. Reports a bin fuller than MAX_BIN_PARTICLES (llvmpipe stops any invocation after 65,535 loop iterations,
//    and p2g_blocks.comp spends 1 + KERNEL_WIDTH² per particle) as an overflow, so a run stops rather than
//    silently dropping particles.
// Reads: region (the node box), bins[].y. Writes: bins[].x, blockColors, blockOrder, the watchdog.
#include "common/bindings.glsl"
#include "common/active_region.glsl"
#include "common/watchdog.glsl"
#include "common/blocks.glsl"

#define SCAN_INVOCATIONS 256u
layout(local_size_x = 256) in;  // SCAN_INVOCATIONS

const int BUCKETS = 64;
const uint BUCKET_PARTICLES = 8u;

shared uint runTotals[SCAN_INVOCATIONS];
shared uint bucketCounts[BLOCK_COLORS * BUCKETS];  // then each bucket's first entry in blockOrder

ivec3 firstBlock() { return region.boxMin.xyz / BLOCK_CELLS; }
ivec3 boxBlocks() {
  ivec3 last = (region.boxMin.xyz + region.boxSize.xyz - 1) / BLOCK_CELLS;
  return region.boxSize.w <= 0 ? ivec3(0) : last - firstBlock() + 1;
}
ivec3 blockAt(uint b, ivec3 size) {
  return firstBlock() + ivec3(int(b) % size.x, (int(b) / size.x) % size.y, int(b) / (size.x * size.y));
}
int colorOf(ivec3 block) { return (block.x & 1) | ((block.y & 1) << 1) | ((block.z & 1) << 2); }
uint bucketOf(uint particles) { return uint(BUCKETS - 1) - min(particles / BUCKET_PARTICLES, uint(BUCKETS - 1)); }

// An exclusive prefix sum of `value` over the group's invocations, in invocation order.
uint groupExclusiveSum(uint value) {
  uint t = gl_LocalInvocationIndex;
  runTotals[t] = value;
  barrier();
  if (t == 0u) {
    uint sum = 0u;
    for (uint i = 0u; i < SCAN_INVOCATIONS; ++i) {
      uint runTotal = runTotals[i];
      runTotals[i] = sum;
      sum += runTotal;
    }
  }
  barrier();
  uint result = runTotals[t];
  barrier();
  return result;
}

void main() {
  uint t = gl_LocalInvocationIndex;
  ivec3 size = boxBlocks();
  uint blocks = uint(size.x * size.y * size.z);
  uint run = (blocks + SCAN_INVOCATIONS - 1u) / SCAN_INVOCATIONS;
  uint runStart = min(t * run, blocks);
  uint runEnd = min(runStart + run, blocks);
  for (uint i = t; i < uint(BLOCK_COLORS * BUCKETS); i += SCAN_INVOCATIONS) bucketCounts[i] = 0u;
  barrier();

  // 1. Bin offsets; and the blocks per colour and fill.
  uint total = 0u;
  for (uint b = runStart; b < runEnd; ++b) {
    uint particles = bins[blockIndex(blockAt(b, size))].y;
    total += particles;
    if (particles > 0u) atomicAdd(bucketCounts[colorOf(blockAt(b, size)) * BUCKETS + int(bucketOf(particles))], 1u);
    if (particles > uint(MAX_BIN_PARTICLES)) reportOverflow(blockIndex(blockAt(b, size)), CHANNEL_BIN);
  }
  uint offset = groupExclusiveSum(total);
  for (uint b = runStart; b < runEnd; ++b) {
    uint index = blockIndex(blockAt(b, size));
    bins[index].x = offset;
    offset += bins[index].y;
  }

  // 2. Each colour's list: buckets' first entries, then the blocks filed by a second pass over the runs.
  if (t == 0u) {
    uint start = 0u;
    for (int color = 0; color < BLOCK_COLORS; ++color) {
      uint colorBlocks = 0u;
      for (int bucket = 0; bucket < BUCKETS; ++bucket) {
        uint count = bucketCounts[color * BUCKETS + bucket];
        bucketCounts[color * BUCKETS + bucket] = start + colorBlocks;
        colorBlocks += count;
      }
      blockColors[color].first = ivec4(int(start), 0, 0, 0);
      blockColors[color].count = ivec4(0, 0, 0, int(colorBlocks));
      blockColors[color].dispatch = uvec4((colorBlocks + 7u) / 8u, 1u, 1u, 0u);  // 8 lanes per group
      start += colorBlocks;
    }
  }
  barrier();
  for (uint b = runStart; b < runEnd; ++b) {
    ivec3 block = blockAt(b, size);
    uint particles = bins[blockIndex(block)].y;
    if (particles > 0u) {
      uint entry = atomicAdd(bucketCounts[colorOf(block) * BUCKETS + int(bucketOf(particles))], 1u);
      blockOrder[entry] = blockIndex(block);
    }
  }
}
