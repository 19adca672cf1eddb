#version 430 core
// Count blocks: one invocation, after mark_blocks.comp. The per-block passes of this step get a work group per
// active block (no more than the pool holds), or an invocation per active block.
// Reads: blockTable (blockCounts).
// Writes: blockTable (blockDispatch and blockRunDispatch).
#include "common/bindings.glsl"
#include "common/blocks.glsl"

layout(local_size_x = 1) in;

void main() {
  blockDispatch = blockWorkGroups(activeBlocks());
  blockRunDispatch = blockWorkGroups((activeBlocks() + uint(BLOCK_NODES) - 1u) / uint(BLOCK_NODES));
}
