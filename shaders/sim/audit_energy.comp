#version 430 core
// The energy audit's sums over the particles (docs/numerics.md, "The energy audit"): an invocation per particle, run
// once a frame, on the state the frame's last step left (Simulation::checkWatchdog), and once at the start. Each
// particle's kinetic energy ½ m (|v|² + D |C|²_F) (APIC's affine part, Jiang et al. 2015: what its transfers keep),
// its gravitational potential energy −m g · (x − floor) above the domain's floor, its elastic strain energy
// V⁰ Ψ(F_E) (common/materials.glsl), and after a step the term −(Δt/2) V⁰ τ : ∇v by which the energy an explicit step
// shows differs from the modified energy it keeps (∇v gathered from the last step's grid velocities at the
// particle's new position, so that Σ V⁰ τ : ∇v = −Σᵢ fᵢ · vᵢ pairs the forces of the state with its velocities), are
// rounded to the ledger's units and summed within the work group in shared memory, then added to the ledger once per
// group: integers, so the sums do not depend on either order.
// Reads: positionMass, velocityVolume, plasticState, materials, elasticDeformation (FIRN_HAS_DEFORMATION_GRADIENT),
//        affine (APIC), kirchhoffStress (after an explicit step), blockMap (after an explicit step),
//        gridMomentumMass (after an explicit step: the last step's velocities),
//        watchdog (the ledger's words: the carries take the atomics' old values).
// Writes: watchdog (the ledger's state sums and its count of values beyond the bound).
#define FIRN_WITHOUT_GRID_IMPULSE
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/materials.glsl"
#include "common/energy.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

// 1 where the grid holds the last step's velocities (after a step), 0 where it holds none (at the start).
uniform uint gridVelocities;

// The group's sums, as 64-bit words: kinetic, potential and elastic energy, and the step's term.
shared uint groupLow[4];
shared int groupHigh[4];

// τ : ∇v (W/m³ over V⁰) of particle p at x, ∇v = Σᵢ vᵢ ∇wᵢₚᵀ from the last step's grid.
float stressPower(uint p, vec3 x) {
  Stencil stencil = particleStencil(x);
  StencilBlocks blocks = stencilBlocks(stencil.baseNode);
  mat3 velocityGradient = mat3(0.0);
  StencilWalk walk = beginStencilWalk(stencil);
  for (int n = 0; n < KERNEL_NODES; ++n) {
    int address = stencilNodeAddress(blocks, walk.k);
    // A node the last step's blocks did not hold moved nothing.
    if (address >= 0) velocityGradient += outerProduct(nodeVelocity(uint(address)), walkGradient(walk));
    advanceStencilWalk(walk);
  }
  mat3 tau = kirchhoffStress[p];
  return dot(tau[0], velocityGradient[0]) + dot(tau[1], velocityGradient[1]) + dot(tau[2], velocityGradient[2]);
}

// Kinetic, potential and elastic energy (J) of particle p, and the step's term.
vec4 particleEnergies(uint p, vec4 positionMassKg, vec4 velocityVolumeM3, ParticlePlasticState state) {
  float massKg = positionMassKg.w;
  vec3 v = velocityVolumeM3.xyz;
  float kineticJ = 0.5 * massKg * dot(v, v);
#ifdef FIRN_TRANSFER_APIC
  mat3 C = affine[p];
  kineticJ += 0.5 * massKg * apicInertiaM2 * (dot(C[0], C[0]) + dot(C[1], C[1]) + dot(C[2], C[2]));
#endif
  float potentialJ = -massKg * dot(gravityMPerS2, positionMassKg.xyz - potentialFloorM);
#ifdef FIRN_HAS_DEFORMATION_GRADIENT
  mat3 F = elasticDeformation[p];
#else
  mat3 F = mat3(1.0);
#endif
  float volumeM3 = velocityVolumeM3.w;
  float elasticJ = volumeM3 * strainEnergyDensity(F, state, materials[state.materialIndex]);
  float stepTermJ = 0.0;
#ifndef FIRN_SEMI_IMPLICIT
  if (gridVelocities != 0u) stepTermJ = -0.5 * dtS * volumeM3 * stressPower(p, positionMassKg.xyz);
#endif
  return vec4(kineticJ, potentialJ, elasticJ, stepTermJ);
}

void main() {
  if (gl_LocalInvocationIndex < 4u) {
    groupLow[gl_LocalInvocationIndex] = 0u;
    groupHigh[gl_LocalInvocationIndex] = 0;
  }
  barrier();
  uint p = invocationIndex();
  if (p < particleCount) {
    vec4 positionMassKg = positionMass[p];
    vec4 velocityVolumeM3 = velocityVolume[p];
    ParticlePlasticState state = plasticState[p];
    uvec4 low;
    ivec4 high;
    energyUnits(particleEnergies(p, positionMassKg, velocityVolumeM3, state), low, high);
    for (int c = 0; c < 4; ++c) {
      FIRN_ADD_FIXED64_WORD(groupLow[c], groupHigh[c], low[c], high[c])
    }
  }
  barrier();
  if (gl_LocalInvocationIndex < 4u) {
    uint c = gl_LocalInvocationIndex;
    FIRN_ADD_FIXED64_WORD(stateLow[c], stateHigh[c], groupLow[c], groupHigh[c])
  }
}
