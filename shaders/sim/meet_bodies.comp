#version 430 core
// The rigid bodies' contacts with each other within the explicit step's coupled solve (docs/algorithm.md, eq. 36 with
// eq. 39): one invocation for all the bodies, after solve_coupling.comp and before couple_nodes.comp. Each body meets
// the others at its probes where both will be at the step's end, as integrate_bodies.comp meets them, but with the
// inertia of its coupled solve, K = M_b + Σ m Gᵀ P G: an impulse j at r moves the body and the nodes it holds together,
// K⁻¹ (j, r × j), so a body resting on another passes its weight on to the snow under that one within the step, as
// the snow meets it. (Met after the solve alone, the lower box of a stack took its upper one's weight after the snow
// had met it, every step, and the stack sank into a bed.) What a contact gives a body goes to its sums of the push
// since the solve, with the snow's impulses at the nodes the body then moves (couple_nodes.comp), which
// integrate_bodies.comp adds to V* and L*: V* and ω* themselves stay as the grid update saw them, for couple_nodes.comp
// holds the nodes that update held by them (common/body_blocks.glsl, heldInCoupling).
// In the semi-implicit step, after the solve, the contacts of a body that held nodes in it with one that held none,
// each body moving by its own inertia, M_b⁻¹ (j, r × j): they start from the impulses they gave in the last step,
// which predict_bodies.comp gave the bodies before the solve, and are kept for the next (the warm start:
// common/body_contacts.glsl).
// Reads: colliders (the table and the bodies' entries), bodies (inverse: K⁻¹; velocity[0].w; semi-implicit step: the
//        contacts).
// Writes: colliders (the bodies' entries: velocities and their push's sums), bodies (semi-implicit step: the
//         contacts).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/colliders.glsl"
#include "common/bodies.glsl"
#include "common/body_blocks.glsl"
#include "common/body_contacts.glsl"

layout(local_size_x = 1) in;

// The inverse of body b's coupled effective mass along direction d at r from its centre of mass, d · K⁻¹ (d, r × d)
// (1/M along no direction, as inverseEffectiveMass gives it: a contact without slip then asks no friction); in the
// semi-implicit step its own, as takeContactImpulse moves it.
float coupledInverseMass(int b, vec3 r, vec3 d) {
  if (d == vec3(0.0)) return 1.0 / bodyRecords[b].massRadius.x;
#ifdef FIRN_SEMI_IMPLICIT
  mat3 turn = rotationMatrix(colliders[bodyEntry(b)].rotation);
  return inverseEffectiveMass(bodyRecords[b].massRadius.x, worldInverseInertia(b, turn), r, d);
#endif
  vec3 linear, angular;
  blockInverseTimes(b, d, cross(r, d), linear, angular);
  return dot(d, linear) + dot(cross(r, d), angular);
}

// Body b takes an impulse j (kg·m/s) at r from its centre of mass: its velocities by K⁻¹ (j, r × j), and j with its
// moment in its push's sums, in the snow's fixed point (one share counts them: the bodies' sums are summed over the
// shares before integrate_bodies.comp reads them). In the semi-implicit step by its own inertia, M_b⁻¹ (j, r × j): a
// body and the nodes it holds have moved together in the solve already.
void takeContactImpulse(int b, vec3 r, vec3 j) {
  uint i = bodyEntry(b);
  vec3 linear, angular;
#ifdef FIRN_SEMI_IMPLICIT
  linear = j / bodyRecords[b].massRadius.x;
  angular = worldInverseInertia(b, rotationMatrix(colliders[i].rotation)) * cross(r, j);
#else
  blockInverseTimes(b, j, cross(r, j), linear, angular);
#endif
  colliders[i].velocity.xyz += linear;
  colliders[i].angularVelocity.xyz += angular;
  addToRigidBody(i, j, cross(r, j));
}

