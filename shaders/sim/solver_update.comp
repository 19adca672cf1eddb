#version 430 core
// The semi-implicit solve's step along p (common/solver.glsl): α = (r, P⁻¹ A z)_k / (A p, P⁻¹ A p)_k, the numerator
// solver_apply.comp's: the method's (z, A z), which is (r, P⁻¹ A p) since r is P⁻¹-orthogonal to the last A p, and in
// the first iteration, whose p = z is v* − x₀, the step that leaves the least residual on that line; x += α p (the
// grid's velocities), r −= α A p, z = P⁻¹ r, and the block's partial sum of (r, z), the residual after the
// iteration. A work group per active block, an invocation per node.
// Reads: the registers, the grid's velocities and masses, residual, direction, directionProduct. Writes: the grid's
// velocities, residual, preconditioned, the block's partial sums.
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/solver.glsl"
#include "common/solver_reduction.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

uniform uint iteration;

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;
  uint i = slot * uint(BLOCK_NODES) + gl_LocalInvocationIndex;

  vec4 denominators = registers[iteration];
  float alpha = denominators.y != 0.0 ? denominators.x / denominators.y : 0.0;
  SolverNode node = solverNodes[i];
  vec4 velocityMass = storedFloats(gridMomentumMass[i]);
  gridMomentumMass[i] = floatsToStored(vec4(velocityMass.xyz + alpha * node.direction.xyz, velocityMass.w));
  vec3 residual = node.residual.xyz - alpha * node.directionProduct.xyz;
  vec3 preconditioned = residual * inversePreconditioner(velocityMass.w, node.residual.w);
  solverNodes[i].residual.xyz = residual;
  solverNodes[i].preconditioned.xyz = preconditioned;
  writeBlockPartial(slot, vec4(0.0, 0.0, dot(residual, preconditioned), 0.0));
}
