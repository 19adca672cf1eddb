#version 430 core
// The semi-implicit solve's per-particle preparation, once per step: each particle's stiffness ∂²Ψ/∂F² at its F, in
// the frame of F's SVD and projected onto the positive semi-definite (common/material_hessians.glsl), so that the
// iterations' products need no SVD. One invocation per particle.
// Reads: elasticDeformation, plasticState, materials. Writes: solverParticles.
#include "common/bindings.glsl"
#include "common/material_hessians.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void main() {
  uint p = particleInvocationIndex();
  if (p >= particleCount()) return;
  ParticlePlasticState state = plasticState[p];
  solverParticles[p] = principalStiffness(elasticDeformation[p], materials[state.materialIndex], state.plasticJ);
}
