#version 430 core
// The semi-implicit solve's Hessian product, β Δt² H u (common/solver.glsl, common/solver_product.glsl), shaped for
// GPUs as P2G's blocks (p2g_block.comp): a work group per active block reads u at the block's region into shared
// memory once; an invocation per particle of the block adds its rounded contributions to the region's 64-bit sums in
// shared memory with integer atomics (the low word's carry taken by hand: FIRN_ADD_FIXED64_WORD, as at the nodes);
// then the group adds each region node's sums to the node, a global atomic per word. The same bytes as the tiles'
// solver_product.comp: the same contributions, rounded alike, summed exactly.
// u is the preconditioned residual z, or, built with FIRN_SOLVER_FIRST_PRODUCT, the start x₀ of the initial residual,
// which update_grid.comp left in the direction: the first product of a step also sums the nodes' stiffness blocks.
// In the solve its dispatch is the solve's status's solveBlockDispatch record: the dispatch's commands, which the
// shader does not read.
// Reads: blockTable (blockCounts and slots[] and after the solve the blockDispatch record), sortedParticles, blockMap,
//        positionMass (xyz), velocityVolume (w: V0), solverParticles,
//        elasticDeformation (FIRN_SOLVER_FORCE_DIFFERENCE test builds), plasticState (the same test builds),
//        materials (the same test builds), solverNodes (u: direction or else preconditioned and the sums' old words),
//        watchdog (the reports' atomics' old values).
// Writes: solverNodes (the product sums and in the first product the stiffness blocks' sums),
//         watchdog (contributions too large for the fixed point).
#define FIRN_WITHOUT_SOLVER_PRECONDITIONER
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/blocks.glsl"
#include "common/solver.glsl"
#include "common/material_hessians.glsl"
#include "common/solver_product.glsl"

layout(local_size_x = FIRN_P2G_BLOCK_GROUP_SIZE) in;

#ifdef FIRN_SOLVER_FIRST_PRODUCT
const int PRODUCT_CHANNELS = 9;  // the product xyz; the stiffness block's diagonal xyz and its yz, zx, xy
#else
const int PRODUCT_CHANNELS = 3;
#endif

// u at the region's nodes (m/s), and the region's 64-bit sums channel after channel (integer atomics take scalars):
// 28 KiB with the cubic kernel's first product, within the 32 KiB GL 4.3 guarantees.
shared vec3 regionVector[BLOCK_REGION_NODES];
shared uint regionLow[PRODUCT_CHANNELS * BLOCK_REGION_NODES];
shared int regionHigh[PRODUCT_CHANNELS * BLOCK_REGION_NODES];
shared bool regionDropped;  // a contribution too large for the fixed point

vec3 productVectorAt(ivec3 offset) { return regionVector[blockRegionIndex(offset)]; }

// Adds (low, high) to channels [firstChannel, firstChannel + 3) of region node i.
void addToRegion(int i, int firstChannel, uvec3 low, ivec3 high) {
  for (int c = 0; c < 3; ++c) {
    int word = (firstChannel + c) * BLOCK_REGION_NODES + i;
    FIRN_ADD_FIXED64_WORD(regionLow[word], regionHigh[word], low[c], high[c])
  }
}

void addProductToRegion(ivec3 offset, uvec3 low, ivec3 high) { addToRegion(blockRegionIndex(offset), 0, low, high); }

#ifdef FIRN_SOLVER_FIRST_PRODUCT
void addStiffnessBlockToRegion(ivec3 offset, uvec3 diagonalLow, ivec3 diagonalHigh, uvec3 offDiagonalLow,
                               ivec3 offDiagonalHigh) {
  int i = blockRegionIndex(offset);
  addToRegion(i, 3, diagonalLow, diagonalHigh);
  addToRegion(i, 6, offDiagonalLow, offDiagonalHigh);
}
#endif

// Region node i's sums of channels [firstChannel, firstChannel + 3), as a node's words take them.
void regionSums(int i, int firstChannel, out uvec4 low, out ivec4 high) {
  low = uvec4(0u);
  high = ivec4(0);
  for (int c = 0; c < 3; ++c) {
    low[c] = regionLow[(firstChannel + c) * BLOCK_REGION_NODES + i];
    high[c] = regionHigh[(firstChannel + c) * BLOCK_REGION_NODES + i];
  }
}

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;  // the whole group: no barrier is left waiting
  uint local = gl_LocalInvocationIndex;
  ivec3 blockFirstNode = blockCoordinates(slots[slot].block) * BLOCK_WIDTH;
  StencilBlocks blocks = stencilBlocks(blockFirstNode);
  for (uint i = local; i < uint(BLOCK_REGION_NODES); i += uint(FIRN_P2G_BLOCK_GROUP_SIZE)) {
    regionVector[i] = productVectorOfNode(stencilNodeAddress(blocks, blockRegionOffset(int(i))));
  }
  for (uint i = local; i < uint(PRODUCT_CHANNELS * BLOCK_REGION_NODES); i += uint(FIRN_P2G_BLOCK_GROUP_SIZE)) {
    regionLow[i] = 0u;
    regionHigh[i] = 0;
  }
  if (local == 0u) regionDropped = false;
  barrier();

  uint first = slots[slot].firstParticle;
  uint count = slots[slot].particles;
  bool fits = true;
  for (uint j = local; j < count; j += uint(FIRN_P2G_BLOCK_GROUP_SIZE)) {
    fits = scatterProductParticle(sortedParticles[first + j], blockFirstNode) && fits;
  }
  if (!fits) regionDropped = true;
  barrier();

  // A dropped contribution is named at the block's first node: its particles' stencils reach a few nodes further.
  if (local == 0u && regionDropped) reportOverflow(nodeIndex(blockFirstNode), CHANNEL_SOLVER);
  for (uint i = local; i < uint(BLOCK_REGION_NODES); i += uint(FIRN_P2G_BLOCK_GROUP_SIZE)) {
    int node = int(i);
    uvec4 low;
    ivec4 high;
    regionSums(node, 0, low, high);
#ifdef FIRN_SOLVER_FIRST_PRODUCT
    uvec4 diagonalLow, offLow;
    ivec4 diagonalHigh, offHigh;
    regionSums(node, 3, diagonalLow, diagonalHigh);
    regionSums(node, 6, offLow, offHigh);
    addRegionSumsToNode(blocks, blockRegionOffset(node), low, high, diagonalLow, diagonalHigh, offLow, offHigh);
#else
    addRegionSumsToNode(blocks, blockRegionOffset(node), low, high);
#endif
  }
}
