// Singular value decomposition of a 3×3 matrix with one instruction stream for every input:
//
//   svd3(A, U, sigma, V):  A = U diag(sigma) Vᵀ
//
// Conventions callers may rely on:
//   - U and V are proper rotations, det U = det V = +1;
//   - sigma[0] >= sigma[1] >= |sigma[2]|, with sigma[0] and sigma[1] >= 0;
//   - sigma[2] has the sign of det A: an inverted A gives sigma[2] < 0, never a reflection in U or V.
//
// Method: McAdams, Selle, Tamstorf, Teran, Sifakis 2011, "Computing the Singular Value Decomposition of 3×3
// matrices with minimal branching and elementary floating point operations" (UW-Madison TR1690):
//   1. Jacobi eigenanalysis of S = AᵀA by approximate Givens rotations, V accumulated as a quaternion;
//   2. B = A V, its columns sorted by decreasing norm with sign flips that keep det V = +1;
//   3. QR factorisation B = U R by exact Givens rotations; R is diagonal up to the Jacobi residual and its
//      diagonal is sigma.
// A fixed sweep count and selects in place of data-dependent branches; reciprocal square roots are
// inversesqrt(), no bit tricks.
//
// Range: S squares A and the Givens tests square S, so the entries of A should stay within about
// [1e-9, 1e9] in magnitude (deformation gradients are O(1)). Accuracy, measured by tests/gl/SvdTest.cpp:
// ‖U diag(sigma) Vᵀ − A‖ and the singular value errors are a few float ε times ‖A‖. As with any method
// that forms AᵀA in float, the singular vectors of a pair of singular values both far below ‖A‖ are only
// as good as ε‖A‖² allows.

// Jacobi sweeps, each over the pairs (0,1), (1,2), (2,0). The paper uses 4; measured on 10^5 matrices per
// family, 4 sweeps leave errors up to 1e-3 ‖A‖ (random matrices with two close small singular values) and
// 5 up to 2e-4 ‖A‖, while 6 reach the float rounding floor everywhere (7 changes nothing). A program may
// inject a smaller count with a #define to trade accuracy for speed.
#ifndef SVD3_JACOBI_SWEEPS
#define SVD3_JACOBI_SWEEPS 6
#endif

// Approximate Givens angles: γ = 3 + 2√2 = cot²(π/8), so the test γ sh² < ch² accepts the first-order
// half angle only while it is below π/8; otherwise the rotation is by π/4, half angle π/8.
const float SVD3_GAMMA = 5.82842712474619;            // 3 + 2*sqrt(2)
const float SVD3_COS_PI_OVER_8 = 0.923879532511287;  // cos(pi/8)
const float SVD3_SIN_PI_OVER_8 = 0.382683432365090;  // sin(pi/8)

// Below this |(a1, a2)| a QR Givens rotation is the identity. Far smaller than the 1e-6 of the
// paper's code, so that small nonzero entries of B are still eliminated; its square, 1e-36, is still a
// normal float (> 1.2e-38), so the normalisation in svd3_qrGivensRotation never divides by zero.
const float SVD3_QR_EPSILON = 1e-18;

