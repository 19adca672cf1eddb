// Grid to particle for one particle, shared by both shapes of the pass (g2p.comp, g2p_block.comp), so that they do
// the same arithmetic and write the same bytes: gathers the new velocity (PIC/FLIP blend or APIC) and the velocity
// gradient from its stencil's nodes, updates its material (F or F_E, its scalar state, and the stress:
// materials.glsl), collides it, advects it (x += Δt v), and feeds the watchdog. A particle whose new state is not
// finite keeps its old state and is reported, so no non-finite value ever reaches a buffer or an output.
//
// The including pass says where the nodes' velocities come from, before it includes this file:
//   StencilNodes stencilNodes(ivec3 baseNode)             what the pass looks the stencil's nodes up by
//   vec3 stencilNodeVelocity(StencilNodes s, ivec3 k)     node baseNode + k's velocity after forces, 0 with no block
//   vec3 stencilNodeVelocityBeforeForces(StencilNodes s, ivec3 k)   and before them (PIC/FLIP)
// Writes: positionMass.xyz, velocityVolume.xyz, elasticDeformation, plasticState, kirchhoffStress, affine.

void advanceParticle(uint p) {
  vec3 x = positionMass[p].xyz;
  vec3 previousVelocity = velocityVolume[p].xyz;
  Stencil stencil = particleStencil(x);
  StencilNodes nodes = stencilNodes(stencil.baseNode);

  vec3 picVelocity = vec3(0.0);
  mat3 velocityGradient = mat3(0.0);
#ifdef FIRN_TRANSFER_APIC
  mat3 affineMoment = mat3(0.0);  // B_p = Σ w v_i (x_i − x_p)ᵀ
#else
  vec3 flipIncrement = vec3(0.0);
#endif
  for (int n = 0; n < KERNEL_NODES; ++n) {
    ivec3 k = stencilOffset(n);
    ivec3 node = stencil.baseNode + k;
    float w = stencilWeight(stencil, k);
    // Every node a particle reaches has a block, unless the pool ran out (the host then redoes the frame): 0 there.
    vec3 vi = stencilNodeVelocity(nodes, k);
    picVelocity += w * vi;
    velocityGradient += outerProduct(vi, stencilGradient(stencil, k));  // ∇v_p = Σ v_i ∇w_ipᵀ
#ifdef FIRN_TRANSFER_APIC
    affineMoment += w * outerProduct(vi, nodePosition(node) - x);
#else
    flipIncrement += w * (vi - stencilNodeVelocityBeforeForces(nodes, k));
#endif
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
  velocity = collideWithColliders(predicted, velocity, endTimeS, positionMass[p].w);
  velocity = collideWithDomainWalls(predicted, velocity, interiorMin(), interiorMax());
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
  float cellsPerStep = length(velocity) * dtS / cellSizeM;
  if (cellsPerStep > 1.0) reportCflViolation(p, cellsPerStep);
#if defined(FIRN_ADAPTIVE_DT) && defined(FIRN_SEMI_IMPLICIT)
  // A semi-implicit step is not bounded by the elastic wave: the next step must keep the particle within a cell.
  reportSpeed(length(velocity));
#elif defined(FIRN_ADAPTIVE_DT)
  // The next step must keep both the particle and the elastic wave through it within a cell (CFL on |v| + c).
  reportSpeed(length(velocity) + waveSpeed(materials[state.materialIndex], material.state));
#endif

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
