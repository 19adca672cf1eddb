// The rigid bodies' records (gpu::BodyRecord: a body's dynamics and its solves; docs/algorithm.md, Rigid bodies), their
// inertia in the world, and a body's 6×6 block, the inertia with which it and the grid nodes it holds move together,
// and its inverse (BodyRecord.inverse): in the explicit step the coupled solve's K = M_b + Σ m Gᵀ P G (eq. 39), whose
// sums over the held nodes the grid update adds (addToCoupling) and with which the bodies then meet each other
// (meet_bodies.comp); in the semi-implicit step the preconditioner's diagonal block
// P_b = M_b + Σ Gᵀ P (m + β Δt² Hᵢᵢ) P G (eq. 39a; common/solver_bodies.glsl).
#include "common/bodies.glsl"

// The bodies' records: the contacts of the last step (the semi-implicit step's warm start), then each body's dynamics
// and solve.
layout(std430, binding = FIRN_BINDING_BODIES) coherent buffer BodiesBuffer {
  BodyContact bodyContacts[CONTACT_SLOTS];
  BodyRecord bodyRecords[];
};

// The entry of body b in the collider table (the bodies are its last entries), and the body of entry i.
uint bodyEntry(int b) { return colliderCount - rigidBodyCount + uint(b); }
int bodyOf(uint i) { return int(i - bodyEntry(0)); }

// I⁻¹ in the world's axes, R I_b⁻¹ Rᵀ, for body b's orientation `turn` (1/(kg·m²)).
mat3 worldInverseInertia(int b, mat3 turn) {
  vec4 columns[3] = bodyRecords[b].inverseInertia;
  return turn * mat3(columns[0].xyz, columns[1].xyz, columns[2].xyz) * transpose(turn);
}

// I in the world's axes, R I_b Rᵀ, for body b's orientation now (kg·m²).
mat3 worldInertia(int b) {
  return inverse(worldInverseInertia(b, rotationMatrix(colliders[bodyEntry(b)].rotation)));
}

// Whether body b holds grid nodes in its solve with them (BodyRecord.velocity[0].w, which the explicit step's
// solve_coupling.comp and the semi-implicit step's solver_bodies_residual.comp set).
bool holdsNodes(int b) { return bodyRecords[b].velocity[0].w != 0.0; }

