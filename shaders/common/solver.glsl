// The semi-implicit solve's storage and arithmetic (docs/numerics.md, "The semi-implicit solve").
//
// Stomakhin et al. 2013 eq. 9 takes the grid velocities of the step from (I + β Δt² M⁻¹ H) v = v*, H = ∂²Φ/∂x² the
// Hessian of the elastic energy and v* the explicit update (update_grid.comp). Firn solves the same system in its
// symmetric form A v = M v*, A = M + β Δt² H, by the conjugate residual method, with the colliders and walls as
// constraints: the projection S of each node's held components (SolverNode.constraint) is applied to every residual
// and product, so the held components keep the collided values of v*. H is the Hessian with each particle's stiffness
// projected onto the positive semi-definite (common/material_hessians.glsl), so A is positive definite on the free
// components. The preconditioner is block Jacobi's, P = M + β Δt² Hᵢᵢ per node, Hᵢᵢ the Hessian's 3×3 block there
// (common/material_hessians.glsl, stiffnessBlock): M alone (eq. 9's own scaling) lets the nodes at a body's surface,
// whose mass is a sliver of their stiffness, set the spectrum's top, and the block's trace alone misjudges a node
// whose stiffness is all in one direction — at a floor, ∇w is nearly vertical, and the block's tangential entries,
// the ones a landing body slides on, are μ|∇w|² against the trace's third, (4μ + λ)|∇w|² / 3.
//
// Determinism. A Hessian product is summed at the nodes from every particle's contribution, like P2G. Its
// contributions are (c Δt / h)² times larger than the product they add up to, too many bits for P2G's 32-bit fixed
// point. Each contribution is rounded to a 64-bit integer on its own and added as two 32-bit words with the carry
// (common/solver_product.glsl): exact, so the same whatever the order, and the same in either shape of the product
// (solver_product.comp, solver_product_block.comp). A dot product is summed
// within a block in a fixed order, and over the blocks, whose slots follow no fixed order, as 64-bit integers at a
// scale set by the largest block's partial sum: again exact. A run repeats to the bit.
#include "common/fixed64.glsl"
#include "common/watchdog.glsl"

//
// This file declares the nodes' vectors; common/solver_reduction.glsl the status and the dot products' sums. A
// compute shader may declare 16 storage blocks on llvmpipe, which counts every block declared, used or not
// (docs/platform.md), so the passes include what they use.

layout(std430, binding = FIRN_BINDING_SOLVER_NODES) coherent buffer SolverNodesBuffer { SolverNode solverNodes[]; };
// The Hessian products, which take no preconditioner and are at llvmpipe's 16 storage blocks with APIC, define
// FIRN_WITHOUT_SOLVER_PRECONDITIONER.
#ifndef FIRN_WITHOUT_SOLVER_PRECONDITIONER
layout(std430, binding = FIRN_BINDING_SOLVER_PRECONDITIONER) buffer SolverPreconditionerBuffer {
  SolverPreconditioner solverPreconditioners[];
};
#endif

// --- Hessian products at the nodes -------------------------------------------------------------------------------

// A contribution to a node in momentum units (a product), or in reference masses (a stiffness block), as the
// 64-bit integers of units 2^−k_H; one too large (or NaN) is dropped and reported: k_H leaves 2^8 of headroom over
// the stiffest wave the scene states (sim/FixedPoint.h).
bool productToFixed64(vec4 units, out uvec4 low, out ivec4 high) {
  vec4 scaled = floor(units * ldexp(1.0, solverFractionBits) + 0.5);
  bool fits = all(lessThan(abs(scaled), vec4(FIXED64_LIMIT)));  // also false for NaN
  splitFixed64(fits ? scaled : vec4(0.0), low, high);
  return fits;
}

// Adds a region's sums of a Hessian product at a node.
void addProductToNode(uint address, uvec4 low, ivec4 high) {
  FIRN_ADD_FIXED64(solverNodes[address].productLow, solverNodes[address].productHigh, low, high)
}

// Adds a region's sums of the stiffness block at a node: its diagonal and its entries yz, zx, xy.
void addStiffnessBlockToNode(uint address, uvec4 diagonalLow, ivec4 diagonalHigh, uvec4 offDiagonalLow,
                             ivec4 offDiagonalHigh) {
  FIRN_ADD_FIXED64(solverNodes[address].diagonalLow, solverNodes[address].diagonalHigh, diagonalLow, diagonalHigh)
  FIRN_ADD_FIXED64(solverNodes[address].offDiagonalLow, solverNodes[address].offDiagonalHigh, offDiagonalLow,
                   offDiagonalHigh)
}

