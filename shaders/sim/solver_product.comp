#version 430 core
// The semi-implicit solve's Hessian product, β Δt² H u (common/solver.glsl): a transfer over the tiles of base nodes
// like P2G (p2g.comp, common/blocks.glsl). The invocation reads u at its tile's region of nodes once, then for each
// particle of the tile gathers the velocity gradient G = Σᵢ uᵢ ∇wᵢₚᵀ (δF = Δt G F, the change of F if the nodes moved
// Δt u), takes δP Fᵀ from the particle's stiffness (common/material_hessians.glsl; δP = ∂²Ψ/∂F² : δF) and scatters
// β Δt V0 δP Fᵀ ∇wᵢₚ to the region, as P2G scatters the force of τ (Stomakhin 2013 §6 and eq. 9). Plasticity is held
// fixed for the step: F is F_E. The region's sums are float, taken particle by particle in the tile's order, which
// solver_order_bins.comp made the particles' index order, so they repeat to the bit; they go to the nodes as 64-bit
// integers (common/solver.glsl), exact whatever the order of the tiles. A contribution rounded to 64 bits one by one,
// as P2G quantizes its own, cost a quarter of the product and bought no accuracy: each is a float to begin with.
// u is the preconditioned residual z, or, built with FIRN_SOLVER_FIRST_PRODUCT, the start x₀ of the initial residual,
// which update_grid.comp left in the direction: the first product of a step also sums β Δt² Hᵢᵢ, the Hessian's 3×3
// block at each node, for the block preconditioner (common/solver.glsl).
// Reads: particle state, solverParticles, the block table and map, bins, sortedParticles, tileOrder, the solver's
// vectors. Writes: the solver's product sums, the watchdog.
#define FIRN_WITHOUT_SOLVER_PRECONDITIONER
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/blocks.glsl"
#include "common/solver.glsl"
#include "common/material_hessians.glsl"

layout(local_size_x = FIRN_TILE_GROUP_SIZE) in;

vec3 regionVector[REGION_NODES];  // u at the region's nodes (m/s)
vec3 regionSum[REGION_NODES];     // the region's sums of the product
#ifdef FIRN_SOLVER_FIRST_PRODUCT
vec3 regionDiagonal[REGION_NODES];     // and of the nodes' stiffness blocks: their diagonals
vec3 regionOffDiagonal[REGION_NODES];  // and their entries yz, zx, xy
#endif

#ifdef FIRN_SOLVER_FORCE_DIFFERENCE
// Test builds (tests/gl/SemiImplicitTest.cpp) put the central difference of the stress the explicit force comes
// from, (P(F + δF) − P(F − δF)) / 2 with P = τ F⁻ᵀ and τ as materials.glsl computes it, in place of δP.
mat3 firstPiolaStress(mat3 F, MaterialParams m, float plasticJ) {
  vec2 lame = currentLameParameters(m, plasticJ);
  mat3 kirchhoff = mat3(0.0);
#if defined(FIRN_MATERIAL_SNOW) || defined(FIRN_MATERIAL_FIXED_COROTATED)
  if (m.model.x == MODEL_SNOW || m.model.x == MODEL_FIXED_COROTATED) {
    mat3 U, V;
    vec3 sigma;
    svd3(F, U, sigma, V);
    kirchhoff = fixedCorotatedStress(F, U, sigma, lame.x, lame.y);
  }
#endif
#ifdef FIRN_MATERIAL_NEO_HOOKEAN
  if (m.model.x == MODEL_NEO_HOOKEAN) {
    kirchhoff = neoHookeanStress(F, lame.x, lame.y);
  }
#endif
  return kirchhoff * transpose(inverse(F));
}
#endif

void loadRegion(ivec3 firstBase) {
  StencilBlocks blocks = stencilBlocks(firstBase);
  for (int i = 0; i < REGION_NODES; ++i) {
    int address = stencilNodeAddress(blocks, regionOffset(i));
    vec3 u = vec3(0.0);
#ifdef FIRN_SOLVER_FIRST_PRODUCT
    if (address >= 0) u = solverNodes[address].direction.xyz;
    regionDiagonal[i] = regionOffDiagonal[i] = vec3(0.0);
#else
    if (address >= 0) u = solverNodes[address].preconditioned.xyz;
#endif
    regionVector[i] = u;
    regionSum[i] = vec3(0.0);
  }
}

// The stencil's node k's term uᵢ ∇wᵢₚᵀ of the velocity gradient.
mat3 gatherFromNode(Stencil stencil, ivec3 k, ivec3 bin) {
  return outerProduct(regionVector[regionIndex(bin + k)], stencilGradient(stencil, k));
}

// Adds the contribution stress · ∇w of the stencil's node k to its region sum.
void scatterToNode(mat3 stressUnits, Stencil stencil, ivec3 k, ivec3 bin) {
  regionSum[regionIndex(bin + k)] += stressUnits * stencilGradient(stencil, k);
}

#ifdef FIRN_SOLVER_FIRST_PRODUCT
// The first product's: adds the contribution stress · ∇w of the stencil's node k, and the particle's share of the
// node's stiffness block, `blockUnits` times stiffnessBlock, to its region sums. The iterations' products leave the
// blocks out, and with them two thirds of the region's sums' traffic.
void scatterToNodeWithBlock(mat3 stressUnits, float blockUnits, StiffnessBlockForm form, Stencil stencil, ivec3 k,
                            ivec3 bin) {
  vec3 gradient = stencilGradient(stencil, k);
  int r = regionIndex(bin + k);
  regionSum[r] += stressUnits * gradient;
  vec3 blockDiagonal, blockOff;
  stiffnessBlock(form, gradient, blockDiagonal, blockOff);
  regionDiagonal[r] += blockUnits * blockDiagonal;
  regionOffDiagonal[r] += blockUnits * blockOff;
}
#endif

