#version 430 core
// The semi-implicit solve's per-particle preparation, once per step: for the corotated models, the rotation of F's
// polar decomposition and the system its derivative solves (common/material_hessians.glsl), so that the iterations'
// products need no SVD. One invocation per particle.
// Reads: elasticDeformation, plasticState, materials. Writes: solverParticles.
#include "common/bindings.glsl"
#include "common/material_hessians.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void main() {
  uint p = particleInvocationIndex();
  if (p >= particleCount()) return;
#if defined(FIRN_MATERIAL_SNOW) || defined(FIRN_MATERIAL_FIXED_COROTATED)
  int model = materials[plasticState[p].materialIndex].model.x;
  if (model == MODEL_SNOW || model == MODEL_FIXED_COROTATED) solverParticles[p] = polarDerivativeSystem(elasticDeformation[p]);
#endif
}
