// The block-sparse grid and the particles sorted into it (docs/numerics.md, "The block-sparse grid").
//
// The domain's nodes are grouped into blocks of BLOCK_WIDTH³ (common/gpu_contract.h). Each step the blocks a
// particle's stencil reaches claim a slot of the pool (mark_blocks.comp), and only they store nodes: slot s holds
// its block's nodes at s·BLOCK_NODES + x + BLOCK_WIDTH (y + BLOCK_WIDTH z), contiguous. The block map, one uint
// per block of the domain, gives a block's slot + 1 (0: not active); the slots of last step's blocks are released
// at the start of the next (release_blocks.comp), so nothing costs in proportion to the domain.
//
// A particle's base node is the first node of its stencil (kernel.glsl); its block is the base node's. Particles are
// sorted by block, then by base node (the base node's "bin"), by a counting sort each step: bin_count.comp counts each
// bin and gives each particle its rank, bin_scan.comp (for the tiles) or bin_scan_block.comp (for the blocks) and
// block_offsets.comp turn counts into offsets, bin_place.comp writes the sorted order. The order within a bin follows
// the count's atomics, but no result depends on it: fixed-point sums are exact and each particle's update is its own.
//
// The transfers take a tile of TILE_WIDTH × TILE_HEIGHT base nodes (x, y) per invocation: a tile's particles reach
// the nodes of its region, (TILE_WIDTH + KERNEL_WIDTH − 1) × (TILE_HEIGHT + KERNEL_WIDTH − 1) × KERNEL_WIDTH, at
// most two blocks per axis, whose slots are looked up once per tile. An invocation loops over its tile's particles
// bin by bin, so the invocations a CPU renderer runs side by side as one vector wait for the fullest: the tiles
// are taken in order of fill, fullest first (order_tiles.comp), so that tiles of alike fill run side by side. The
// sort files the tiles only where a tile pass runs (sim/BlockGrid.h, SortFor).

#include "common/kernel.glsl"

layout(std430, binding = FIRN_BINDING_BLOCK_TABLE) coherent buffer BlockTableBuffer {
  FIRN_MEMBERS(FIRN_BLOCK_TABLE_HEADER)
  BlockSlot slots[];
};
layout(std430, binding = FIRN_BINDING_BLOCK_MAP) coherent buffer BlockMapBuffer { uint blockMap[]; };
layout(std430, binding = FIRN_BINDING_BINS) coherent buffer BinsBuffer { uvec2 bins[]; };  // particles, first
layout(std430, binding = FIRN_BINDING_SORTED_PARTICLES) buffer SortedParticlesBuffer { uint sortedParticles[]; };
layout(std430, binding = FIRN_BINDING_PARTICLE_RANKS) buffer ParticleRanksBuffer { uint particleRanks[]; };
layout(std430, binding = FIRN_BINDING_TILE_ORDER) buffer TileOrderBuffer { uint tileOrder[]; };  // slot · BLOCK_TILES + tile

// A block being claimed (common/claim_blocks.glsl): its slot is not yet written.
const uint CLAIMED = 0xffffffffu;

ivec3 blocksPerAxis() { return (gridNodes + BLOCK_WIDTH - 1) / BLOCK_WIDTH; }
uint blockIndex(ivec3 block) {
  ivec3 count = blocksPerAxis();
  return uint(block.x + count.x * (block.y + count.y * block.z));
}
ivec3 blockCoordinates(uint index) {
  ivec3 count = blocksPerAxis();
  int i = int(index);
  return ivec3(i % count.x, (i / count.x) % count.y, i / (count.x * count.y));
}
uint activeBlocks() { return min(blockCounts.x, blockCounts.y); }

// The slot of a block, or −1 where it is not active (or the pool ran out).
int blockSlot(ivec3 block) {
  uint entry = blockMap[blockIndex(block)];
  return entry == 0u || entry == CLAIMED ? -1 : int(entry - 1u);
}