// The product's contribution of particle p, whose base node is the tile's `bin`-th.
void scatterParticle(uint p, ivec3 bin) {
  vec3 x = positionMass[p].xyz;
  Stencil stencil = particleStencil(x);
  // G = Σᵢ uᵢ ∇wᵢₚᵀ, the stencil row by row along x with each row written out, as the scatter below: the product
  // took 6% less time on llvmpipe than with one loop over the stencil's nodes.
  mat3 velocityGradient = mat3(0.0);
  for (int yz = 0; yz < KERNEL_WIDTH * KERNEL_WIDTH; ++yz) {
    ivec3 k = ivec3(0, yz % KERNEL_WIDTH, yz / KERNEL_WIDTH);
    velocityGradient += gatherFromNode(stencil, k, bin);
    velocityGradient += gatherFromNode(stencil, k + ivec3(1, 0, 0), bin);
    velocityGradient += gatherFromNode(stencil, k + ivec3(2, 0, 0), bin);
#ifdef FIRN_KERNEL_CUBIC
    velocityGradient += gatherFromNode(stencil, k + ivec3(3, 0, 0), bin);
#endif
  }
  SolverParticle stiffness = solverParticles[p];
#ifdef FIRN_SOLVER_FORCE_DIFFERENCE
  mat3 F = elasticDeformation[p];
  mat3 dF = dtS * velocityGradient * F;
  ParticlePlasticState state = plasticState[p];
  MaterialParams material = materials[state.materialIndex];
  mat3 dP = 0.5 * (firstPiolaStress(F + dF, material, state.plasticJ) - firstPiolaStress(F - dF, material, state.plasticJ));
  mat3 stressTimesFT = dP * transpose(F);
#else
  mat3 stressTimesFT = stressDifferentialTimesFT(stiffness, velocityGradient, dtS);
#endif
  // β Δt V0 δP Fᵀ in momentum units per unit of ∇w (m), and β Δt² V0 (Pa/m² of stiffnessBlock to kg) in reference
  // masses.
  float volume = velocityVolume[p].w;
  mat3 stressUnits = (implicitRatio * dtS * volume / momentumUnitKgMPerS) * stressTimesFT;
#ifdef FIRN_SOLVER_FIRST_PRODUCT
  float blockUnits = implicitRatio * dtS * dtS * volume / referenceMassKg;
  StiffnessBlockForm form = stiffnessBlockForm(stiffness);
  for (int n = 0; n < KERNEL_NODES; ++n) {
    scatterToNodeWithBlock(stressUnits, blockUnits, form, stencil, stencilOffset(n), bin);
  }
#else
  for (int yz = 0; yz < KERNEL_WIDTH * KERNEL_WIDTH; ++yz) {
    ivec3 k = ivec3(0, yz % KERNEL_WIDTH, yz / KERNEL_WIDTH);
    scatterToNode(stressUnits, stencil, k, bin);
    scatterToNode(stressUnits, stencil, k + ivec3(1, 0, 0), bin);
    scatterToNode(stressUnits, stencil, k + ivec3(2, 0, 0), bin);
#ifdef FIRN_KERNEL_CUBIC
    scatterToNode(stressUnits, stencil, k + ivec3(3, 0, 0), bin);
#endif
  }
#endif
}

void main() {
  uint entry = workGroupSlot() * uint(FIRN_TILE_GROUP_SIZE) + gl_LocalInvocationIndex;
  if (entry >= tileCounts.x) return;
  uint slot = tileOrder[entry] / uint(BLOCK_TILES);
  uint tile = tileOrder[entry] % uint(BLOCK_TILES);
  ivec3 firstBase = tileFirstBase(slot, tile);

  loadRegion(firstBase);
  for (int b = 0; b < TILE_BASE_NODES; ++b) {
    uvec2 particles = binParticles(slot, tileFirstBin(tile) + uint(b));  // first, count
    ivec3 bin = ivec3(b % TILE_WIDTH, b / TILE_WIDTH, 0);
    for (uint j = particles.x; j < particles.x + particles.y; ++j) scatterParticle(sortedParticles[j], bin);
  }
  StencilBlocks blocks = stencilBlocks(firstBase);
  bool overflowed = false;
  for (int i = 0; i < REGION_NODES; ++i) {
    bool hasProduct = regionSum[i] != vec3(0.0);
#ifdef FIRN_SOLVER_FIRST_PRODUCT
    // A block is positive semi-definite: a zero diagonal is a zero block.
    bool hasBlock = regionDiagonal[i] != vec3(0.0);
#else
    const bool hasBlock = false;
#endif
    if (!hasProduct && !hasBlock) continue;
    int address = stencilNodeAddress(blocks, regionOffset(i));
    uvec4 low;
    ivec4 high;
    if (hasProduct) {
      overflowed = !productToFixed64(vec4(regionSum[i], 0.0), low, high) || overflowed;
      if (address >= 0) addProductToNode(uint(address), low, high);
    }
#ifdef FIRN_SOLVER_FIRST_PRODUCT
    if (hasBlock) {
      uvec4 offLow;
      ivec4 offHigh;
      overflowed = !productToFixed64(vec4(regionDiagonal[i], 0.0), low, high) || overflowed;
      overflowed = !productToFixed64(vec4(regionOffDiagonal[i], 0.0), offLow, offHigh) || overflowed;
      if (address >= 0) addStiffnessBlockToNode(uint(address), low, high, offLow, offHigh);
    }
#endif
  }
  if (overflowed) reportOverflow(nodeIndex(firstBase), CHANNEL_SOLVER);
}
