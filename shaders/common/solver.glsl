// The semi-implicit solve's storage and arithmetic (docs/numerics.md, "The semi-implicit solve").
//
// Stomakhin et al. 2013 eq. 9 takes the grid velocities of the step from (I + β Δt² M⁻¹ H) v = v*, H = ∂²Φ/∂x² the
// Hessian of the elastic energy and v* the explicit update (update_grid.comp). Firn solves the same system in its
// symmetric form A v = M v*, A = M + β Δt² H, by the conjugate residual method, with the colliders and walls as
// constraints: the projection S of each node's held components (SolverNode.constraint) is applied to every residual
// and product, so the held components keep the collided values of v*. H is the Hessian with each particle's stiffness
// projected onto the positive semi-definite (common/material_hessians.glsl), so A is positive definite on the free
// components. The preconditioner is Jacobi's, P = M + β Δt² diag(H) with a node's diagonal the mean of its 3×3 block:
// M alone (eq. 9's own scaling) lets the nodes at a body's surface, whose mass is a sliver of their stiffness, set
// the spectrum's top.
//
// Determinism. A Hessian product is summed at the nodes from every particle's contribution, like P2G. Its
// contributions are (c Δt / h)² times larger than the product they add up to, too many bits for P2G's 32-bit fixed
// point. A tile sums its particles' contributions in float, in the particles' index order within each bin
// (solver_order_bins.comp), which repeats; the tiles' sums, which reach a node in no fixed order, are added there as
// 64-bit integers, two 32-bit words with the carry: exact, so the same whatever the order. A dot product is summed
// within a block in a fixed order, and over the blocks, whose slots follow no fixed order, as 64-bit integers at a
// scale set by the largest block's partial sum: again exact. A run repeats to the bit.
#include "common/fixed64.glsl"
#include "common/watchdog.glsl"

//
// This file declares the nodes' vectors; common/solver_reduction.glsl the status and the dot products' sums. A
// compute shader may declare 16 storage blocks on llvmpipe, which counts every block declared, used or not
// (docs/platform.md), so the passes include what they use.

layout(std430, binding = FIRN_BINDING_SOLVER_NODES) coherent buffer SolverNodeBuffer { SolverNode solverNodes[]; };

float implicitRatio() { return solver.x; }
float toleranceSquared() { return solver.y; }

// --- Hessian products at the nodes -------------------------------------------------------------------------------

// A tile's sum at a node in momentum units (xyz; w the diagonal's, in reference masses), as the 64-bit integers of
// units 2^−k_H; one too large (or NaN) is dropped and reported: k_H leaves 2^8 of headroom over the stiffest wave the
// scene states (sim/FixedPoint.h).
bool productToFixed64(vec4 units, out uvec4 low, out ivec4 high) {
  vec4 scaled = floor(units * solver.z + 0.5);
  bool fits = all(lessThan(abs(scaled), vec4(FIXED64_LIMIT)));  // also false for NaN
  splitFixed64(fits ? scaled : vec4(0.0), low, high);
  return fits;
}

// Adds a node's sums, a word at a time: the low word's atomicAdd returns the sum before, which tells whether it
// carried into the high word. The words end as the exact 64-bit sum whatever the order of the additions.
void addProductToNode(uint address, uvec4 low, ivec4 high) {
  for (int c = 0; c < 4; ++c) {
    if (low[c] == 0u && high[c] == 0) continue;
    uint previous = atomicAdd(solverNodes[address].productLow[c], low[c]);
    int carry = previous + low[c] < previous ? 1 : 0;
    if (high[c] + carry != 0) atomicAdd(solverNodes[address].productHigh[c], high[c] + carry);
  }
}

// A node's Hessian product (xyz, kg·m/s: β Δt² H u) and, after the first product of a step, the stiffness part of
// the preconditioner's diagonal (w, kg: β Δt² tr(Hᵢᵢ) / 3); the sums are cleared for the next product.
vec4 takeProduct(uint address) {
  vec4 sums = fixed64ToFloat(solverNodes[address].productLow, solverNodes[address].productHigh);
  solverNodes[address].productLow = uvec4(0u);
  solverNodes[address].productHigh = ivec4(0);
  return sums * solver.w * vec4(vec3(fixedPoint.y), fixedPoint.x);
}

// --- Constraints -------------------------------------------------------------------------------------------------

// S v: the components the node's constraint leaves free.
vec3 constrain(vec3 v, vec4 constraint) {
  int code = int(constraint.w);
  if ((code & CONSTRAINT_FIXED) != 0) return vec3(0.0);
  if ((code & CONSTRAINT_NORMAL) != 0) v -= dot(v, constraint.xyz) * constraint.xyz;
  ivec3 walls = ivec3(code) & ivec3(CONSTRAINT_WALL_X, 2 * CONSTRAINT_WALL_X, 4 * CONSTRAINT_WALL_X);
  return mix(v, vec3(0.0), notEqual(walls, ivec3(0)));
}

// The preconditioner P⁻¹ = diag(M + β Δt² H)⁻¹ at a node of `massKg` and diagonal `diagonalKg` (residual.w): Jacobi's,
// with H's diagonal as the mean of its 3×3 block's. 0 for a node without mass, which the constraints hold.
float inversePreconditioner(float massKg, float diagonalKg) { return massKg > 0.0 ? 1.0 / diagonalKg : 0.0; }
