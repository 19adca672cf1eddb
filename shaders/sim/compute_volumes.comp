#version 430 core
// Initial particle volumes, once, after a P2G of mass: ρ_p = Σ_i m_i w_ip / h³ (Stomakhin 2013 §6 step 2; Snow
// thesis 2015 §3.4 step 2), V0_p = m_p / max(ρ_p, ρ) with ρ the material's rest density (docs/algorithm.md eq. 6).
// ρ_p counts the empty part of a kernel that reaches past the material as the particle's: alone, a particle reads
// ρ_p = m_p Σ_i w_ip² / h³, independent of its material and 1/38 to 1/64 of ρ at 8 particles per cell, and its wave
// speed sqrt(stiffness / (m_p / V0_p)) would outrun the step's stability bound, which is derived for ρ.
// Reads: positionMass, velocityVolume (w: m_p / ρ from the host), gridMomentumMass (the mass sums), blockMap.
// Writes: velocityVolume (w: V0).
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void computeVolume(uint p) {
  vec4 xm = positionMass[p];
  Stencil stencil = particleStencil(xm.xyz);
  float densityMassUnits = 0.0;
  for (int n = 0; n < KERNEL_NODES; ++n) {
    ivec3 k = stencilOffset(n);
    int address = nodeAddress(stencil.baseNode + k);
    densityMassUnits += stencilWeight(stencil, k) * (address < 0 ? 0.0 : nodeMassUnits(uint(address)));
  }
  float h = cellSizeM;
  float densityKgPerM3 = densityMassUnits * referenceMassKg / (h * h * h);
  // An estimate above ρ (a cloud packed denser than its material) is kept; one below it gives way to ρ. A mass
  // too small for the fixed point (densityKgPerM3 = 0, V = ∞) also keeps m_p / ρ.
  velocityVolume[p].w = min(velocityVolume[p].w, xm.w / densityKgPerM3);
}

void main() {
  uint p = invocationIndex();
  if (p < particleCount) computeVolume(p);
}