// Stores the inverse of body b's block in SI units, row after row, from the block's upper triangle (row by row) in
// P2G's nondimensional units (mass m_ref, length h, velocity h / Δt_ref): with D = diag(1/u_v, 1/u_v, 1/u_v, h⁻¹/u_v,
// …) (u_v velocity units per m/s), the inverse is u_p u_v D B⁻¹ D, u_p momentum units per kg·m/s.
void storeBlockInverse(int b, float upper[21]) {
  float velocityUnitsPerMPerS = momentumUnitsPerKgMPerS / massUnitsPerKg;
  float scale[6];
  for (int k = 0; k < 3; ++k) {
    scale[k] = 1.0 / velocityUnitsPerMPerS;
    scale[3 + k] = cellsPerM / velocityUnitsPerMPerS;
  }
  for (int c = 0; c < 6; ++c) {
    float column[6] = float[6](0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    column[c] = 1.0;
    solveSymmetric(upper, column);
    for (int r = 0; r < 6; ++r) {
      float value = momentumUnitsPerKgMPerS * velocityUnitsPerMPerS * scale[r] * column[r] * scale[c];
      bodyRecords[b].inverse[(6 * r + c) / 4][(6 * r + c) % 4] = value;
    }
  }
}

// The block's inverse times v for body b: v's force-like part (kg·m/s) and moment-like part (kg·m²/s) into (V, ω)
// (m/s, rad/s).
void blockInverseTimes(int b, vec3 force, vec3 moment, out vec3 linear, out vec3 angular) {
  float v[6] = float[6](force.x, force.y, force.z, moment.x, moment.y, moment.z);
  float result[6];
  for (int r = 0; r < 6; ++r) {
    float sum = 0.0;
    for (int c = 0; c < 6; ++c) sum += bodyRecords[b].inverse[(6 * r + c) / 4][(6 * r + c) % 4] * v[c];
    result[r] = sum;
  }
  linear = vec3(result[0], result[1], result[2]);
  angular = vec3(result[3], result[4], result[5]);
}

#if defined(FIRN_HAS_RIGID_BODIES) && !defined(FIRN_SEMI_IMPLICIT)
// Whether a body whose solid holds a node at velocity v holds it in the coupled solve (eq. 39): a sticky or slip body
// always, a separating one where the node approaches its surface moving before the solve at `freeSurfaceVelocity`.
// The grid update and couple_nodes.comp decide alike, so that the nodes the solve counted are the nodes that take
// its motion, pulled or pushed: a set that changed with the solved motion would push the body with what the solve
// did not count, explicitly, and a light body rocks apart on that.
bool heldInCoupling(ColliderParams body, vec3 v, vec3 normal, vec3 freeSurfaceVelocity) {
  return body.shapeBoundary.y != BOUNDARY_SEPARATE || dot(v - freeSurfaceVelocity, normal) < 0.0;
}

// The explicit step's coupled solve (docs/algorithm.md, eq. 39): a node of mass m at x that body i holds, at the
// velocity v the grid update gave it, adds m Gᵀ P G and m Gᵀ P v to the body's sums, G the 3×6 map from the body's
// velocities (V, ω) to its surface's velocity at x, V + ω × (x − c), and P what the body holds of the node's velocity:
// all of it if sticky, its normal component if slip, or if separating and approaching the body's surface as the
// body moves before the solve (predict_bodies.comp). P is a projection, so Gᵀ P G = (P G)ᵀ (P G), from the six
// columns of P G. The sums are in P2G's nondimensional units (mass m_ref, length h, velocity h / Δt_ref) and 64-bit
// fixed point, so that they do not depend on the order of the GPU's additions.
void addToCoupling(uint i, vec3 x, float timeS, float massKg, vec3 v) {
  if (!countedHere) return;
  ColliderParams body = colliders[i];
  vec3 normal;
  if (colliderDistance(body, x, timeS, normal) > 0.0) return;
  if (!heldInCoupling(body, v, normal, colliderVelocity(body, x, timeS))) return;
  bool sticky = body.shapeBoundary.y == BOUNDARY_STICKY;
  float massUnits = massKg * massUnitsPerKg;
  vec3 fromCentreCells = (x - colliderPivot(body, timeS)) * cellsPerM;
  vec3 velocityUnits = v * (momentumUnitsPerKgMPerS / massUnitsPerKg);
  vec3 columns[6];
  for (int k = 0; k < 3; ++k) {
    vec3 axis = vec3(0.0);
    axis[k] = 1.0;
    vec3 turning = cross(axis, fromCentreCells);  // ∂(ω × r)/∂ω_k
    columns[k] = sticky ? axis : normal * normal[k];
    columns[3 + k] = sticky ? turning : normal * dot(normal, turning);
  }
  float sums[4 * COUPLING_WORDS];
  int n = 0;
  for (int a = 0; a < 6; ++a) {
    for (int b = a; b < 6; ++b) sums[n++] = massUnits * dot(columns[a], columns[b]);
  }
  for (int a = 0; a < 6; ++a) sums[n++] = massUnits * dot(columns[a], velocityUnits);
  sums[n] = 0.0;
  float unitsPerValue = ldexp(1.0, COUPLING_FRACTION_BITS);
  for (int w = 0; w < COUPLING_WORDS; ++w) {
    uvec4 low;
    ivec4 high;
    splitFixed64(round(vec4(sums[4 * w], sums[4 * w + 1], sums[4 * w + 2], sums[4 * w + 3]) * unitsPerValue), low,
                 high);
    FIRN_ADD_FIXED64(bodyRecords[bodyOf(i)].blockLow[w], bodyRecords[bodyOf(i)].blockHigh[w], low, high)
  }
}

// Whether any rigid body may hold x: within the reach of one that takes part (colliderWithinReach).
bool withinReachOfABody(vec3 x, float timeS) {
  for (uint i = colliderCount - rigidBodyCount; i < colliderCount; ++i) {
    if (colliderWithinReach(i, x, timeS)) return true;
  }
  return false;
}
#endif
