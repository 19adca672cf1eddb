#version 430 core
// The semi-implicit solve's initial residual (common/solver.glsl), a work group per active block and an invocation
// per node: from the start x₀ (update_grid.comp: the velocity before the elastic force, with v*'s held components)
// r₀ = S (M v* − A x₀) = S (M (v* − x₀) − β Δt² H x₀), the preconditioner's diagonal P = M + β Δt² diag(H) (summed
// by the same product), the first iteration's direction v* − x₀ in place of z₀ (solver_step.comp), and the block's
// partial sums of (r₀, P⁻¹ r₀), of (M v*, P⁻¹ M v*), the tolerance's reference, and of the rounding floor (below).
// The grid's velocities become x₀, the solution's start.
// Reads: the grid's velocities (v*) and masses, the solver's start (direction), the product sums, constraints.
// Writes: the grid's velocities, residual (w: P), preconditioned (v* − x₀), the product sums (cleared), the block's
// partial sums.
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/solver.glsl"
#include "common/solver_reduction.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

// The rounding floor at a node of stiffness diagonal `diagonalKg` (β Δt² diag(H), the first product's w) and inverse
// preconditioner `inverse`: its term of ‖δb‖² in the P⁻¹ norm, δb the float rounding of the right-hand side M v*.
// The explicit force rounds τ to about ε (2μ + λ) in each entry (ε = 2⁻²⁴; at F = I svd3's rotation alone leaves
// that), so a node's impulse is uncertain by 3 Σₚ (Δt V⁰ ε (2μ + λ) |∇w|)² (three components, the particles' errors
// independent). The preconditioner's diagonal is Σₚ β Δt² V⁰ (4μ + λ) |∇w|² / 3 at F = I, so the two relate by
// about 9 ε² V⁰ (2μ + λ)² / (β (4μ + λ)) ≥ 4.5 ε² V⁰ (2μ + λ) / β per unit of diagonal. Firn takes 3 ε² V⁰ (2μ + λ)
// / β with the least V⁰ (2μ + λ) of the step's particles (solver_prepare.comp), an underestimate, so that the floor
// never excuses a residual the right-hand side does determine. 0 where β is 0 (no stiffness, no floor).
float roundingFloorTerm(float diagonalKg, float inverse) {
  const float EPSILON_SQUARED = 3.5527137e-15;  // (2⁻²⁴)²
  float scale = implicitRatio() > 0.0 ? 3.0 * EPSILON_SQUARED * uintBitsToFloat(roundingStiffness.x) / implicitRatio() : 0.0;
  return scale * diagonalKg * inverse;
}

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;
  uint i = slot * uint(BLOCK_NODES) + gl_LocalInvocationIndex;

  vec4 velocityMass = storedFloats(gridMomentumMass[i]);
  vec4 product = takeProduct(i);
  vec3 start = solverNodes[i].direction.xyz;
  vec3 residual = constrain(velocityMass.w * (velocityMass.xyz - start) - product.xyz, solverNodes[i].constraint);
  gridMomentumMass[i] = floatsToStored(vec4(start, velocityMass.w));  // the solution's storage from here on
  float diagonalKg = velocityMass.w + product.w;
  float inverse = inversePreconditioner(velocityMass.w, diagonalKg);
  solverNodes[i].residual = vec4(residual, diagonalKg);
  solverNodes[i].preconditioned.xyz = velocityMass.xyz - start;  // the first iteration's direction, v* − x₀
  vec3 momentum = velocityMass.w * velocityMass.xyz;
  writeBlockPartial(slot, vec4(roundingFloorTerm(product.w, inverse), 0.0, dot(residual, residual) * inverse,
                               dot(momentum, momentum) * inverse));
}