// A node's place within its block.
uint nodeInBlock(ivec3 node) {
  ivec3 local = node % BLOCK_WIDTH;
  return uint(local.x + BLOCK_WIDTH * (local.y + BLOCK_WIDTH * local.z));
}
ivec3 nodeOfBlock(ivec3 block, uint localIndex) {
  int i = int(localIndex);
  return block * BLOCK_WIDTH + ivec3(i % BLOCK_WIDTH, (i / BLOCK_WIDTH) % BLOCK_WIDTH, i / (BLOCK_WIDTH * BLOCK_WIDTH));
}

// Where a node's data is stored, or −1 where its block is not active.
int nodeAddress(ivec3 node) {
  int slot = blockSlot(node / BLOCK_WIDTH);
  return slot < 0 ? -1 : slot * BLOCK_NODES + int(nodeInBlock(node));
}

// The per-block passes that read their dispatch from the block table run a work group per active block, laid out in
// rows of 65,535 (the least maximum GL_MAX_COMPUTE_WORK_GROUP_COUNT allows) when there are more.
uvec4 blockWorkGroups(uint blocks) {
  const uint ROW = 65535u;
  return uvec4(min(blocks, ROW), (blocks + ROW - 1u) / ROW, 1u, 0u);
}
uint workGroupSlot() { return gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x; }

// A step sorted for blocks (the GPUs' shape) runs its passes over the blocks (release_blocks and update_grid built with
// FIRN_STRIDE_OVER_BLOCKS, bin_scan_block, p2g_block) dispatched directly, not from the block table: NVIDIA's GL takes
// longer over a pass dispatched indirectly (docs/platform.md, NVIDIA). The host dispatches about as many work groups
// as the blocks it last counted (BlockGrid::runOverBlocks), and each group takes the slots from its own,
// workGroupCount() apart, so that any count of blocks is covered. A step sorted for tiles (CPU renderers) takes a
// work group per block from the block table: the loop slowed llvmpipe's release and grid update (docs/platform.md,
// Timing on llvmpipe).
uint workGroupCount() { return gl_NumWorkGroups.x * gl_NumWorkGroups.y; }

// The particles of the sorted order (block_offsets.comp counts them).
uint sortedParticleCount() { return tileCounts.y; }

// A block's bins are its nodes' (the base node of a bin is the node with the same place).
uint binIndex(uint slot, ivec3 baseNode) { return slot * uint(BLOCK_NODES) + nodeInBlock(baseNode); }

// The particles of a bin, as a range of the sorted order.
uvec2 binParticles(uint slot, uint localBin) {
  uvec2 bin = bins[slot * uint(BLOCK_NODES) + localBin];
  return uvec2(slots[slot].firstParticle + bin.y, bin.x);  // first, count
}

// The blocks a particle's stencil (or a tile's region) reaches: its base node's block and the next one along each
// axis, the slots of the 2³ in two vectors (block offsets x + 2 y, for z = 0 and z = 1), −1 where not active.
struct StencilBlocks {
  ivec3 baseInBlock;  // the base node's place in its block
  ivec4 slotsNear;    // z offset 0
  ivec4 slotsFar;     // z offset 1
};

// The slot of a block that may lie past the domain's last block (−1 there).
int blockSlotInDomain(ivec3 block) { return all(lessThan(block, blocksPerAxis())) ? blockSlot(block) : -1; }

// Each slot written out: a vector's component written at a variable index costs NVIDIA's compiler a chain of branches.
StencilBlocks stencilBlocks(ivec3 baseNode) {
  StencilBlocks b;
  b.baseInBlock = baseNode % BLOCK_WIDTH;
  ivec3 block = baseNode / BLOCK_WIDTH;
  b.slotsNear = ivec4(blockSlotInDomain(block), blockSlotInDomain(block + ivec3(1, 0, 0)),
                      blockSlotInDomain(block + ivec3(0, 1, 0)), blockSlotInDomain(block + ivec3(1, 1, 0)));
  b.slotsFar = ivec4(blockSlotInDomain(block + ivec3(0, 0, 1)), blockSlotInDomain(block + ivec3(1, 0, 1)),
                     blockSlotInDomain(block + ivec3(0, 1, 1)), blockSlotInDomain(block + ivec3(1, 1, 1)));
  return b;
}

