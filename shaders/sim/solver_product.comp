#version 430 core
// The semi-implicit solve's Hessian product, β Δt² H u (common/solver.glsl): a transfer over the tiles of base nodes
// like P2G (p2g.comp, common/blocks.glsl). The invocation reads u at its tile's region of nodes once, then for each
// particle of the tile gathers δF = Δt (Σ_i u_i ∇w_ipᵀ) F (the change of F if the nodes moved Δt u), takes the
// stress differential δP = ∂²Ψ/∂F² : δF (common/material_hessians.glsl) and scatters β Δt V0 δP Fᵀ ∇w_ip to the
// region, as P2G scatters the force of τ (Stomakhin 2013 §6 and eq. 9). Plasticity is held fixed for the step:
// F is F_E. The region's sums go to the nodes as 64-bit integers (exact, so deterministic).
// u is x₀ = v* (the initial residual, `productOfSolution` 1, which update_grid.comp left in the direction) or the
// preconditioned residual z.
// Reads: particle state, solverParticles, the block table and map, bins, sortedParticles, tileOrder, the solver's
// vectors. Writes: the solver's product sums, the watchdog.
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/blocks.glsl"
#include "common/solver.glsl"
#include "common/material_hessians.glsl"

layout(local_size_x = FIRN_TILE_GROUP_SIZE) in;

uniform uint productOfSolution;

vec3 regionVector[REGION_NODES];  // u at the region's nodes (m/s)
uvec3 sumLow[REGION_NODES];       // the region's sums, 64-bit
ivec3 sumHigh[REGION_NODES];
bool overflowed = false;

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
    kirchhoff = lame.x * (F * transpose(F) - mat3(1.0)) + lame.y * log(determinant(F)) * mat3(1.0);
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
    if (address >= 0) u = productOfSolution != 0u ? solverNodes[address].direction.xyz : solverNodes[address].preconditioned.xyz;
    regionVector[i] = u;
    sumLow[i] = uvec3(0u);
    sumHigh[i] = ivec3(0);
  }
}

// Adds the contribution stress · ∇w of the stencil's node k to its region sum.
void scatterToNode(mat3 stressUnits, Stencil stencil, ivec3 k, ivec3 bin) {
  uvec3 low;
  ivec3 high;
  overflowed = !productToFixed64(stressUnits * stencilGradient(stencil, k), low, high) || overflowed;
  int i = regionIndex(bin + k);
  addFixed64(sumLow[i], sumHigh[i], low, high);
}

// The product's contribution of particle p, whose base node is the tile's `bin`-th.
void scatterParticle(uint p, ivec3 bin) {
  vec3 x = positionMass[p].xyz;
  Stencil stencil = particleStencil(x);
  mat3 velocityGradient = mat3(0.0);  // Σ_i u_i ∇w_ipᵀ
  for (int n = 0; n < KERNEL_NODES; ++n) {
    ivec3 k = stencilOffset(n);
    velocityGradient += outerProduct(regionVector[regionIndex(bin + k)], stencilGradient(stencil, k));
  }
  mat3 F = elasticDeformation[p];
  mat3 dF = stepDt() * velocityGradient * F;
  ParticlePlasticState state = plasticState[p];
  MaterialParams material = materials[state.materialIndex];
#ifdef FIRN_SOLVER_FORCE_DIFFERENCE
  mat3 dP = 0.5 * (firstPiolaStress(F + dF, material, state.plasticJ) - firstPiolaStress(F - dF, material, state.plasticJ));
#else
  mat3 dP = stressDifferential(p, F, dF, material, state.plasticJ);
#endif
  // β Δt V0 δP Fᵀ in momentum units per unit of ∇w (m).
  mat3 stressUnits = (implicitRatio() * stepDt() * velocityVolume[p].w / fixedPoint.y) * (dP * transpose(F));
  for (int yz = 0; yz < KERNEL_WIDTH * KERNEL_WIDTH; ++yz) {
    ivec3 k = ivec3(0, yz % KERNEL_WIDTH, yz / KERNEL_WIDTH);
    scatterToNode(stressUnits, stencil, k, bin);
    scatterToNode(stressUnits, stencil, k + ivec3(1, 0, 0), bin);
    scatterToNode(stressUnits, stencil, k + ivec3(2, 0, 0), bin);
#ifdef FIRN_KERNEL_CUBIC
    scatterToNode(stressUnits, stencil, k + ivec3(3, 0, 0), bin);
#endif
  }
}

void main() {
  uint entry = workGroupSlot() * uint(FIRN_TILE_GROUP_SIZE) + gl_LocalInvocationIndex;
  if (entry >= tileCounts.x) return;
  uint slot = tileOrder[entry] / uint(BLOCK_TILES);
  uint tile = tileOrder[entry] % uint(BLOCK_TILES);
  ivec3 firstBase = tileFirstBase(slot, tile);

  loadRegion(firstBase);
  overflowed = false;
  for (int b = 0; b < TILE_BASE_NODES; ++b) {
    uvec2 particles = binParticles(slot, tileFirstBin(tile) + uint(b));  // first, count
    ivec3 bin = ivec3(b % TILE_WIDTH, b / TILE_WIDTH, 0);
    for (uint j = particles.x; j < particles.x + particles.y; ++j) scatterParticle(sortedParticles[j], bin);
  }
  if (overflowed) reportOverflow(nodeIndex(firstBase), CHANNEL_SOLVER);

  StencilBlocks blocks = stencilBlocks(firstBase);
  for (int i = 0; i < REGION_NODES; ++i) {
    if (sumLow[i] == uvec3(0u) && sumHigh[i] == ivec3(0)) continue;
    int address = stencilNodeAddress(blocks, regionOffset(i));
    if (address >= 0) addProductToNode(uint(address), sumLow[i], sumHigh[i]);
  }
}
