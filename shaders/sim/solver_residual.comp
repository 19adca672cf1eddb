#version 430 core
// The semi-implicit solve's initial residual (common/solver.glsl), a work group per active block and an invocation
// per node: from the start x₀ (update_grid.comp: the velocity before the elastic force, with v*'s held components)
// r₀ = S (M v* − A x₀) = S (M (v* − x₀) − β Δt² H x₀), the block preconditioner's inverse from the node's
// stiffness block β Δt² Hᵢᵢ (summed by the same product; common/solver.glsl), the first iteration's direction v* − x₀
// in place of z₀ (solver_step.comp), and the block's partial sums of (r₀, P⁻¹ r₀), of the tolerance's reference
// (M v*, (M + β Δt² Hᵢᵢ)⁻¹ M v*) over all the components, held ones too, and of the rounding floor (below). The grid's
// velocities become x₀, the solution's start.
// Reads: solverStatus (roundingStiffness and the solveBlockDispatch record),
//        blockTable (blockCounts, and slots[].block with rigid bodies),
//        gridMomentumMass (the velocities v* and masses),
//        solverNodes (direction: the start x₀ and the product and stiffness block sums and constraint and residual.w),
//        solverPreconditioner (the inverse it has just written at the node), colliders (with rigid bodies: their
//        centres).
// Writes: gridMomentumMass (the velocities become x₀), solverPreconditioner (the inverse),
//         solverNodes (residual with w: the normal impulse and preconditioned: v* − x₀ and the sums cleared),
//         solverStatus (the block's partial sums),
//         bodies (with rigid bodies: at the nodes a body holds, its sums and its preconditioner's block sums),
//         watchdog (a body's sum out of range).
// At a node a rigid body holds (common/solver_bodies.glsl), the held part of β Δt² H x₀ goes to the body's sums, and
// the node's share of the body's preconditioner block to its block sums.
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/solver.glsl"
#include "common/solver_reduction.glsl"
#ifdef FIRN_HAS_RIGID_BODIES
#include "common/colliders.glsl"
#include "common/bodies.glsl"
#include "common/solver_bodies.glsl"
#endif

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

// The rounding floor at a node of mass `massKg` and stiffness block trace `traceKg` (β Δt² tr(Hᵢᵢ)): its term of ‖δb‖²
// in the P⁻¹ norm, δb the float rounding of the right-hand side M v*. The explicit force rounds τ to about ε (2μ + λ)
// in each entry (ε = 2⁻²⁴; at F = I svd3's rotation alone leaves that), so a node's impulse is uncertain by
// 3 Σₚ (Δt V⁰ ε (2μ + λ) |∇w|)² (three components, the particles' errors independent). The block's trace is
// Σₚ β Δt² V⁰ (4μ + λ) |∇w|² at F = I, so the two relate by about 9 ε² V⁰ (2μ + λ)² / (β (4μ + λ)) ≥
// 4.5 ε² V⁰ (2μ + λ) / β per unit of trace / 3. Firn takes 3 ε² V⁰ (2μ + λ) / β with the least V⁰ (2μ + λ) of the
// step's particles (solver_prepare.comp), and P⁻¹ as the inverse of the block's mean diagonal, which is no larger
// than P⁻¹'s mean (the harmonic mean is the least): an underestimate, so that the floor never excuses a residual
// the right-hand side does determine. 0 where β is 0 (no stiffness, no floor).
float roundingFloorTerm(float massKg, float traceKg) {
  const float EPSILON_SQUARED = 3.5527137e-15;  // (2⁻²⁴)²
  float scale = implicitRatio > 0.0 ? 3.0 * EPSILON_SQUARED * uintBitsToFloat(roundingStiffness.x) / implicitRatio : 0.0;
  float meanDiagonalKg = massKg + traceKg / 3.0;
  return massKg > 0.0 ? scale * (traceKg / 3.0) / meanDiagonalKg : 0.0;
}

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;
  uint i = slot * uint(BLOCK_NODES) + gl_LocalInvocationIndex;

  vec4 velocityMass = storedFloats(gridMomentumMass[i]);
  vec3 product = takeProduct(i);
  mat3 stiffnessKg = takeStiffnessBlock(i);
  vec4 constraint = solverNodes[i].constraint;
  vec3 start = solverNodes[i].direction.xyz;
  vec3 residual = constrain(velocityMass.w * (velocityMass.xyz - start) - product, constraint);
  gridMomentumMass[i] = floatsToStored(vec4(start, velocityMass.w));  // the solution's storage from here on
  vec3 inverseDiagonal, inverseOffDiagonal;
  invertPreconditioner(velocityMass.w, stiffnessKg, constraint, inverseDiagonal, inverseOffDiagonal);
  solverPreconditioners[i] = SolverPreconditioner(vec4(inverseDiagonal, 0.0), vec4(inverseOffDiagonal, 0.0));
  solverNodes[i].residual.xyz = residual;
#ifdef FIRN_HAS_RIGID_BODIES
  int body = constraintBody(constraint);
  if (body >= 0) {
    ivec3 node = nodeOfBlock(blockCoordinates(slots[slot].block), gl_LocalInvocationIndex);
    vec3 fromCentreCells = fromBodyCentreCells(body, nodePosition(node));
    addToBodySums(body, fromCentreCells, heldPart(product, constraint), node);
    addToBodyBlock(body, fromCentreCells, velocityMass.w, stiffnessKg, constraint);
  }
#endif
  // The held component's push at the start, n·(A x₀ − M v*), joins the approach update_grid.comp removed.
  if (velocityMass.w > 0.0) {
    solverNodes[i].residual.w += heldNormalComponent(velocityMass.w * (start - velocityMass.xyz) + product, constraint) /
                                 velocityMass.w;
  }
  solverNodes[i].preconditioned.xyz = velocityMass.xyz - start;  // the first iteration's direction, v* − x₀
  vec3 momentum = velocityMass.w * velocityMass.xyz;
  // (m + β Δt² Hᵢᵢ)⁻¹ m v* = (I + β Δt² Hᵢᵢ / m)⁻¹ v*, inverted over m as the preconditioner is (common/solver.glsl).
  vec3 scaledMomentum =
      velocityMass.w > 0.0 ? inverse(mat3(1.0) + stiffnessKg / velocityMass.w) * velocityMass.xyz : vec3(0.0);
  float traceKg = stiffnessKg[0][0] + stiffnessKg[1][1] + stiffnessKg[2][2];
  writeBlockPartial(slot, vec4(roundingFloorTerm(velocityMass.w, traceKg), 0.0, dot(residual, precondition(i, residual)),
                               dot(momentum, scaledMomentum)));
}
