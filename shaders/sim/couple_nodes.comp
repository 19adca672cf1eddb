#version 430 core
// The nodes rigid bodies hold take the bodies' solved motion (docs/algorithm.md, eq. 39), explicit step: a work group
// per active block, an invocation per node, after solve_coupling.comp and meet_bodies.comp. A node the solve counted
// (heldInCoupling) meets the body as a collider (boundaryResponse), its surface now moving at the solved (V', ω'), and
// the body takes the opposite of what that changed in the node's momentum — the solve's own impulse, and Coulomb
// friction besides — in 64-bit fixed point, so that momentum is kept to the unit. Then the domain walls again, as the
// grid update left them last.
// Reads: blockTable (blockCounts and slots[].block and .auditedElsewhere and the blockDispatch record),
//        gridMomentumMass (the nodes' velocities and masses), colliders (the table and the bodies' sums' old words),
//        bodies (the free velocities), watchdog (the loads' words: the carries take the atomics' old values).
// Writes: gridMomentumMass (the nodes' velocities), colliders (the bodies' sums), watchdog (the bodies' loads).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/grid.glsl"
#include "common/blocks.glsl"
#include "common/colliders.glsl"
#include "common/body_blocks.glsl"
#include "common/energy.glsl"

layout(local_size_x = FIRN_BLOCK_GROUP_SIZE) in;

void coupleNode(uint slot) {
  ivec3 node = nodeOfBlock(blockCoordinates(slots[slot].block), gl_LocalInvocationIndex);
  vec3 x = nodePosition(node);
  if (!withinReachOfABody(x, timeS)) return;
  uint i = slot * uint(BLOCK_NODES) + gl_LocalInvocationIndex;
  vec4 velocityMass = storedFloats(gridMomentumMass[i]);
  if (velocityMass.w == 0.0) return;
  countedHere = slots[slot].auditedElsewhere == 0u;
  float massKg = velocityMass.w;
  vec3 velocity = velocityMass.xyz;
  for (uint b = colliderCount - rigidBodyCount; b < colliderCount; ++b) {
    if (!colliderWithinReach(b, x, timeS)) continue;
    ColliderParams body = colliders[b];
    vec3 normal;
    if (colliderDistance(body, x, timeS, normal) > 0.0) continue;
    vec3 fromCentreM = x - colliderPivot(body, timeS);
    int r = bodyOf(b);
    vec3 freeSurfaceVelocity =
        bodyRecords[r].freeVelocity.xyz + cross(bodyRecords[r].freeAngularVelocity.xyz, fromCentreM);
    if (!heldInCoupling(body, velocity, normal, freeSurfaceVelocity)) continue;
    // Held: a separating body holds the normal component whichever way the solved motion takes it, as a slip one.
    int boundary = body.shapeBoundary.y == BOUNDARY_STICKY ? BOUNDARY_STICKY : BOUNDARY_SLIP;
    vec3 surfaceVelocity = colliderVelocity(body, x, timeS);
    vec3 response = boundaryResponse(velocity, normal, surfaceVelocity, body.contact.x, boundary);
    if (response == velocity) continue;
    pushRigidBody(b, x, timeS, massKg * (response - velocity));
    colliderImpulse(b, body, massKg * (response - velocity), surfaceVelocity);  // its load; its work is its own
    velocity = response;
  }
  velocity = collideWithDomainWalls(x, velocity, interiorMin(), interiorMax());
  gridMomentumMass[i] = floatsToStored(vec4(velocity, massKg));
}

void main() {
#ifdef FIRN_STRIDE_OVER_BLOCKS
  for (uint slot = workGroupSlot(); slot < activeBlocks(); slot += workGroupCount()) coupleNode(slot);
#else
  uint slot = workGroupSlot();
  if (slot < activeBlocks()) coupleNode(slot);
#endif
}
