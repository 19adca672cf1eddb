#version 430 core
// Particle to grid: one invocation per particle. Scatters mass, momentum and the elastic impulse
// −Δt V0 τ ∇w_ip (Stomakhin 2013 eq. 6, the force of the stress left by the last deformation update) to the
// particle's stencil, in the nondimensional units of grid.glsl.
// Reads: positionMass, velocityVolume, kirchhoffStress, affine (APIC). Writes: grid accumulators (atomics).
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/grid.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void main() {
  uint p = particleInvocationIndex();
  if (p >= particleCount()) return;
  vec3 x = positionMass[p].xyz;
  float massKg = positionMass[p].w;
  vec4 velocityVolumeP = velocityVolume[p];
  mat3 stress = kirchhoffStress[p];
  // G2P never stores a non-finite state, so one here came from outside (an upload): report it, scatter nothing.
  if (!allFinite(x) || !allFinite(velocityVolumeP.xyz) || !allFinite(stress)) {
    reportNonFinite(p);
    return;
  }
  Stencil stencil = particleStencil(x);

  float massUnits = massKg / fixedPoint.x;
  vec3 momentumUnits = velocityVolumeP.xyz * (massKg / fixedPoint.y);
  mat3 impulseUnits = (-stepDt() * velocityVolumeP.w / fixedPoint.y) * stress;
#ifdef FIRN_TRANSFER_APIC
  // APIC (Jiang et al. 2015): momentum m w (v + C (x_i − x_p)).
  mat3 affineMomentumUnits = affine[p] * (massKg / fixedPoint.y);
#endif

  for (int n = 0; n < KERNEL_NODES; ++n) {
    ivec3 k = stencilOffset(n);
    ivec3 node = stencil.baseNode + k;
    uint i = nodeIndex(node);
    float w = stencilWeight(stencil, k);
    uint seed = contributionSeed(x, i);
    vec3 impulse = impulseUnits * stencilGradient(stencil, k);
#ifdef FIRN_TRANSFER_APIC
    vec3 momentum = w * (momentumUnits + affineMomentumUnits * (nodePosition(node) - x)) + impulse;
    scatterMomentumMass(i, vec4(momentum, w * massUnits), seed);
#else
    scatterMomentumMass(i, vec4(w * momentumUnits, w * massUnits), seed);
    scatterImpulse(i, impulse, seed);
#endif
  }
}