// A node's Hessian product (kg·m/s: β Δt² H u); the sums are cleared for the next product.
vec3 takeProduct(uint address) {
  vec3 sums = fixed64ToFloat(solverNodes[address].productLow, solverNodes[address].productHigh).xyz;
  solverNodes[address].productLow = uvec4(0u);
  solverNodes[address].productHigh = ivec4(0);
  return sums * (ldexp(1.0, -solverFractionBits) * momentumUnitKgMPerS);
}

// After the first product of a step: β Δt² Hᵢᵢ, the Hessian's 3×3 block at the node (kg); the sums are cleared for
// the next step.
mat3 takeStiffnessBlock(uint address) {
  vec3 diagonal = fixed64ToFloat(solverNodes[address].diagonalLow, solverNodes[address].diagonalHigh).xyz;
  vec3 offDiagonal = fixed64ToFloat(solverNodes[address].offDiagonalLow, solverNodes[address].offDiagonalHigh).xyz;
  solverNodes[address].diagonalLow = solverNodes[address].offDiagonalLow = uvec4(0u);
  solverNodes[address].diagonalHigh = solverNodes[address].offDiagonalHigh = ivec4(0);
  float unitKg = ldexp(1.0, -solverFractionBits) * referenceMassKg;
  return unitKg * mat3(diagonal.x, offDiagonal.z, offDiagonal.y,
                       offDiagonal.z, diagonal.y, offDiagonal.x,
                       offDiagonal.y, offDiagonal.x, diagonal.z);
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

// The index among the rigid bodies of the body whose unknowns hold the node (common/solver_bodies.glsl), or −1.
int constraintBody(vec4 constraint) { return (int(constraint.w) >> CONSTRAINT_BODY_SHIFT) - 1; }

// n·u at a node a collider holds along its normal n, else 0: the held component of a product or a residual, which
// the projection drops and the collider's normal impulse takes (SolverNode.residual.w; solver_finish.comp).
float heldNormalComponent(vec3 u, vec4 constraint) {
  int code = int(constraint.w);
  return (code & CONSTRAINT_NORMAL) != 0 && (code & CONSTRAINT_FIXED) == 0 ? dot(u, constraint.xyz) : 0.0;
}

// --- The preconditioner ------------------------------------------------------------------------------------------

// The block Jacobi preconditioner's inverse at a node of mass `massKg` and stiffness block `stiffnessKg` (β Δt² Hᵢᵢ):
// P = S (m I + β Δt² Hᵢᵢ) S on the components the constraint leaves free, inverted there, 0 on the held ones (and at a
// node without mass, which the constraints hold). S P S + (I − S) m keeps the free and held components apart, so its
// inverse is P⁻¹ on the free ones; a final projection drops what rounding leaves on the held ones. Returned as the
// diagonal (xyz) and the entries yz, zx, xy of the symmetric inverse. The block is inverted over m, P⁻¹ =
// (P / m)⁻¹ / m: with float sums a node at a cubic stencil's far corner holds 1e-14 of a particle's mass, and the
// determinant of a block of such entries, their cube, underflows float, so inverse() returned infinities there.
void invertPreconditioner(float massKg, mat3 stiffnessKg, vec4 constraint, out vec3 inverseDiagonal,
                          out vec3 inverseOffDiagonal) {
  inverseDiagonal = inverseOffDiagonal = vec3(0.0);
  if (!(massKg > 0.0)) return;
  mat3 free = mat3(constrain(vec3(1.0, 0.0, 0.0), constraint), constrain(vec3(0.0, 1.0, 0.0), constraint),
                   constrain(vec3(0.0, 0.0, 1.0), constraint));
  mat3 blockOverMass = free * (mat3(1.0) + stiffnessKg / massKg) * free + (mat3(1.0) - free);
  mat3 inverseBlock = free * inverse(blockOverMass) * free / massKg;
  inverseDiagonal = vec3(inverseBlock[0][0], inverseBlock[1][1], inverseBlock[2][2]);
  inverseOffDiagonal = vec3(inverseBlock[2][1], inverseBlock[0][2], inverseBlock[1][0]);
}

#ifndef FIRN_WITHOUT_SOLVER_PRECONDITIONER
// P⁻¹ v at node `address` (invertPreconditioner).
vec3 precondition(uint address, vec3 v) {
  vec3 diagonal = solverPreconditioners[address].inverseDiagonal.xyz;
  vec3 offDiagonal = solverPreconditioners[address].inverseOffDiagonal.xyz;  // yz, zx, xy
  return diagonal * v + vec3(offDiagonal.z * v.y + offDiagonal.y * v.z, offDiagonal.z * v.x + offDiagonal.x * v.z,
                             offDiagonal.y * v.x + offDiagonal.x * v.y);
}
#endif