void main() {
  if (gl_GlobalInvocationID.x != 0u) return;
  countedHere = bodiesCountedElsewhere == 0u;
  int bodies = int(rigidBodyCount);
  float endTimeS = timeS + dtS;
  for (int slot = 0; slot < CONTACT_SLOTS; ++slot) accumulated[slot] = vec4(0.0);
#ifdef FIRN_SEMI_IMPLICIT
  // The warm start (common/body_contacts.glsl): the impulse each contact of the last step gave, which both bodies took
  // before the solve, is taken back, and a contact that the bodies, moving as they would without it, still meet, in
  // the slot the passes give it, starts its total from it (turned into the plane the normal now gives), given anew
  // where it acts now.
  for (int s = 0; s < CONTACT_SLOTS; ++s) {
    bool inUse = slotInUse(s);
    BodyContact contact = bodyContacts[s];
    bodyContacts[s].key.w = 0;
    if (!inUse) continue;
    vec3 givenR, givenOtherR;
    vec3 given = slotImpulse(s, givenR, givenOtherR);
    uint i = uint(contact.key.x), o = uint(contact.key.z);
    int b = bodyOf(i), a = bodyOf(o);
    takeContactImpulse(b, givenR, -given);
    takeContactImpulse(a, givenOtherR, given);
    vec3 r = rotationMatrix(colliders[i].rotation) * probe(i, contact.key.y);
    vec3 v = colliders[i].velocity.xyz, omega = colliders[i].angularVelocity.xyz;
    vec3 end = colliderPivot(colliders[i], timeS) + dtS * v + r;
    vec3 normal, contactR, otherR, relative;
    if (holdsNodes(b) == holdsNodes(a) || contactSlotOf(i, contact.key.y, o) != s ||
        !meetsBody(o, r, end, endTimeS, bodyRecords[b].massRadius.y, v, omega, normal, contactR, otherR, relative)) {
      continue;
    }
    vec3 friction = withinFrictionCone(contact.impulse.xyz - dot(contact.impulse.xyz, normal) * normal,
                                       meetingFriction(i, o) * contact.impulse.w);
    accumulated[s] = vec4(friction, contact.impulse.w);
    vec3 start = contact.impulse.w * normal + friction;
    takeContactImpulse(b, contactR, start);
    takeContactImpulse(a, otherR, -start);
  }
#endif
  for (int pass = 0; pass < CONTACT_PASSES; ++pass) {
    int contactSlot = 0;
    for (int b = 0; b < bodies; ++b) {
      uint i = bodyEntry(b);
      if (!takesPart(i)) continue;
      float probeRadiusM = bodyRecords[b].massRadius.y;
      mat3 turn = rotationMatrix(colliders[i].rotation);
      for (int k = 0; k < bodyRecords[b].probes.y; ++k) {
        vec3 r = turn * probe(i, k);
        for (int a = 0; a < bodies; ++a) {
          uint o = bodyEntry(a);
          if (o == i || !takesPart(o)) continue;
          int slot = contactSlot++;
#ifdef FIRN_SEMI_IMPLICIT
          // Two bodies of which one held nodes in the solve and the other none (the others: integrate_bodies.comp).
          if (holdsNodes(b) == holdsNodes(a)) continue;
#else
          // Two bodies that hold no node are met after G2P alone (integrate_bodies.comp), with the colliders and
          // walls they may rest on.
          if (!holdsNodes(b) && !holdsNodes(a)) continue;
#endif
          vec3 v = colliders[i].velocity.xyz, omega = colliders[i].angularVelocity.xyz;
          vec3 end = colliderPivot(colliders[i], timeS) + dtS * v + r;
          vec3 normal, contactR, otherR, relative;
          if (!meetsBody(o, r, end, endTimeS, probeRadiusM, v, omega, normal, contactR, otherR, relative)) continue;
          vec3 t = slipDirection(relative, normal);
          vec3 j = contactImpulse(slot, relative, normal, meetingFriction(i, o),
                                  coupledInverseMass(b, contactR, normal) + coupledInverseMass(a, otherR, normal),
                                  coupledInverseMass(b, contactR, t) + coupledInverseMass(a, otherR, t), t);
          takeContactImpulse(b, contactR, j);
          takeContactImpulse(a, otherR, -j);
#ifdef FIRN_SEMI_IMPLICIT
          if (slot < CONTACT_SLOTS) {
            bodyContacts[slot] = BodyContact(accumulated[slot], vec4(normal, 0.0), ivec4(i, k, o, 1));
          }
#endif
        }
      }
    }
  }
}
