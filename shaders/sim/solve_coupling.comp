#version 430 core
// The explicit step's coupled solve (docs/algorithm.md, eq. 39): an invocation per rigid body, after the grid update
// has summed the nodes it holds. The body's velocities u = (V, ω) and the nodes' held components move together: with
// M_b = diag(M, I) and the sums Σ m Gᵀ P G and Σ m Gᵀ P v (BodyRecord.blockLow/High),
//   (M_b + Σ m Gᵀ P G) u' = M_b u* + Σ m Gᵀ P v,
// the velocities that keep the body's and the held nodes' momentum and angular momentum, with the nodes' held
// components moving with the body's surface: a perfectly inelastic collision of the body with the snow it holds,
// whatever their masses' ratio. The body's entry then moves at u' for the rest of the step: couple_nodes.comp gives
// the nodes that surface velocity and the body their impulses, which integrate_bodies.comp adds to u*. A body that
// holds no node keeps u*. With two bodies or more, the inverse of K = M_b + Σ m Gᵀ P G (M_b⁻¹ where it holds none),
// with which a body and the nodes it holds move together, is kept for their contacts with each other
// (meet_bodies.comp), and whether it holds any.
// Reads: colliders (the bodies' entries), bodies (the records' mass and inertia and coupling sums).
// Writes: colliders (the bodies' entries: velocities), bodies (inverse, velocity[0].w, the coupling sums cleared).
#define FIRN_WITHOUT_PARTICLE_BUFFERS
#include "common/bindings.glsl"
#include "common/colliders.glsl"
#include "common/bodies.glsl"
#include "common/body_blocks.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

void main() {
  uint b = gl_GlobalInvocationID.x;
  if (b >= rigidBodyCount) return;
  uint i = bodyEntry(int(b));
  ColliderParams body = colliders[i];
  if (body.shapeBoundary.w == 0) return;  // parked
  bool holds = false;
  for (int w = 0; w < COUPLING_WORDS; ++w) {
    holds = holds || nonzero(bodyRecords[b].blockLow[w], bodyRecords[b].blockHigh[w]);
  }
  float sums[4 * COUPLING_WORDS];
  float valuePerUnit = ldexp(1.0, -COUPLING_FRACTION_BITS);
  for (int w = 0; w < COUPLING_WORDS; ++w) {
    vec4 values = fixed64ToFloat(bodyRecords[b].blockLow[w], bodyRecords[b].blockHigh[w]) * valuePerUnit;
    for (int c = 0; c < 4; ++c) sums[4 * w + c] = values[c];
    bodyRecords[b].blockLow[w] = uvec4(0u);
    bodyRecords[b].blockHigh[w] = ivec4(0);
  }
  // The body in the sums' units: mass m_ref, length h, velocity h / Δt_ref, so ω in 1 / Δt_ref.
  float velocityUnitsPerMPerS = momentumUnitsPerKgMPerS / massUnitsPerKg;
  float massUnits = bodyRecords[b].massRadius.x * massUnitsPerKg;
  mat3 inertiaUnits = worldInertia(int(b)) * (massUnitsPerKg * cellsPerM * cellsPerM);
  float upper[21];
  for (int k = 0; k < 21; ++k) upper[k] = sums[k];
  addBodyMass(massUnits, inertiaUnits, upper);
  if (rigidBodyCount > 1u) {  // for meet_bodies.comp, which has none to meet otherwise
    storeBlockInverse(int(b), upper);
    bodyRecords[b].velocity[0].w = holds ? 1.0 : 0.0;
  }
  if (!holds) return;
  vec3 velocity = body.velocity.xyz * velocityUnitsPerMPerS;
  vec3 angularVelocity = body.angularVelocity.xyz * (velocityUnitsPerMPerS / cellsPerM);
  vec3 angularMomentum = inertiaUnits * angularVelocity;
  float x[6];
  for (int k = 0; k < 3; ++k) {
    x[k] = massUnits * velocity[k] + sums[21 + k];
    x[3 + k] = angularMomentum[k] + sums[24 + k];
  }
  solveSymmetric(upper, x);
  colliders[i].velocity.xyz = vec3(x[0], x[1], x[2]) / velocityUnitsPerMPerS;
  colliders[i].angularVelocity.xyz = vec3(x[3], x[4], x[5]) * (cellsPerM / velocityUnitsPerMPerS);
}
