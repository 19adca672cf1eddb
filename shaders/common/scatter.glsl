// A particle's P2G contribution: mass, momentum and the elastic impulse −Δt V0 τ ∇w_ip (Stomakhin 2013 eq. 6,
// the force of the stress left by the last deformation update) to the nodes of its stencil, in the
// nondimensional units of grid.glsl, for p2g.comp to sum.
// Reads: positionMass, velocityVolume, kirchhoffStress, affine (APIC).

struct Contribution {
  bool finite;
  vec3 x;
  float massUnits;
  vec3 momentumUnits;
  mat3 impulseUnits;          // times ∇w_ip: the node's impulse
#ifdef FIRN_TRANSFER_APIC
  mat3 affineMomentumUnits;   // times (x_i − x_p): APIC's affine momentum
#endif
  float particleU;            // the particle's rounding dither (grid.glsl)
};

// precise, as the weights (common/bspline.glsl): P2G's two shapes must compute each contribution to the same bits.
Contribution particleContribution(uint p) {
  precise Contribution c;
  c.x = positionMass[p].xyz;
  float massKg = positionMass[p].w;
  vec4 velocityVolumeP = velocityVolume[p];
  mat3 stress = kirchhoffStress[p];
  // G2P never stores a non-finite state, so one here came from outside (an upload): report it, scatter nothing.
  c.finite = allFinite(c.x) && allFinite(velocityVolumeP.xyz) && allFinite(stress);
  c.massUnits = massKg * massUnitsPerKg;
  c.momentumUnits = velocityVolumeP.xyz * (massKg * momentumUnitsPerKgMPerS);
  c.impulseUnits = (velocityVolumeP.w * impulseUnitsPerPaM3) * stress;
#ifdef FIRN_TRANSFER_APIC
  // APIC (Jiang et al. 2015): momentum m w (v + C (x_i − x_p)).
  c.affineMomentumUnits = affine[p] * (massKg * momentumUnitsPerKgMPerS);
#endif
  c.particleU = particleDither(c.x);
  return c;
}

// The contribution to `node` with weight w and gradient ∇w: (momentum, mass) and the impulse, which an explicit
// APIC step adds to the momentum (grid.glsl's FIRN_GRID_IMPULSE).
void contributionToNode(Contribution c, ivec3 node, float w, vec3 gradient, out vec4 momentumMass, out vec3 impulse) {
  precise vec3 nodeImpulse = c.impulseUnits * gradient;
#ifdef FIRN_TRANSFER_APIC
  precise vec3 momentum = w * (c.momentumUnits + c.affineMomentumUnits * (nodePosition(node) - c.x));
#else
  precise vec3 momentum = w * c.momentumUnits;
#endif
#ifndef FIRN_GRID_IMPULSE
  momentum += nodeImpulse;
#endif
  precise vec4 nodeMomentumMass = vec4(momentum, w * c.massUnits);
  impulse = nodeImpulse;
  momentumMass = nodeMomentumMass;
}
