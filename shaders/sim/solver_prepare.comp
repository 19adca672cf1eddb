#version 430 core
// The semi-implicit solve's per-particle preparation, once per step: each particle's stiffness ∂²Ψ/∂F² at its F, in
// the frame of F's SVD and projected onto the positive semi-definite (common/material_hessians.glsl), so that the
// iterations' products need no SVD; and the least V⁰ (2μ + λ) of the particles, the scale of the tolerance's rounding
// floor (solver_residual.comp), a minimum per work group and one atomic per group. One invocation per particle.
// Reads: elasticDeformation, plasticState, materials, velocityVolume (w: V0).
// Writes: solverParticles, solverStatus (roundingStiffness).
#include "common/bindings.glsl"
#include "common/material_hessians.glsl"
#include "common/solver_reduction.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

// Non-negative floats order as their bits do.
shared uint leastBits[FIRN_PARTICLE_GROUP_SIZE];

void main() {
  uint p = invocationIndex();
  uint l = gl_LocalInvocationIndex;
  uint bits = 0x7f800000u;  // +∞
  if (p < particleCount) {
    ParticlePlasticState state = plasticState[p];
    SolverParticle s = principalStiffness(elasticDeformation[p], materials[state.materialIndex], state.plasticJ);
    solverParticles[p] = s;
    bits = floatBitsToUint(velocityVolume[p].w * s.blockCoupling.w);
  }
  leastBits[l] = bits;
  barrier();
  for (uint stride = uint(FIRN_PARTICLE_GROUP_SIZE) / 2u; stride > 0u; stride /= 2u) {
    if (l < stride) leastBits[l] = min(leastBits[l], leastBits[l + stride]);
    barrier();
  }
  if (l == 0u && leastBits[0] < 0x7f800000u) atomicMin(roundingStiffness.x, leastBits[0]);
}
