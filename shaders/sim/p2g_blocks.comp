#version 430 core
// Particle to grid without atomics on the grid (solver.atomics "none"), run once per colour
// (common/blocks.glsl): one invocation per non-empty block of the colour, taken from bin_scan.comp's list
// (fullest first, alike bins side by side), scatters its bin's particles (common/scatter.glsl) with plain
// additions. No other invocation of this colour reaches those nodes.
// Reads: particle state, bins, blockOrder, blockColors[blockColor]. Writes: grid sums.
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/scatter.glsl"

layout(local_size_x = 8) in;  // one llvmpipe SIMD row

uniform int blockColor;

void main() {
  BlockColor color = blockColors[blockColor];
  int entry = int(gl_GlobalInvocationID.x);
  if (entry >= color.count.w) return;
  uvec2 bin = bins[blockOrder[color.first.x + entry]];
  for (uint j = bin.x; j < bin.x + bin.y; ++j) {
    uint p = blockParticles[j];
    Contribution contribution = particleContribution(p);
    if (!contribution.finite) {
      reportNonFinite(p);
      continue;
    }
    Stencil stencil = particleStencil(contribution.x);
    // Rows of KERNEL_WIDTH nodes along x written out, so that a particle costs KERNEL_WIDTH² loop iterations
    // rather than KERNEL_NODES (llvmpipe's loop limit: kMaxBinParticles in engine/sim/GpuLayout.h).
    for (int row = 0; row < KERNEL_WIDTH * KERNEL_WIDTH; ++row) {
      ivec3 k = ivec3(0, row % KERNEL_WIDTH, row / KERNEL_WIDTH);
      int n = row * KERNEL_WIDTH;
      scatterToNode(contribution, stencil.baseNode + k, n, stencilWeight(stencil, k), stencilGradient(stencil, k));
      k.x = 1;
      scatterToNode(contribution, stencil.baseNode + k, n + 1, stencilWeight(stencil, k), stencilGradient(stencil, k));
      k.x = 2;
      scatterToNode(contribution, stencil.baseNode + k, n + 2, stencilWeight(stencil, k), stencilGradient(stencil, k));
#ifdef FIRN_KERNEL_CUBIC
      k.x = 3;
      scatterToNode(contribution, stencil.baseNode + k, n + 3, stencilWeight(stencil, k), stencilGradient(stencil, k));
#endif
    }
  }
}