// The storage address of the stencil's node k (an offset from the base node), or −1 where its block is not active.
// Selects, not an indexed array: an index that differs between invocations costs a CPU renderer a load per lane.
int stencilNodeAddress(StencilBlocks b, ivec3 k) {
  ivec3 inBlocks = b.baseInBlock + k;
  ivec3 offset = inBlocks / BLOCK_WIDTH;  // 0 or 1 per axis
  ivec4 layerSlots = offset.z == 0 ? b.slotsNear : b.slotsFar;
  ivec2 slotPair = offset.y == 0 ? layerSlots.xy : layerSlots.zw;
  int slot = offset.x == 0 ? slotPair.x : slotPair.y;
  return slot < 0 ? -1 : slot * BLOCK_NODES + int(nodeInBlock(inBlocks));
}

// A tile's bucket of fill: the fullest tiles first.
uint tileBucket(uint particles) {
  return uint(TILE_BUCKETS - 1) - min(particles / TILE_BUCKET_PARTICLES, uint(TILE_BUCKETS - 1));
}

// The transfers' work groups, FIRN_TILE_GROUP_SIZE tiles each.
uvec4 tileWorkGroups(uint tiles) {
  return blockWorkGroups((tiles + uint(FIRN_TILE_GROUP_SIZE) - 1u) / uint(FIRN_TILE_GROUP_SIZE));
}

// A tile's bins are TILE_BASE_NODES consecutive bins of its block (x, then y, then z).
uint tileFirstBin(uint tile) { return tile * uint(TILE_BASE_NODES); }

// A tile's first base node. Its region starts there and, like a stencil, reaches at most the next block along
// each axis: stencilBlocks(tileFirstBase(…)) and stencilNodeAddress give its nodes' addresses.
ivec3 tileFirstBase(uint slot, uint tile) {
  ivec3 block = blockCoordinates(slots[slot].block);
  int first = int(tileFirstBin(tile));
  return block * BLOCK_WIDTH + ivec3(0, (first / BLOCK_WIDTH) % BLOCK_WIDTH, first / (BLOCK_WIDTH * BLOCK_WIDTH));
}

// The tile's region: the nodes its particles' stencils reach, indexed x, then y, then z.
const int REGION_WIDTH = TILE_WIDTH + KERNEL_WIDTH - 1;
const int REGION_HEIGHT = TILE_HEIGHT + KERNEL_WIDTH - 1;
const int REGION_NODES = REGION_WIDTH * REGION_HEIGHT * KERNEL_WIDTH;
int regionIndex(ivec3 offset) { return offset.x + REGION_WIDTH * (offset.y + REGION_HEIGHT * offset.z); }
ivec3 regionOffset(int index) {
  return ivec3(index % REGION_WIDTH, (index / REGION_WIDTH) % REGION_HEIGHT, index / (REGION_WIDTH * REGION_HEIGHT));
}

// A block's region, for the transfers shaped for GPUs (p2g_block.comp, solver_product_block.comp): the nodes the
// stencils of the particles based in the block reach, from its first node on, indexed x, then y, then z.
const int BLOCK_REGION_WIDTH = BLOCK_WIDTH + KERNEL_WIDTH - 1;
const int BLOCK_REGION_NODES = BLOCK_REGION_WIDTH * BLOCK_REGION_WIDTH * BLOCK_REGION_WIDTH;
int blockRegionIndex(ivec3 offset) {
  return offset.x + BLOCK_REGION_WIDTH * (offset.y + BLOCK_REGION_WIDTH * offset.z);
}
ivec3 blockRegionOffset(int index) {
  return ivec3(index % BLOCK_REGION_WIDTH, (index / BLOCK_REGION_WIDTH) % BLOCK_REGION_WIDTH,
               index / (BLOCK_REGION_WIDTH * BLOCK_REGION_WIDTH));
}
