// The index of this invocation in a pass over items (particles, nodes, chunks) that runs FIRN_PARTICLE_GROUP_SIZE
// invocations to a work group: more groups than one dimension allows (65,535 at GL 4.3's minimum) are laid out in
// rows of gl_NumWorkGroups.x (gl/ComputePass.h, runOver), folded back into one index here.
#include "common/gpu_contract.h"

uint invocationIndex() {
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * uint(FIRN_PARTICLE_GROUP_SIZE);
}
