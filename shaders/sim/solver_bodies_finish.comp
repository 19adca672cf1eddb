#version 430 core
// Rigid bodies after the semi-implicit solve (common/solver_bodies.glsl, eq. 39a): each body's entry moves at the
// velocities solved, u = (V, ω), for the rest of the step — the friction after the solve and G2P meet its surface
// moving so, and integrate_bodies.comp adds their impulses to u, as the explicit step's bodies after their coupled
// solve (BodyRecord.freeVelocity). What the solve gave the body, M_b (u − u*), is the opposite of its push on the
// snow: the body's load (bodies.csv), with its work at the velocity solved.
// An invocation per body.
// Reads: colliders (the bodies' entries), bodies (velocity, the mass and inertia), watchdog (the loads' atomics' old
//        values).
// Writes: colliders (the bodies' entries: velocities), bodies (the free velocities and angular momentum),
//         watchdog (the objects' loads).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/colliders.glsl"
#include "common/bodies.glsl"
#include "common/solver.glsl"
#include "common/solver_bodies.glsl"
#include "common/energy.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= rigidBodyCount) return;
  int b = int(k);
  uint i = bodyEntry(b);
  ColliderParams body = colliders[i];
  if (body.shapeBoundary.w == 0) return;  // parked
  countedHere = true;  // the semi-implicit step runs in one process
  vec3 v = bodyRecords[b].velocity[0].xyz;
  vec3 omega = bodyRecords[b].velocity[1].xyz;
  vec3 impulseOnSnow = -bodyRecords[b].massRadius.x * (v - body.velocity.xyz);
  if (impulseOnSnow != vec3(0.0)) addObjectLoad(i, impulseOnSnow, dot(impulseOnSnow, v));
  colliders[i].velocity.xyz = v;
  bodyRecords[b].freeVelocity.xyz = v;
  colliders[i].angularVelocity.xyz = omega;
  bodyRecords[b].freeAngularVelocity.xyz = omega;
  bodyRecords[b].angularMomentum.xyz = worldInertia(b) * omega;
}
