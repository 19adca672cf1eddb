#version 430 core
// Initial particle volumes, once, after a P2G of mass: ρ_p = Σ_i m_i w_ip / h³, V0_p = m_p / ρ_p
// (Stomakhin 2013 §6 step 2; Snow thesis 2015 §3.4 step 2).
// Reads: positionMass, grid mass, the block map. Writes: velocityVolume.w.
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
  velocityVolume[p].w = xm.w / densityKgPerM3;
}

void main() {
  uint p = invocationIndex();
  if (p < particleCount) computeVolume(p);
}
