#version 430 core
// The smoothed volume fraction f(x) = Σ_p V_p W(x − x_p; R_p) at the grid's nodes (docs/surfaces.md eq. 1): 1
// inside snow at its rest density, ½ on a flat edge of it, 0 outside. With colours, also Σ_p V_p W · albedo_p,
// which the mesh divides by f to carry the particles' colours onto the surface; with velocities, Σ_p V_p W · v_p,
// which divided by f is the snow's velocity there (the caches' motion blur). One invocation per particle over
// the nodes of its kernel's ball, row by row (at most (2 · MAX_KERNEL_RADIUS_CELLS + 1)³ nodes). Each contribution
// is rounded to fixed point on its own and added with an integer atomic, so the sums are exact and the same
// whatever order the particles add in.
// It reads positionMass, velocityVolume, plasticState and the particle colours, and writes the density and node
// sums (atomic adds).
#include "common/particles.glsl"
#include "surface/surface_common.glsl"
#include "surface/kernel_radius.glsl"
#include "surface/node_sums.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

layout(std430, binding = FIRN_BINDING_SURFACE_DENSITY) buffer SurfaceDensityBuffer { int density[]; };
layout(std430, binding = FIRN_BINDING_SURFACE_PARTICLE_COLORS) readonly buffer ParticleColorBuffer {
  vec4 particleColors[];
};

int toUnits(float value) { return int(floor(value * SURFACE_UNITS_PER_VALUE + 0.5)); }

void main() {
  uint p = invocationIndex();
  if (p >= reconstructedParticles) return;
  vec3 x = positionMass[p].xyz;
  float volumeM3 = particleRestVolumeM3(p);
  float radiusM = kernelRadiusM(volumeM3);
  if (any(isnan(x)) || any(isinf(x)) || !(radiusM > 0.0)) return;
  // The kernel's box of nodes, in this frame's grid (which holds it: measure_bounds.comp).
  ivec3 low = ivec3(ceil((x - radiusM - latticeOriginM) / nodeSpacingM)) - firstNode;
  ivec3 high = ivec3(floor((x + radiusM - latticeOriginM) / nodeSpacingM)) - firstNode;
  low = max(low, ivec3(0));
  high = min(high, boxNodes - 1);
  ivec3 extent = high - low + 1;
  if (any(lessThanEqual(extent, ivec3(0)))) return;
  vec3 albedo = withColors() ? particleColors[p].rgb : vec3(0.0);
  vec3 velocity = withVelocities() ? velocityVolume[p].xyz : vec3(0.0);
  float weightScale = volumeM3 / (radiusM * radiusM * radiusM);
  // Row by row along x, each row only across the kernel's ball: a third of the box's nodes.
  int rows = extent.y * extent.z;
  for (int row = 0; row < rows; ++row) {
    ivec3 first = low + ivec3(0, row % extent.y, row / extent.y);
    vec3 offsetM = nodePositionM(first) - x;
    float acrossM2 = radiusM * radiusM - offsetM.y * offsetM.y - offsetM.z * offsetM.z;
    if (acrossM2 <= 0.0) continue;
    float halfChordM = sqrt(acrossM2);
    int rowLow = max(int(ceil((x.x - halfChordM - latticeOriginM.x) / nodeSpacingM)) - firstNode.x, low.x);
    int rowHigh = min(int(floor((x.x + halfChordM - latticeOriginM.x) / nodeSpacingM)) - firstNode.x, high.x);
    for (int i = rowLow; i <= rowHigh; ++i) {
      ivec3 node = ivec3(i, first.y, first.z);
      float q = length(nodePositionM(node) - x) / radiusM;
      if (q >= 1.0) continue;
      float weight = weightScale * smoothingKernel(q);
      uint address = nodeAddress(node);
      atomicAdd(density[address], toUnits(weight));
      if (withColors()) {
        atomicAdd(nodeSums[address].color.x, toUnits(weight * albedo.r));
        atomicAdd(nodeSums[address].color.y, toUnits(weight * albedo.g));
        atomicAdd(nodeSums[address].color.z, toUnits(weight * albedo.b));
      }
      if (withVelocities()) {
        atomicAdd(nodeSums[address].velocity.x, toUnits(weight * velocity.x));
        atomicAdd(nodeSums[address].velocity.y, toUnits(weight * velocity.y));
        atomicAdd(nodeSums[address].velocity.z, toUnits(weight * velocity.z));
      }
    }
  }
}
