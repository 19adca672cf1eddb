// A rigid body's 6×6 block, the inertia with which it and the grid nodes it holds move together, and its inverse
// (BodyRecord.inverse): in the explicit step the coupled solve's K = M_b + Σ m Gᵀ P G (eq. 39), with which the bodies
// then meet each other (meet_bodies.comp); in the semi-implicit step the preconditioner's diagonal block
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
