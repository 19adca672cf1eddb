#version 430 core
// The box of lattice nodes the particles' kernels reach, which this frame's grid covers (with a node to spare).
// One invocation per particle. Reads: positionMass, plasticState. Writes: the header's kernel bounds (atomic
// min and max; the host starts them at the extremes of int).
#include "common/particles.glsl"
#include "surface/surface_common.glsl"
#include "surface/kernel_radius.glsl"
#include "surface/header.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void main() {
  uint p = invocationIndex();
  if (p >= reconstructedParticles) return;
  vec3 x = positionMass[p].xyz;
  float radiusM = kernelRadiusM(particleRestVolumeM3(p));
  // The simulation never stores a non-finite particle (its watchdog stops the run first); a kernel of none is
  // left out rather than stretching the box to infinity.
  if (any(isnan(x)) || any(isinf(x)) || !(radiusM > 0.0)) return;
  ivec3 low = ivec3(ceil((x - radiusM - latticeOriginM) / nodeSpacingM));
  ivec3 high = ivec3(floor((x + radiusM - latticeOriginM) / nodeSpacingM));
  for (int axis = 0; axis < 3; ++axis) {
    atomicMin(kernelNodesMin[axis], low[axis]);
    atomicMax(kernelNodesMax[axis], high[axis]);
  }
}
