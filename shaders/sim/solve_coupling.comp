#version 430 core
// The explicit step's coupled solve (docs/algorithm.md, eq. 39): one invocation for all the rigid bodies, after the
// grid update has summed the nodes each holds. The body's velocities u = (V, ω) and the nodes' held components move
// together: with M_b = diag(M, I) and the sums Σ m Gᵀ P G and Σ m Gᵀ P v (ColliderParams.couplingLow/High),
//   (M_b + Σ m Gᵀ P G) u' = M_b u* + Σ m Gᵀ P v,
// the velocities that keep the body's and the held nodes' momentum and angular momentum, with the nodes' held
// components moving with the body's surface: a perfectly inelastic collision of the body with the snow it holds,
// whatever their masses' ratio. The body's entry then moves at u' for the rest of the step: couple_nodes.comp gives
// the nodes that surface velocity and the body their impulses, which integrate_bodies.comp adds to u*. A body that
// holds no node keeps u*.
// Then the bodies' contacts with each other (eq. 36) at their positions at the step's end, each body with the inertia
// of its coupled solve, K = M_b + Σ m Gᵀ P G: an impulse j on a body moves it and the nodes it holds together,
// K⁻¹ (j, r × j), so that a body resting on another passes its weight on to the snow under that one within the step
// (resolved after the solve, in integrate_bodies.comp alone, the lower body of a stack was pushed into the snow by its
// upper one's weight every step, after the snow had met it, and a stack of two boxes sank into a bed at 5 mm/s). What
// the contacts give a body is added to its u* as well (ColliderParams.freeVelocity, angularMomentum), whose snow's
// impulses integrate_bodies.comp adds.
// Reads: colliders (the bodies' entries and their coupling sums).
// Writes: colliders (the bodies' entries: velocities, V* and L*, and their coupling sums cleared).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/colliders.glsl"
#include "common/bodies.glsl"
#include "common/body_contacts.glsl"

layout(local_size_x = 1) in;

// Body entry i's coupled system, K = M_b + Σ m Gᵀ P G (its upper triangle, row by row), in the sums' units: mass
// m_ref, length h, velocity h / Δt_ref, so ω in 1 / Δt_ref.
void coupledSystem(uint i, out float upper[21], out float rightSide[6]) {
  ColliderParams body = colliders[i];
  float sums[4 * COUPLING_WORDS];
  float valuePerUnit = ldexp(1.0, -COUPLING_FRACTION_BITS);
  for (int w = 0; w < COUPLING_WORDS; ++w) {
    vec4 values = fixed64ToFloat(body.couplingLow[w], body.couplingHigh[w]) * valuePerUnit;
    for (int c = 0; c < 4; ++c) sums[4 * w + c] = values[c];
  }
  float velocityUnitsPerMPerS = momentumUnitsPerKgMPerS / massUnitsPerKg;
  float massUnits = body.bodyMass.x * massUnitsPerKg;
  mat3 inertiaUnits = inverse(worldInverseInertia(body, rotationMatrix(body.rotation))) *
                      (massUnitsPerKg * cellsPerM * cellsPerM);
  vec3 velocity = body.velocityFriction.xyz * velocityUnitsPerMPerS;
  vec3 angularMomentum = inertiaUnits * (body.angularVelocity.xyz * (velocityUnitsPerMPerS / cellsPerM));
  for (int k = 0; k < 21; ++k) upper[k] = sums[k];
  addBodyMass(massUnits, inertiaUnits, upper);
  for (int k = 0; k < 3; ++k) {
    rightSide[k] = massUnits * velocity[k] + sums[21 + k];
    rightSide[3 + k] = angularMomentum[k] + sums[24 + k];
  }
}

// K⁻¹ (impulse, moment) for body entry i: the change of its velocity (m/s) and angular velocity (rad/s) when it and
// the nodes it holds take the impulse (kg·m/s) with its moment (kg·m²/s) together.
void coupledResponse(uint i, vec3 impulseKgMPerS, vec3 momentKgM2PerS, out vec3 linear, out vec3 angular) {
  float upper[21], unused[6];
  coupledSystem(i, upper, unused);
  float velocityUnitsPerMPerS = momentumUnitsPerKgMPerS / massUnitsPerKg;
  float x[6];
  for (int k = 0; k < 3; ++k) {
    x[k] = impulseKgMPerS[k] * momentumUnitsPerKgMPerS;
    x[3 + k] = momentKgM2PerS[k] * (momentumUnitsPerKgMPerS * cellsPerM);
  }
  solveSymmetric(upper, x);
  linear = vec3(x[0], x[1], x[2]) / velocityUnitsPerMPerS;
  angular = vec3(x[3], x[4], x[5]) * (cellsPerM / velocityUnitsPerMPerS);
}

