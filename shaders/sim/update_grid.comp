#version 430 core
// Grid update: a work group per active block, an invocation per node of it (common/blocks.glsl).
// v_i* = (Σ w m v)_i / m_i + Δt (f_i / m_i + g) (Stomakhin 2013 eq. 9–10, explicit), then colliders and the domain
// walls. Nodes without mass stay zero.
// Reads: grid sums, the block table, colliders. Writes: the same storage as floats (velocity m/s, mass kg), and for
// PIC/FLIP the velocity before forces. Semi-implicit steps: the node's constraints for the solve (solver.glsl).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/colliders.glsl"
#ifdef FIRN_SEMI_IMPLICIT
#include "common/solver.glsl"
#endif

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

void main() {
  uint slot = workGroupSlot();
  if (slot >= activeBlocks()) return;
  ivec3 node = nodeOfBlock(blockCoordinates(slots[slot].block), gl_LocalInvocationIndex);
  uint i = slot * uint(BLOCK_NODES) + gl_LocalInvocationIndex;

  vec4 sums = storedToNondimensional(gridMomentumMass[i]);
  vec3 velocity = vec3(0.0);
  vec3 velocityBeforeForces = vec3(0.0);
  float massKg = 0.0;
#ifdef FIRN_SEMI_IMPLICIT
  vec4 constraint = vec4(0.0, 0.0, 0.0, float(CONSTRAINT_FIXED));  // a node without mass stays at rest
#endif
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
#ifdef FIRN_SEMI_IMPLICIT
    constraint = colliderConstraint(x, velocity, transfer.y);
#endif
    velocity = collideWithColliders(x, velocity, transfer.y);
#ifdef FIRN_SEMI_IMPLICIT
    int walls = wallConstraint(x, velocity, interiorMin(), interiorMax());
    // A normal and a wall's axis together: held whole, so that the projection stays one.
    if (walls != 0 && (int(constraint.w) & CONSTRAINT_NORMAL) != 0) constraint.w = float(CONSTRAINT_FIXED);
    constraint.w = float(int(constraint.w) | walls);
#endif
    velocity = collideWithDomainWalls(x, velocity, interiorMin(), interiorMax());
  }
#ifdef FIRN_SEMI_IMPLICIT
  solverNodes[i].constraint = constraint;
  solverNodes[i].direction.xyz = velocity;  // x₀ = v*, for the initial residual's product
#endif
  gridMomentumMass[i] = floatsToStored(vec4(velocity, massKg));
#ifndef FIRN_TRANSFER_APIC
  gridImpulse[i] = floatsToStored(vec4(velocityBeforeForces, 0.0));
#endif
}
