#version 430 core
// Grid to particle: one invocation per particle, in the sorted order (common/blocks.glsl), so that the invocations
// side by side read the same nodes. Gathers the new velocity (PIC/FLIP blend or APIC) and the velocity gradient
// from the blocks its stencil reaches, updates the particle's material (F or F_E, its scalar state, and the stress:
// materials.glsl), collides the particle, advects it (x += Δt v), and feeds the watchdog and the energy ledger's flows
// (the moving colliders' work and what the walls took: common/energy.glsl). A particle whose new
// state is not finite keeps its old state and is reported, so no non-finite value ever reaches a buffer or an
// output.
// Reads: blockTable (tileCounts.y: the particles of the sorted order), sortedParticles, positionMass, velocityVolume,
//        elasticDeformation (FIRN_HAS_DEFORMATION_GRADIENT), plasticState, materials, blockMap,
//        gridMomentumMass (the nodes' velocities), gridImpulse (PIC/FLIP: the velocities before forces),
//        colliders (with colliders), watchdog (the reports' and the ledger's atomics' old values).
// Writes: positionMass (xyz), velocityVolume (xyz), elasticDeformation (FIRN_HAS_DEFORMATION_GRADIENT),
//         kirchhoffStress, plasticState (plasticJ and sand's volumeCorrection), affine (APIC),
//         colliders (rigid bodies: the snow's push summed in their entries),
//         watchdog (reports and the adaptive step's fastest speed and the ledger's flows and the objects' loads).
#ifdef FIRN_TRANSFER_APIC
#define FIRN_WITHOUT_GRID_IMPULSE  // APIC reads no velocity before forces (common/grid.glsl)
#endif
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/colliders.glsl"
#include "common/materials.glsl"
#include "common/energy.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void advanceParticle(uint p) {
  vec3 x = positionMass[p].xyz;
  vec3 previousVelocity = velocityVolume[p].xyz;
  Stencil stencil = particleStencil(x);
  StencilBlocks blocks = stencilBlocks(stencil.baseNode);

  vec3 picVelocity = vec3(0.0);
  mat3 velocityGradient = mat3(0.0);
#ifdef FIRN_TRANSFER_APIC
  mat3 affineMoment = mat3(0.0);  // B_p = Σ w v_i (x_i − x_p)ᵀ
#else
  vec3 flipIncrement = vec3(0.0);
#endif
  StencilWalk walk = beginStencilWalk(stencil);
  for (int n = 0; n < KERNEL_NODES; ++n) {
    ivec3 k = walk.k;
    ivec3 node = stencil.baseNode + k;
    int address = stencilNodeAddress(blocks, k);
    float w = walkWeight(walk);
    // Every node a particle reaches has a block, unless the pool ran out (the host then redoes the frame).
    vec3 vi = address < 0 ? vec3(0.0) : nodeVelocity(uint(address));
    picVelocity += w * vi;
    velocityGradient += outerProduct(vi, walkGradient(walk));  // ∇v_p = Σ v_i ∇w_ipᵀ
#ifdef FIRN_TRANSFER_APIC
    affineMoment += w * outerProduct(vi, nodePosition(node) - x);
#else
    flipIncrement += w * (vi - (address < 0 ? vec3(0.0) : nodeVelocityBeforeForces(uint(address))));
#endif
    advanceStencilWalk(walk);
  }

#ifdef FIRN_TRANSFER_APIC
  vec3 velocity = picVelocity;
  mat3 newAffine = affineMoment * apicInverseInertiaPerM2;  // C_p = B_p D_p⁻¹ (Jiang et al. 2015)
#else
  // v_p = α (v_p + Σ w Δv_i) + (1 − α) Σ w v_i (Snow thesis 2015 §3.4 step 8)
  vec3 velocity = mix(picVelocity, previousVelocity + flipIncrement, flipRatio);
#endif

  ParticlePlasticState state = plasticState[p];
#ifdef FIRN_HAS_DEFORMATION_GRADIENT
  mat3 deformation = elasticDeformation[p];
#else
  mat3 deformation = mat3(1.0);
#endif
  MaterialUpdate material = updateMaterial(deformation, state, velocityGradient, dtS, materials[state.materialIndex]);

  // Particle collisions at the predicted position, at the end of the step.
  float endTimeS = timeS + dtS;
  vec3 predicted = x + dtS * velocity;
  float massKg = positionMass[p].w;
  float workJ = 0.0;
  velocity = collideWithColliders(predicted, velocity, endTimeS, massKg, workJ);
  vec3 beforeWalls = velocity;
  velocity = collideWithDomainWalls(predicted, velocity, interiorMin(), interiorMax());
  vec4 flowsJ = vec4(workJ, wallsRemovedJ(massKg, beforeWalls, velocity), 0.0,
                     velocityVolume[p].w * material.hardeningEnergyDensity);
  // Keep the stencil on the grid whatever happens: cubic needs x/h ∈ [1, nodes − 2).
  vec3 newPosition = clamp(x + dtS * velocity, gridOriginM + cellSizeM,
                           gridOriginM + (vec3(gridNodes) - 2.001) * cellSizeM);

  bool finite = allFinite(newPosition) && allFinite(velocity) && allFinite(material.deformation) &&
                allFinite(material.kirchhoffStress) && !isnan(material.state) && !isinf(material.state) &&
                !isnan(material.volumeCorrection) && !isinf(material.volumeCorrection);
#ifdef FIRN_TRANSFER_APIC
  finite = finite && allFinite(newAffine);
#endif
  if (!finite) {
    reportNonFinite(p);
    return;
  }
  float cellsPerStep = length(velocity) * dtS * cellsPerM;
  if (cellsPerStep > 1.0) reportCflViolation(p, cellsPerStep);
#if defined(FIRN_ADAPTIVE_DT) && defined(FIRN_SEMI_IMPLICIT)
  // A semi-implicit step is not bounded by the elastic wave: the next step must keep the particle within a cell.
  reportSpeed(length(velocity));
#elif defined(FIRN_ADAPTIVE_DT)
  // The next step must keep both the particle and the elastic wave through it within a cell (CFL on |v| + c).
  reportSpeed(length(velocity) + waveSpeed(materials[state.materialIndex], material.state));
#endif

  addEnergyFlows(flowsJ);
  positionMass[p].xyz = newPosition;
  velocityVolume[p].xyz = velocity;
#ifdef FIRN_HAS_DEFORMATION_GRADIENT
  elasticDeformation[p] = material.deformation;
#endif
  kirchhoffStress[p] = material.kirchhoffStress;
  plasticState[p].plasticJ = material.state;
#ifdef FIRN_MATERIAL_DRUCKER_PRAGER
  plasticState[p].volumeCorrection = material.volumeCorrection;  // only sand has one
#endif
#ifdef FIRN_TRANSFER_APIC
  affine[p] = newAffine;
#endif
}

void main() {
  uint i = invocationIndex();
  if (i < sortedParticleCount()) advanceParticle(sortedParticles[i]);
}