// The inverse of body entry i's coupled effective mass along direction d at r from its centre of mass (1/M along no
// direction, as inverseEffectiveMass gives it: a contact without slip then asks no friction, rather than 0 / 0).
float coupledInverseMass(uint i, vec3 r, vec3 d) {
  if (d == vec3(0.0)) return 1.0 / colliders[i].bodyMass.x;
  vec3 linear, angular;
  coupledResponse(i, d, cross(r, d), linear, angular);
  return dot(d, linear) + dot(cross(r, d), angular);
}

// Body entry i takes an impulse j at r from its centre of mass: its velocities by K⁻¹, and its V* and L* by j itself.
void takeContactImpulse(uint i, vec3 r, vec3 j) {
  vec3 linear, angular;
  coupledResponse(i, j, cross(r, j), linear, angular);
  colliders[i].velocityFriction.xyz += linear;
  colliders[i].angularVelocity.xyz += angular;
  colliders[i].freeVelocity.xyz += j / colliders[i].bodyMass.x;
  colliders[i].angularMomentum.xyz += cross(r, j);
}

void main() {
  if (gl_GlobalInvocationID.x != 0u) return;
  uint firstBody = colliderCount - rigidBodyCount;
  for (uint i = firstBody; i < colliderCount; ++i) {
    if (!takesPart(i)) continue;
    bool holds = false;
    for (int w = 0; w < COUPLING_WORDS; ++w) {
      holds = holds || nonzero(colliders[i].couplingLow[w], colliders[i].couplingHigh[w]);
    }
    if (!holds) continue;
    float upper[21], x[6];
    coupledSystem(i, upper, x);
    solveSymmetric(upper, x);
    float velocityUnitsPerMPerS = momentumUnitsPerKgMPerS / massUnitsPerKg;
    colliders[i].velocityFriction.xyz = vec3(x[0], x[1], x[2]) / velocityUnitsPerMPerS;
    colliders[i].angularVelocity.xyz = vec3(x[3], x[4], x[5]) * (cellsPerM / velocityUnitsPerMPerS);
  }

  // The bodies' contacts with each other, as integrate_bodies.comp meets them, with each body's coupled inertia.
  float endTimeS = timeS + dtS;
  for (int slot = 0; slot < CONTACT_SLOTS; ++slot) accumulated[slot] = vec4(0.0);
  for (int pass = 0; pass < CONTACT_PASSES; ++pass) {
    int contactSlot = 0;
    for (uint i = firstBody; i < colliderCount; ++i) {
      if (!takesPart(i)) continue;
      float probeRadiusM = colliders[i].bodyMass.y;
      mat3 turn = rotationMatrix(colliders[i].rotation);
      for (int k = 0; k < colliders[i].bodyProbes.y; ++k) {
        ColliderParams body = colliders[i];
        vec3 r = turn * probe(body, k);
        vec3 end = colliderPivot(body, timeS) + dtS * body.velocityFriction.xyz + r;
        for (uint o = firstBody; o < colliderCount; ++o) {
          if (o == i || !takesPart(o)) continue;
          int slot = contactSlot++;
          if (!colliderWithinReach(o, end, endTimeS, probeRadiusM)) continue;
          ColliderParams other = colliders[o];
          vec3 normal;
          if (colliderDistance(other, end, endTimeS, normal) - probeRadiusM >= 0.0) continue;
          body = colliders[i];
          vec3 contactR = r - probeRadiusM * normal;
          vec3 point = end - probeRadiusM * normal;
          vec3 otherR = point - colliderPivot(other, endTimeS);
          vec3 relative = body.velocityFriction.xyz + cross(body.angularVelocity.xyz, contactR) -
                          colliderVelocity(other, point, endTimeS);
          vec3 t = slipDirection(relative, normal);
          vec3 j = contactImpulse(slot, relative, normal, sqrt(body.velocityFriction.w * other.velocityFriction.w),
                                  coupledInverseMass(i, contactR, normal) + coupledInverseMass(o, otherR, normal),
                                  coupledInverseMass(i, contactR, t) + coupledInverseMass(o, otherR, t), t);
          takeContactImpulse(i, contactR, j);
          takeContactImpulse(o, otherR, -j);
        }
      }
    }
  }
  for (uint i = firstBody; i < colliderCount; ++i) {
    for (int w = 0; w < COUPLING_WORDS; ++w) {
      colliders[i].couplingLow[w] = uvec4(0u);
      colliders[i].couplingHigh[w] = ivec4(0);
    }
  }
}
