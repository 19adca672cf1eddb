// Claiming the blocks of the pool a step needs (common/blocks.glsl): mark_blocks.comp for the particles' stencils,
// claim_image_blocks.comp for their images' in the rigid bodies.

// Claims a slot of the pool for `block` unless another invocation has: the first to swap the block's map entry from
// 0 takes the next slot and lists the block there; `forImages` says which pass claimed it (BlockSlot). Past the pool's
// capacity the block stays unlisted (and the host sees the count and grows the pool).
void claimBlock(ivec3 block, uint forImages) {
  uint index = blockIndex(block);
  if (blockMap[index] != 0u || atomicCompSwap(blockMap[index], 0u, CLAIMED) != 0u) return;
  uint slot = atomicAdd(blockCounts.x, 1u);
  if (slot >= blockCounts.y) return;
  slots[slot].block = index;
  slots[slot].auditedElsewhere = 0u;  // a share of the domain marks it after summing (DomainShare::sumSharedNodes)
  slots[slot].claimedForImages = forImages;
  blockMap[index] = slot + 1u;
}
