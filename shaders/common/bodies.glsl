// What the passes over rigid bodies share (docs/algorithm.md, Rigid bodies): an entry's orientation, and the snow's
// push summed in its entry (eq. 35).
#include "common/colliders.glsl"
#include "common/fixed64.glsl"

// 1 on every share of the domain but the first (RigidBodies.cpp): each moves the bodies alike, and one counts the
// energy that moves.
uniform uint bodiesCountedElsewhere;

mat3 rotationMatrix(vec4 q) {
  return mat3(rotateByQuaternion(q, vec3(1.0, 0.0, 0.0)), rotateByQuaternion(q, vec3(0.0, 1.0, 0.0)),
              rotateByQuaternion(q, vec3(0.0, 0.0, 1.0)));
}

// The impulse (kg·m/s) and its moment about the centre of mass (kg·m²/s) summed in the body's entry.
void summedPush(ColliderParams body, out vec3 impulseKgMPerS, out vec3 momentKgM2PerS) {
  float kgMPerSPerUnit = ldexp(momentumUnitKgMPerS, -fixedPointFractionBits);
  impulseKgMPerS = fixed64ToFloat(body.impulseLow, body.impulseHigh).xyz * kgMPerSPerUnit;
  momentKgM2PerS = fixed64ToFloat(body.angularLow, body.angularHigh).xyz * (kgMPerSPerUnit * cellSizeM);
}

// The energy (J) a push J with moment K gives a body of mass M and inverse inertia I⁻¹ beyond what the snow's side
// pays for it to first order (J · V + K · ω): |J|² / 2M + K · I⁻¹ K / 2 (docs/numerics.md, The energy audit).
float pushOwnEnergyJ(float massKg, mat3 inverseInertia, vec3 impulseKgMPerS, vec3 momentKgM2PerS) {
  return 0.5 * dot(impulseKgMPerS, impulseKgMPerS) / massKg +
         0.5 * dot(momentKgM2PerS, inverseInertia * momentKgM2PerS);
}

// Empties the entry's sums of the snow's push.
void clearPush(uint i) {
  colliders[i].impulseLow = uvec4(0u);
  colliders[i].impulseHigh = ivec4(0);
  colliders[i].angularLow = uvec4(0u);
  colliders[i].angularHigh = ivec4(0);
}

// Adds M_b = diag(M, I) to a 6×6 upper triangle (row by row), in the units its values are in.
void addBodyMass(float mass, mat3 inertia, inout float upper[21]) {
  // The upper triangle's row r starts at 6r − r(r − 1)/2.
  for (int r = 0; r < 3; ++r) upper[6 * r - r * (r - 1) / 2] += mass;
  for (int r = 3; r < 6; ++r) {
    for (int c = r; c < 6; ++c) upper[6 * r - r * (r - 1) / 2 + (c - r)] += inertia[c - 3][r - 3];
  }
}

// Solves A x = b for a symmetric positive definite 6×6 A (its upper triangle, row by row) by Cholesky's A = L Lᵀ.
void solveSymmetric(float upper[21], inout float x[6]) {
  float l[6][6];
  int k = 0;
  float a[6][6];
  for (int r = 0; r < 6; ++r) {
    for (int c = r; c < 6; ++c) {
      a[r][c] = upper[k];
      a[c][r] = upper[k];
      ++k;
    }
  }
  for (int c = 0; c < 6; ++c) {
    float diagonal = a[c][c];
    for (int j = 0; j < c; ++j) diagonal -= l[c][j] * l[c][j];
    l[c][c] = sqrt(diagonal);
    for (int r = c + 1; r < 6; ++r) {
      float value = a[r][c];
      for (int j = 0; j < c; ++j) value -= l[r][j] * l[c][j];
      l[r][c] = value / l[c][c];
    }
  }
  for (int r = 0; r < 6; ++r) {  // L y = b
    for (int j = 0; j < r; ++j) x[r] -= l[r][j] * x[j];
    x[r] /= l[r][r];
  }
  for (int r = 5; r >= 0; --r) {  // Lᵀ x = y
    for (int j = r + 1; j < 6; ++j) x[r] -= l[j][r] * x[j];
    x[r] /= l[r][r];
  }
}
