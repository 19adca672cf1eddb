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
// holds the nodes that update held by them (common/colliders.glsl, heldInCoupling).
// Reads: colliders (the table and the bodies' entries), solverBodies (inverse: K⁻¹; velocity[0].w).
// Writes: colliders (the bodies' entries: velocities and their push's sums).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/colliders.glsl"
#include "common/bodies.glsl"
#include "common/body_blocks.glsl"
#include "common/body_contacts.glsl"

layout(local_size_x = 1) in;

// Whether body b holds grid nodes in its coupled solve (solve_coupling.comp). Two bodies that hold none are met after
// G2P alone (integrate_bodies.comp), with the colliders and walls they may rest on.
bool holdsNodes(int b) { return solverBodies[b].velocity[0].w != 0.0; }

// The inverse of body b's coupled effective mass along direction d at r from its centre of mass, d · K⁻¹ (d, r × d)
// (1/M along no direction, as inverseEffectiveMass gives it: a contact without slip then asks no friction).
float coupledInverseMass(int b, vec3 r, vec3 d) {
  if (d == vec3(0.0)) return 1.0 / colliders[bodyEntry(b)].bodyMass.x;
  vec3 linear, angular;
  blockInverseTimes(b, d, cross(r, d), linear, angular);
  return dot(d, linear) + dot(cross(r, d), angular);
}

// Body b takes an impulse j (kg·m/s) at r from its centre of mass: its velocities by K⁻¹ (j, r × j), and j with its
// moment in its push's sums, in the snow's fixed point (one share counts them: the bodies' sums are summed over the
// shares before integrate_bodies.comp reads them).
void takeContactImpulse(int b, vec3 r, vec3 j) {
  uint i = bodyEntry(b);
  vec3 linear, angular;
  blockInverseTimes(b, j, cross(r, j), linear, angular);
  colliders[i].velocityFriction.xyz += linear;
  colliders[i].angularVelocity.xyz += angular;
  addToRigidBody(i, j, cross(r, j));
}

void main() {
  if (gl_GlobalInvocationID.x != 0u) return;
  countedHere = bodiesCountedElsewhere == 0u;
  int bodies = int(rigidBodyCount);
  float endTimeS = timeS + dtS;
  for (int slot = 0; slot < CONTACT_SLOTS; ++slot) accumulated[slot] = vec4(0.0);
  for (int pass = 0; pass < CONTACT_PASSES; ++pass) {
    int contactSlot = 0;
    for (int b = 0; b < bodies; ++b) {
      uint i = bodyEntry(b);
      if (!takesPart(i)) continue;
      float probeRadiusM = colliders[i].bodyMass.y;
      mat3 turn = rotationMatrix(colliders[i].rotation);
      for (int k = 0; k < colliders[i].bodyProbes.y; ++k) {
        vec3 r = turn * probe(colliders[i], k);
        for (int a = 0; a < bodies; ++a) {
          uint o = bodyEntry(a);
          if (o == i || !takesPart(o)) continue;
          int slot = contactSlot++;
          if (!holdsNodes(b) && !holdsNodes(a)) continue;  // as integrate_bodies.comp would meet them
          vec3 v = colliders[i].velocityFriction.xyz, omega = colliders[i].angularVelocity.xyz;
          vec3 end = colliderPivot(colliders[i], timeS) + dtS * v + r;
          vec3 normal, contactR, otherR, relative;
          if (!meetsBody(o, r, end, endTimeS, probeRadiusM, v, omega, normal, contactR, otherR, relative)) continue;
          vec3 t = slipDirection(relative, normal);
          vec3 j = contactImpulse(slot, relative, normal, meetingFriction(i, o),
                                  coupledInverseMass(b, contactR, normal) + coupledInverseMass(a, otherR, normal),
                                  coupledInverseMass(b, contactR, t) + coupledInverseMass(a, otherR, t), t);
          takeContactImpulse(b, contactR, j);
          takeContactImpulse(a, otherR, -j);
        }
      }
    }
  }
}
