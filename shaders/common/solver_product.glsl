// One particle's part of the semi-implicit solve's Hessian product β Δt² H u (common/solver.glsl), for both shapes of
// the product: solver_product.comp (a tile of base nodes per invocation, its region in private arrays) and
// solver_product_block.comp (a block per work group, an invocation per particle, its region in shared memory). The
// particle gathers the velocity gradient G = Σᵢ uᵢ ∇wᵢₚᵀ from u at its stencil's nodes (δF = Δt G F, the change of F
// if the nodes moved Δt u), takes δP Fᵀ from its stiffness (common/material_hessians.glsl; δP = ∂²Ψ/∂F² : δF) and
// adds β Δt V0 δP Fᵀ ∇wᵢₚ to each node, as P2G adds the force of τ (Stomakhin 2013 §6 and eq. 9). Plasticity is held
// fixed for the step: F is F_E. The first product of a step (FIRN_SOLVER_FIRST_PRODUCT, of the start x₀) also adds
// β Δt² Hᵢᵢ, the Hessian's 3×3 block at each node, for the block preconditioner. Where the scene has rigid bodies a
// last product takes the solution x, which solver_solution.comp leaves in z: at the nodes the colliders hold, its held
// components are the constraints' push on the snow (solver_finish.comp, common/colliders.glsl).
//
// Each contribution to a node is rounded to the solve's 64-bit fixed point on its own (productToFixed64) and the
// region sums them as 64-bit integers, exact in any order: the two shapes write the same bytes, as P2G's do
// (sim/TransferShape.h), and neither needs the particles in a fixed order. The values are precise (as the weights,
// common/bspline.glsl), so that the two programs compute each contribution to the same bits.
//
// The pass says where its region lives, `offset` counted from the region's first node:
vec3 productVectorAt(ivec3 offset);                               // u there (m/s)
void addProductToRegion(ivec3 offset, uvec3 low, ivec3 high);     // adds a product contribution there
#ifdef FIRN_SOLVER_FIRST_PRODUCT
void addStiffnessBlockToRegion(ivec3 offset, uvec3 diagonalLow, ivec3 diagonalHigh, uvec3 offDiagonalLow,
                               ivec3 offDiagonalHigh);             // adds a stiffness block's diagonal, yz zx xy
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

// The stencil node k's term uᵢ ∇wᵢₚᵀ of the velocity gradient (`gradient` its ∇wᵢₚ); `base` is the stencil's first
// node in the region.
mat3 gatherFromNode(ivec3 k, vec3 gradient, ivec3 base) {
  precise mat3 term = outerProduct(productVectorAt(base + k), gradient);
  return term;
}

// Rounds a node's product contribution, stressUnits ∇w (`gradient` the node's ∇w), and adds it to the region at
// `offset`; false when it was too large for the fixed point (dropped, for the pass to report).
bool scatterToNode(mat3 stressUnits, vec3 gradient, ivec3 offset) {
  precise vec3 contribution = stressUnits * gradient;
  uvec4 low;
  ivec4 high;
  bool fits = productToFixed64(vec4(contribution, 0.0), low, high);
  addProductToRegion(offset, low.xyz, high.xyz);
  return fits;
}

#ifdef FIRN_SOLVER_FIRST_PRODUCT
// The first product's: also the particle's share of the node's stiffness block, `blockUnits` times
// stiffnessBlock. The iterations' products leave the blocks out, and with them two thirds of the region's traffic.
bool scatterToNodeWithBlock(mat3 stressUnits, float blockUnits, StiffnessBlockForm form, vec3 gradient, ivec3 offset) {
  bool fits = scatterToNode(stressUnits, gradient, offset);
  vec3 blockDiagonal, blockOff;
  stiffnessBlock(form, gradient, blockDiagonal, blockOff);
  precise vec4 diagonalUnits = vec4(blockUnits * blockDiagonal, 0.0);
  precise vec4 offDiagonalUnits = vec4(blockUnits * blockOff, 0.0);
  uvec4 diagonalLow, offLow;
  ivec4 diagonalHigh, offHigh;
  fits = productToFixed64(diagonalUnits, diagonalLow, diagonalHigh) && fits;
  fits = productToFixed64(offDiagonalUnits, offLow, offHigh) && fits;
  addStiffnessBlockToRegion(offset, diagonalLow.xyz, diagonalHigh.xyz, offLow.xyz, offHigh.xyz);
  return fits;
}
#endif

// G = Σᵢ uᵢ ∇wᵢₚᵀ over the stencil, its nodes in stencilOffset's order (the same sum, to the bit, in either shape).
// The tiles (FIRN_PRODUCT_BY_ROWS) take the stencil row by row along x, each row written out, so that their private
// arrays' indices differ by constants: walking the stencil slowed them on llvmpipe (docs/platform.md, Timing on
// llvmpipe). The blocks walk it, since NVIDIA's compiler makes each read of a weight at a variable index a chain of
// branches (common/kernel.glsl, StencilWalk).
mat3 gatherVelocityGradient(Stencil stencil, ivec3 base) {
  precise mat3 velocityGradient = mat3(0.0);
#ifdef FIRN_PRODUCT_BY_ROWS
  for (int yz = 0; yz < KERNEL_WIDTH * KERNEL_WIDTH; ++yz) {
    ivec3 k = ivec3(0, yz % KERNEL_WIDTH, yz / KERNEL_WIDTH);
    velocityGradient += gatherFromNode(k, stencilGradient(stencil, k), base);
    velocityGradient += gatherFromNode(k + ivec3(1, 0, 0), stencilGradient(stencil, k + ivec3(1, 0, 0)), base);
    velocityGradient += gatherFromNode(k + ivec3(2, 0, 0), stencilGradient(stencil, k + ivec3(2, 0, 0)), base);
#ifdef FIRN_KERNEL_CUBIC
    velocityGradient += gatherFromNode(k + ivec3(3, 0, 0), stencilGradient(stencil, k + ivec3(3, 0, 0)), base);
#endif
  }
#else
  StencilWalk walk = beginStencilWalk(stencil);
  for (int n = 0; n < KERNEL_NODES; ++n) {
    velocityGradient += gatherFromNode(walk.k, walkGradient(walk), base);
    advanceStencilWalk(walk);
  }
#endif
  return velocityGradient;
}

