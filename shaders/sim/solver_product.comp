#version 430 core
// The semi-implicit solve's Hessian product, β Δt² H u (common/solver.glsl, common/solver_product.glsl), shaped for
// CPU renderers as P2G's tiles (p2g.comp): an invocation per tile of base nodes reads u at its tile's region of
// nodes once, adds each particle's rounded contributions to the region's 64-bit sums in private arrays, and then the
// region's sums to the nodes. solver_product_block.comp is the same product shaped for GPUs; a run times both and
// keeps the faster (ImplicitSolver::timeProducts), and both write the same bytes.
// u is the preconditioned residual z, or, built with FIRN_SOLVER_FIRST_PRODUCT, the start x₀ of the initial residual,
// which update_grid.comp left in the direction: the first product of a step also sums the nodes' stiffness blocks.
// In the solve its dispatch is the solve's status's solveProductDispatch record: the dispatch's commands, which the
// shader does not read.
// Reads: blockTable (tileCounts.x and slots[] and after the solve the tileDispatch record), tileOrder, bins,
//        sortedParticles, blockMap, positionMass (xyz), velocityVolume (w: V0), solverParticles,
//        elasticDeformation (FIRN_SOLVER_FORCE_DIFFERENCE test builds), plasticState (the same test builds),
//        materials (the same test builds), solverNodes (u: direction or else preconditioned and the sums' old words),
//        watchdog (the reports' atomics' old values).
// Writes: solverNodes (the product sums and in the first product the stiffness blocks' sums),
//         watchdog (contributions too large for the fixed point).
#define FIRN_WITHOUT_SOLVER_PRECONDITIONER
#define FIRN_PRODUCT_BY_ROWS  // common/solver_product.glsl: the stencil row by row, for CPU renderers
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/blocks.glsl"
#include "common/solver.glsl"
#include "common/material_hessians.glsl"
#include "common/solver_product.glsl"

layout(local_size_x = FIRN_TILE_GROUP_SIZE) in;

vec3 regionVector[REGION_NODES];  // u at the region's nodes (m/s)
uvec3 regionLow[REGION_NODES];    // the region's sums of the product, 64-bit (common/fixed64.glsl)
ivec3 regionHigh[REGION_NODES];
#ifdef FIRN_SOLVER_FIRST_PRODUCT
uvec3 regionDiagonalLow[REGION_NODES];  // and of the nodes' stiffness blocks: their diagonals
ivec3 regionDiagonalHigh[REGION_NODES];
uvec3 regionOffDiagonalLow[REGION_NODES];  // and their entries yz, zx, xy
ivec3 regionOffDiagonalHigh[REGION_NODES];
#endif

void loadRegion(ivec3 firstBase) {
  StencilBlocks blocks = stencilBlocks(firstBase);
  for (int i = 0; i < REGION_NODES; ++i) {
    regionVector[i] = productVectorOfNode(stencilNodeAddress(blocks, regionOffset(i)));
#ifdef FIRN_SOLVER_FIRST_PRODUCT
    regionDiagonalLow[i] = regionOffDiagonalLow[i] = uvec3(0u);
    regionDiagonalHigh[i] = regionOffDiagonalHigh[i] = ivec3(0);
#endif
    regionLow[i] = uvec3(0u);
    regionHigh[i] = ivec3(0);
  }
}

vec3 productVectorAt(ivec3 offset) { return regionVector[regionIndex(offset)]; }

void addProductToRegion(ivec3 offset, uvec3 low, ivec3 high) {
  int r = regionIndex(offset);
  addFixed64(regionLow[r], regionHigh[r], low, high);
}

#ifdef FIRN_SOLVER_FIRST_PRODUCT
void addStiffnessBlockToRegion(ivec3 offset, uvec3 diagonalLow, ivec3 diagonalHigh, uvec3 offDiagonalLow,
                               ivec3 offDiagonalHigh) {
  int r = regionIndex(offset);
  addFixed64(regionDiagonalLow[r], regionDiagonalHigh[r], diagonalLow, diagonalHigh);
  addFixed64(regionOffDiagonalLow[r], regionOffDiagonalHigh[r], offDiagonalLow, offDiagonalHigh);
}
#endif

void main() {
  uint entry = workGroupSlot() * uint(FIRN_TILE_GROUP_SIZE) + gl_LocalInvocationIndex;
  if (entry >= tileCounts.x) return;
  uint slot = tileOrder[entry] / uint(BLOCK_TILES);
  uint tile = tileOrder[entry] % uint(BLOCK_TILES);
  ivec3 firstBase = tileFirstBase(slot, tile);

  loadRegion(firstBase);
  bool fits = true;
  for (int b = 0; b < TILE_BASE_NODES; ++b) {
    uvec2 particles = binParticles(slot, tileFirstBin(tile) + uint(b));  // first, count
    for (uint j = particles.x; j < particles.x + particles.y; ++j) {
      fits = scatterProductParticle(sortedParticles[j], firstBase) && fits;
    }
  }
  StencilBlocks blocks = stencilBlocks(firstBase);
  for (int i = 0; i < REGION_NODES; ++i) {
#ifdef FIRN_SOLVER_FIRST_PRODUCT
    addRegionSumsToNode(blocks, regionOffset(i), uvec4(regionLow[i], 0u), ivec4(regionHigh[i], 0),
                        uvec4(regionDiagonalLow[i], 0u), ivec4(regionDiagonalHigh[i], 0),
                        uvec4(regionOffDiagonalLow[i], 0u), ivec4(regionOffDiagonalHigh[i], 0));
#else
    addRegionSumsToNode(blocks, regionOffset(i), uvec4(regionLow[i], 0u), ivec4(regionHigh[i], 0));
#endif
  }
  if (!fits) reportOverflow(nodeIndex(firstBase), CHANNEL_SOLVER);
}
