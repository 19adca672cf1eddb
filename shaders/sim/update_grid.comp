#version 430 core
// Grid update: one invocation per node of the active box. v_i* = (Σ w m v)_i / m_i + Δt (f_i / m_i + g)
// (Stomakhin 2013 eq. 9–10, explicit), then colliders and the domain walls. Nodes without mass stay zero.
// Reads: grid accumulators, colliders. Writes: the same storage as floats (velocity m/s, mass kg), and for
// PIC/FLIP the velocity before forces.
#include "common/bindings.glsl"
#include "common/active_region.glsl"
#include "common/grid.glsl"
#include "common/colliders.glsl"

layout(FIRN_GRID_GROUP_SIZE) in;

void main() {
  ivec3 local = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(local, region.boxSize.xyz))) return;
  ivec3 node = region.boxMin.xyz + local;
  uint i = nodeIndex(node);

  vec4 sums = storedToNondimensional(gridMomentumMass[i]);
  vec3 velocity = vec3(0.0);
  vec3 velocityBeforeForces = vec3(0.0);
  float massKg = 0.0;
  if (sums.w > 0.0) {
    massKg = sums.w * fixedPoint.x;
    float unitsToVelocity = fixedPoint.y / massKg;
#ifdef FIRN_TRANSFER_APIC
    velocity = sums.xyz * unitsToVelocity + stepDt() * gravityDt.xyz;  // impulse already in the momentum
#else
    vec3 impulse = storedToNondimensional(gridImpulse[i]).xyz;
    velocityBeforeForces = sums.xyz * unitsToVelocity;
    velocity = (sums.xyz + impulse) * unitsToVelocity + stepDt() * gravityDt.xyz;
#endif
    vec3 x = nodePosition(node);
    velocity = collideWithColliders(x, velocity, transfer.y);
    velocity = collideWithDomainWalls(x, velocity, interiorMin(), interiorMax());
  }
  gridMomentumMass[i] = floatsToStored(vec4(velocity, massKg));
#ifndef FIRN_TRANSFER_APIC
  gridImpulse[i] = floatsToStored(vec4(velocityBeforeForces, 0.0));
#endif
}