// Particle p's contributions to the region whose first node is `regionFirstNode`; false when one was dropped.
bool scatterProductParticle(uint p, ivec3 regionFirstNode) {
  vec3 x = positionMass[p].xyz;
  Stencil stencil = particleStencil(x);
  ivec3 base = stencil.baseNode - regionFirstNode;
  precise mat3 velocityGradient = gatherVelocityGradient(stencil, base);
  SolverParticle stiffness = solverParticles[p];
#ifdef FIRN_SOLVER_FORCE_DIFFERENCE
  mat3 F = elasticDeformation[p];
  mat3 dF = dtS * velocityGradient * F;
  ParticlePlasticState state = plasticState[p];
  MaterialParams material = materials[state.materialIndex];
  precise mat3 stressTimesFT =
      0.5 * (firstPiolaStress(F + dF, material, state.plasticJ) - firstPiolaStress(F - dF, material, state.plasticJ)) *
      transpose(F);
#else
  precise mat3 stressTimesFT = stressDifferentialTimesFT(stiffness, velocityGradient, dtS);
#endif
  // β Δt V0 δP Fᵀ in momentum units per unit of ∇w (m), and β Δt² V0 (Pa/m² of stiffnessBlock to kg) in reference
  // masses.
  float volume = velocityVolume[p].w;
  precise mat3 stressUnits = (implicitRatio * dtS * volume * momentumUnitsPerKgMPerS) * stressTimesFT;
  bool fits = true;
#ifdef FIRN_SOLVER_FIRST_PRODUCT
  precise float blockUnits = implicitRatio * dtS * dtS * volume * massUnitsPerKg;
  StiffnessBlockForm form = stiffnessBlockForm(stiffness);
  StencilWalk walk = beginStencilWalk(stencil);
  for (int n = 0; n < KERNEL_NODES; ++n) {
    fits = scatterToNodeWithBlock(stressUnits, blockUnits, form, walkGradient(walk), base + walk.k) && fits;
    advanceStencilWalk(walk);
  }
#elif defined(FIRN_PRODUCT_BY_ROWS)
  for (int yz = 0; yz < KERNEL_WIDTH * KERNEL_WIDTH; ++yz) {
    ivec3 k = ivec3(0, yz % KERNEL_WIDTH, yz / KERNEL_WIDTH);
    fits = scatterToNode(stressUnits, stencilGradient(stencil, k), base + k) && fits;
    fits = scatterToNode(stressUnits, stencilGradient(stencil, k + ivec3(1, 0, 0)), base + k + ivec3(1, 0, 0)) && fits;
    fits = scatterToNode(stressUnits, stencilGradient(stencil, k + ivec3(2, 0, 0)), base + k + ivec3(2, 0, 0)) && fits;
#ifdef FIRN_KERNEL_CUBIC
    fits = scatterToNode(stressUnits, stencilGradient(stencil, k + ivec3(3, 0, 0)), base + k + ivec3(3, 0, 0)) && fits;
#endif
  }
#else
  StencilWalk walk = beginStencilWalk(stencil);
  for (int n = 0; n < KERNEL_NODES; ++n) {
    fits = scatterToNode(stressUnits, walkGradient(walk), base + walk.k) && fits;
    advanceStencilWalk(walk);
  }
#endif
  return fits;
}

// u at the node stored at `address` (m/s): the solve's start x₀ for the first product, else the preconditioned
// residual z; 0 for a node past the pool (address < 0). Each shape reads its region's u through this.
vec3 productVectorOfNode(int address) {
  if (address < 0) return vec3(0.0);
#ifdef FIRN_SOLVER_FIRST_PRODUCT
  return solverNodes[address].direction.xyz;
#else
  return solverNodes[address].preconditioned.xyz;
#endif
}

// Adds a region node's sums to the node `offset` from the region's first (`blocks` its stencilBlocks): nothing where
// they are all zero, or where the node's block lies past the pool's capacity (the host sees the count and grows the
// pool). The first product's also carry the stiffness block's diagonal and its entries yz, zx, xy.
#ifdef FIRN_SOLVER_FIRST_PRODUCT
void addRegionSumsToNode(StencilBlocks blocks, ivec3 offset, uvec4 low, ivec4 high, uvec4 diagonalLow,
                         ivec4 diagonalHigh, uvec4 offDiagonalLow, ivec4 offDiagonalHigh) {
  bool hasProduct = nonzero(low, high);
  bool hasBlock = nonzero(diagonalLow, diagonalHigh) || nonzero(offDiagonalLow, offDiagonalHigh);
  if (!hasProduct && !hasBlock) return;
  int address = stencilNodeAddress(blocks, offset);
  if (address < 0) return;
  if (hasProduct) addProductToNode(uint(address), low, high);
  if (hasBlock) addStiffnessBlockToNode(uint(address), diagonalLow, diagonalHigh, offDiagonalLow, offDiagonalHigh);
}
#else
void addRegionSumsToNode(StencilBlocks blocks, ivec3 offset, uvec4 low, ivec4 high) {
  if (!nonzero(low, high)) return;
  int address = stencilNodeAddress(blocks, offset);
  if (address >= 0) addProductToNode(uint(address), low, high);
}
#endif
