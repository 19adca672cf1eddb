#version 430 core
// Lists the particles that left this process's slab, after a step of a run over several processes
// (docs/distributed.md, Migration): an invocation per particle; a particle whose stencil's base node lies in a block
// layer along `slabAxis` outside [slabFirstLayer, slabEndLayer) is listed in particleRanks, which the sort no longer
// needs, and counted in `migration.x`. The host then reads back only the listed particles, not every position: the
// block layer is the GPU's own, so each particle is sorted into the slab it is owned by.
// Reads: positionMass (xyz), blockTable (migration.x: the atomic's old value is the particle's entry).
// Writes: particleRanks (the list), blockTable (migration.x).
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/blocks.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

uniform uint particles;  // now, after the step's migration: the step's particleCount may be more
uniform uint slabAxis;
uniform uint slabFirstLayer;
uniform uint slabEndLayer;

void main() {
  uint p = invocationIndex();
  if (p >= particles) return;
  ivec3 base = max(stencilBaseNode(cellCoordinates(positionMass[p].xyz)), ivec3(0));
  uint layer = min(uint(base[slabAxis] / BLOCK_WIDTH), uint(blocksPerAxis()[slabAxis] - 1));
  if (layer >= slabFirstLayer && layer < slabEndLayer) return;
  particleRanks[atomicAdd(migration.x, 1u)] = p;
}
