#version 430 core
// Lists the particles whose stress mirror_stress.comp mirrors into a rigid body (common/mirror.glsl: a fluid's within
// a kernel's reach of the body's surface), after P2G: a
// work group per block list_mirror_blocks.comp listed, an invocation per particle of it (in the sorted order). The
// list takes particleRanks, which the sort no longer needs, and sizes mirror_stress.comp's dispatch (mirrorDispatch,
// rows of 65,535 work groups). Only the listed particles then run the images' scatter: on llvmpipe the scatter behind
// a branch cost most of a P2G over all particles even when no particle took it (docs/platform.md, Timing on
// llvmpipe).
// Reads: blockTable (mirrorBlocks: the dispatch record and w and slots[] and mirrorDispatch.w's old value),
//        sortedParticles, positionMass (xyz), plasticState (materialIndex), materials (model), colliders.
// Writes: particleRanks (the list), blockTable (mirrorDispatch).
#include "common/bindings.glsl"
#include "common/kernel.glsl"
#include "common/blocks.glsl"
#include "common/colliders.glsl"
#include "common/mirror.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void listIfMirrored(uint p, float reachM) {
  if (!stressMirrored(p)) return;
  vec3 x = positionMass[p].xyz;
  bool mirrored = false;
  for (uint i = 0u; i < colliderCount; ++i) {
    vec3 normal;
    float distanceM = mirroredDistance(i, x, reachM, normal);
    mirrored = mirrored || (distanceM > 0.0 && distanceM < reachM);
  }
  if (!mirrored) return;
  uint listed = atomicAdd(mirrorDispatch.w, 1u);
  particleRanks[listed] = p;
  uint groups = listed / uint(FIRN_PARTICLE_GROUP_SIZE) + 1u;
  atomicMax(mirrorDispatch.x, min(groups, 65535u));
  atomicMax(mirrorDispatch.y, (groups + 65534u) / 65535u);
}

void main() {
  uint k = workGroupSlot();
  if (k >= mirrorBlocks.w) return;
  uint slot = slots[k].mirrorBlock;
  uint first = slots[slot].firstParticle;
  uint count = slots[slot].particles;
  float reachM = mirrorReachM();
  for (uint j = gl_LocalInvocationIndex; j < count; j += uint(FIRN_PARTICLE_GROUP_SIZE)) {
    listIfMirrored(sortedParticles[first + j], reachM);
  }
}
