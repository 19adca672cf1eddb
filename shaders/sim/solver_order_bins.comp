#version 430 core
// The semi-implicit solve's order of the particles within each bin (common/blocks.glsl), once per step: by index.
// The counting sort leaves a bin's particles in the order of bin_count.comp's atomics, which changes from run to run; P2G's
// fixed-point sums do not mind, but the Hessian products sum their tiles' contributions in float
// (solver_product.comp), and a float sum repeats only in a repeated order. A work group per active block, an
// invocation per bin, an insertion sort of the bin's few particles in place.
// Reads: bins, slots[].firstParticle. Writes: sortedParticles.
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/watchdog.glsl"
#include "common/blocks.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;
  uvec2 particles = binParticles(slot, gl_LocalInvocationIndex);  // first, count
  for (uint j = particles.x + 1u; j < particles.x + particles.y; ++j) {
    uint p = sortedParticles[j];
    uint i = j;
    for (; i > particles.x && sortedParticles[i - 1u] > p; --i) sortedParticles[i] = sortedParticles[i - 1u];
    sortedParticles[i] = p;
  }
}
