#version 430 core
// The semi-implicit solve's initial residual (common/solver.glsl), a work group per active block and an invocation
// per node: from x₀ = v*, the explicit update with its collisions (update_grid.comp), r₀ = S (M v* − A x₀) =
// −S β Δt² H v*, the preconditioner's diagonal P = M + β Δt² diag(H) (summed by the same product), z₀ = P⁻¹ r₀, and
// the block's partial sums of (r₀, z₀) and of (M v*, P⁻¹ M v*), the tolerance's reference.
// Reads: the grid's velocities and masses, the product sums, constraints. Writes: residual (w: P), preconditioned,
// the product sums (cleared), the block's partial sums.
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/solver.glsl"
#include "common/solver_reduction.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;
  uint i = slot * uint(BLOCK_NODES) + gl_LocalInvocationIndex;

  vec4 velocityMass = storedFloats(gridMomentumMass[i]);
  vec4 product = takeProduct(i);
  vec3 residual = constrain(-product.xyz, solverNodes[i].constraint);
  float diagonalKg = velocityMass.w + product.w;
  float inverse = inversePreconditioner(velocityMass.w, diagonalKg);
  vec3 preconditioned = residual * inverse;
  solverNodes[i].residual = vec4(residual, diagonalKg);
  solverNodes[i].preconditioned.xyz = preconditioned;
  vec3 momentum = velocityMass.w * velocityMass.xyz;
  writeBlockPartial(slot, vec4(0.0, 0.0, dot(residual, preconditioned), dot(momentum, momentum) * inverse));
}
