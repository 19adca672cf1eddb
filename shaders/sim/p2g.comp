#version 430 core
// Particle to grid with atomics (solver.atomics "fixed" or "float"): one invocation per particle, adding its
// contribution (common/scatter.glsl) to each node of its stencil.
// Reads: particle state. Writes: grid accumulators (atomics).
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/grid.glsl"
#include "common/scatter.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void main() {
  uint p = particleInvocationIndex();
  if (p >= particleCount()) return;
  Contribution contribution = particleContribution(p);
  if (!contribution.finite) {
    reportNonFinite(p);
    return;
  }
  Stencil stencil = particleStencil(contribution.x);
  for (int n = 0; n < KERNEL_NODES; ++n) {
    ivec3 k = stencilOffset(n);
    scatterToNode(contribution, stencil.baseNode + k, n, stencilWeight(stencil, k), stencilGradient(stencil, k));
  }
}