// Hamilton product a ⊗ b of quaternions vec4(x, y, z, w), w the scalar part: R(a ⊗ b) = R(a) R(b).
vec4 svd3_quatMultiply(vec4 a, vec4 b) {
  return vec4(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}

// Rotation matrix of a unit quaternion vec4(x, y, z, w).
mat3 svd3_quatToMat3(vec4 q) {
  float xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
  float xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
  float wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  return mat3(vec3(1.0 - 2.0 * (yy + zz), 2.0 * (xy + wz), 2.0 * (xz - wy)),
              vec3(2.0 * (xy - wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz + wx)),
              vec3(2.0 * (xz + wy), 2.0 * (yz - wx), 1.0 - 2.0 * (xx + yy)));
}

// The paper's approximate Givens quaternion: (cos, sin) of the half angle of a rotation that nearly
// annihilates the off-diagonal entry of the symmetric block [[s_pp, s_pq], [s_pq, s_qq]]. The exact Jacobi
// angle θ solves tan 2θ = 2 s_pq / (s_pp − s_qq); to first order θ/2 = s_pq / (2 (s_pp − s_qq)), hence
// (ch, sh) ∝ (2 (s_pp − s_qq), s_pq). Angles the first-order form would get wrong fall back to θ = π/4.
vec2 svd3_approxGivensQuaternion(float s_pp, float s_pq, float s_qq) {
  float ch = 2.0 * (s_pp - s_qq);
  float sh = s_pq;
  bool firstOrderIsAccurate = SVD3_GAMMA * sh * sh < ch * ch;
  // Where the test fails ch² + sh² may be zero and ω infinite; the select discards that value.
  float omega = inversesqrt(ch * ch + sh * sh);
  return firstOrderIsAccurate ? omega * vec2(ch, sh) : vec2(SVD3_COS_PI_OVER_8, SVD3_SIN_PI_OVER_8);
}

// One Jacobi conjugation S ← Qᵀ S Q in the (p, q) plane, k the remaining index. Q rotates by θ about
// `axis` = e_k, (p, q, k) a cyclic permutation of (0, 1, 2), so on the (p, q) plane Q = [[c, −s], [s, c]] with
// c = cos θ = ch² − sh² and s = sin θ = 2 ch sh. V accumulates as qV ← qV ⊗ (sh e_k, ch).
void svd3_jacobiConjugation(inout float s_pp, inout float s_qq, inout float s_pq, inout float s_pk,
                            inout float s_qk, vec3 axis, inout vec4 qV) {
  vec2 halfAngle = svd3_approxGivensQuaternion(s_pp, s_pq, s_qq);
  float c = halfAngle.x * halfAngle.x - halfAngle.y * halfAngle.y;
  float s = 2.0 * halfAngle.x * halfAngle.y;

  float pp = c * c * s_pp + 2.0 * c * s * s_pq + s * s * s_qq;
  float qq = s * s * s_pp - 2.0 * c * s * s_pq + c * c * s_qq;
  float pq = c * s * (s_qq - s_pp) + (c * c - s * s) * s_pq;
  float pk = c * s_pk + s * s_qk;
  float qk = c * s_qk - s * s_pk;
  s_pp = pp;
  s_qq = qq;
  s_pq = pq;
  s_pk = pk;
  s_qk = qk;

  qV = svd3_quatMultiply(qV, vec4(halfAngle.y * axis, halfAngle.x));
}

// Step 1: the rotation V that diagonalises S = AᵀA, as a unit quaternion. S is held as its six distinct entries;
// visiting the pairs in cyclic order makes every rotation one about a coordinate axis with the same sign
// convention.
vec4 svd3_jacobiEigenanalysis(mat3 S) {
  float s00 = S[0][0], s11 = S[1][1], s22 = S[2][2];
  float s01 = S[1][0], s02 = S[2][0], s12 = S[2][1];
  vec4 qV = vec4(0.0, 0.0, 0.0, 1.0);
  for (int sweep = 0; sweep < SVD3_JACOBI_SWEEPS; ++sweep) {
    svd3_jacobiConjugation(s00, s11, s01, s02, s12, vec3(0.0, 0.0, 1.0), qV);  // (p, q, k) = (0, 1, 2)
    svd3_jacobiConjugation(s11, s22, s12, s01, s02, vec3(1.0, 0.0, 0.0), qV);  // (p, q, k) = (1, 2, 0)
    svd3_jacobiConjugation(s22, s00, s02, s12, s01, vec3(0.0, 1.0, 0.0), qV);  // (p, q, k) = (2, 0, 1)
  }
  // Every factor is a unit quaternion; this removes the rounding drift of their product.
  return qV * inversesqrt(dot(qV, qV));
}

// When `swap` holds, exchanges x and y and negates the new y, so that a matrix with x and y as columns keeps
// its determinant.
void svd3_conditionalNegatingSwap(bool swap, inout vec3 x, inout vec3 y) {
  vec3 negatedX = -x;
  x = swap ? y : x;
  y = swap ? negatedX : y;
}

// Step 2: sorts the columns of B = A V by decreasing norm, swapping the columns of V alike, so that B = A V
// still holds and det V stays +1.
void svd3_sortSingularValues(inout mat3 B, inout mat3 V) {
  vec3 rho = vec3(dot(B[0], B[0]), dot(B[1], B[1]), dot(B[2], B[2]));
  bool swap = rho.x < rho.y;
  svd3_conditionalNegatingSwap(swap, B[0], B[1]);
  svd3_conditionalNegatingSwap(swap, V[0], V[1]);
  rho.xy = swap ? rho.yx : rho.xy;

  swap = rho.x < rho.z;
  svd3_conditionalNegatingSwap(swap, B[0], B[2]);
  svd3_conditionalNegatingSwap(swap, V[0], V[2]);
  rho.xz = swap ? rho.zx : rho.xz;

  swap = rho.y < rho.z;
  svd3_conditionalNegatingSwap(swap, B[1], B[2]);
  svd3_conditionalNegatingSwap(swap, V[1], V[2]);
}

// The paper's QR Givens quaternion, returned as (c, s) = (cos θ, sin θ) of the Givens rotation
// G = [[c, −s], [s, c]] with Gᵀ (a1, a2) = (ρ, 0), ρ = |(a1, a2)|. Formed from the half angle,
// tan(θ/2) = a2 / (a1 + ρ), written for a1 < 0 as the equal (ρ − a1) / a2 by exchanging ch and sh, so that
// neither form suffers cancellation.
vec2 svd3_qrGivensRotation(float a1, float a2) {
  float rho = sqrt(a1 * a1 + a2 * a2);
  float sh = rho > SVD3_QR_EPSILON ? a2 : 0.0;
  float ch = abs(a1) + max(rho, SVD3_QR_EPSILON);
  vec2 halfAngle = a1 < 0.0 ? vec2(sh, ch) : vec2(ch, sh);
  halfAngle *= inversesqrt(dot(halfAngle, halfAngle));
  return vec2(halfAngle.x * halfAngle.x - halfAngle.y * halfAngle.y, 2.0 * halfAngle.x * halfAngle.y);
}

// Applies the Givens rotation (c, s) to a pair of vectors: rows p, q of B under B ← Gᵀ B, and equally
// columns p, q of U under U ← U G.
void svd3_rotatePair(vec2 cs, inout vec3 x, inout vec3 y) {
  vec3 rotatedX = cs.x * x + cs.y * y;
  y = cs.x * y - cs.y * x;
  x = rotatedX;
}

// Step 3: B = U R, U a rotation, R upper triangular with R00, R11 >= 0, by Givens rotations zeroing the entries
// (1,0), (2,0), (2,1) in turn; U is their product. Returns the diagonal of R. det R = det B, so the last
// entry carries the sign of det B.
vec3 svd3_qrDecomposition(mat3 B, out mat3 U) {
  mat3 rows = transpose(B);  // rows[i] is row i of B, so that row operations act on whole vectors
  U = mat3(1.0);
  vec2 cs = svd3_qrGivensRotation(rows[0].x, rows[1].x);
  svd3_rotatePair(cs, rows[0], rows[1]);
  svd3_rotatePair(cs, U[0], U[1]);

  cs = svd3_qrGivensRotation(rows[0].x, rows[2].x);
  svd3_rotatePair(cs, rows[0], rows[2]);
  svd3_rotatePair(cs, U[0], U[2]);

  cs = svd3_qrGivensRotation(rows[1].y, rows[2].y);
  svd3_rotatePair(cs, rows[1], rows[2]);
  svd3_rotatePair(cs, U[1], U[2]);
  return vec3(rows[0].x, rows[1].y, rows[2].z);
}

void svd3(mat3 A, out mat3 U, out vec3 sigma, out mat3 V) {
  V = svd3_quatToMat3(svd3_jacobiEigenanalysis(transpose(A) * A));
  mat3 B = A * V;
  svd3_sortSingularValues(B, V);
  sigma = svd3_qrDecomposition(B, U);
}
