#version 430 core
// Rigid bodies before their solve with the nodes they hold (docs/algorithm.md, eq. 39, and in the semi-implicit step
// eq. 39a): an invocation per body, after the images of a fluid's stress (mirror_stress.comp, explicit step) have
// pushed it and before the grid update. The body takes that push and gravity, V* = V + J / M + Δt g and L* = L + K, and
// its entry moves at V* and ω* = I⁻¹ L* from here to the solve: the grid update meets its surface moving so (a
// separating body holds the nodes approaching it then), and integrate_bodies.comp adds the snow's impulses after the
// solve to V* (BodyRecord.freeVelocity). The energy ledger takes the push's own energy, as integrate_bodies.comp
// takes the rest's (common/bodies.glsl). In the semi-implicit step each body also takes the impulses its contacts with
// the other bodies gave after the last solve, the start of this step's, which the contacts after this solve revise
// (the warm start: common/body_contacts.glsl).
// Reads: colliders (the bodies' entries and the push summed there), watchdog (the ledger's atomics' old values),
//        bodies (the records' dynamics; semi-implicit step: the contacts).
// Writes: colliders (the bodies' entries: velocities and their sums cleared), bodies (angular momentum and the free
//         velocities), watchdog (the ledger's flows).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/colliders.glsl"
#include "common/body_blocks.glsl"
#include "common/body_contacts.glsl"
#include "common/energy.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void main() {
  if (gl_GlobalInvocationID.x >= rigidBodyCount) return;
  countedHere = bodiesCountedElsewhere == 0u;
  int b = int(gl_GlobalInvocationID.x);
  uint i = bodyEntry(b);
  ColliderParams body = colliders[i];
  if (body.shapeBoundary.w == 0) return;  // parked
  float massKg = bodyRecords[b].massRadius.x;
  vec3 impulse, angularImpulse;
  summedPush(body, impulse, angularImpulse);
  vec3 v = body.velocity.xyz + impulse / massKg + dtS * gravityMPerS2;
  vec3 angularMomentum = bodyRecords[b].angularMomentum.xyz + angularImpulse;
  mat3 inverseInertia = worldInverseInertia(b, rotationMatrix(body.rotation));
#ifdef FIRN_SEMI_IMPLICIT
  // The impulses of its contacts with the other bodies after the last solve, the start of this step's.
  vec3 contacts, contactsMoment;
  impulsesBeforeSolve(i, contacts, contactsMoment);
  v += contacts / massKg;
  angularMomentum += contactsMoment;
#endif
  colliders[i].velocity.xyz = v;
  bodyRecords[b].freeVelocity.xyz = v;
  bodyRecords[b].angularMomentum.xyz = angularMomentum;
  vec3 omega = inverseInertia * angularMomentum;
  colliders[i].angularVelocity.xyz = omega;
  bodyRecords[b].freeAngularVelocity.xyz = omega;
  clearPush(i);
  addEnergyFlows(vec4(0.0, 0.0, pushOwnEnergyJ(massKg, inverseInertia, impulse, angularImpulse), 0.0));
}
