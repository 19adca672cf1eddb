// svd3.glsl: singular value decomposition of a 3×3 matrix with a fixed instruction stream.
//
//   svd3(A, U, sigma, V):  A = U * diag(sigma) * transpose(V)
//
// Conventions (what callers may rely on):
//   - U and V are proper rotations, det U = det V = +1;
//   - sigma[0] >= sigma[1] >= |sigma[2]| and sigma[0], sigma[1] >= 0;
//   - sigma[2] carries the sign of det A: negative for an inverted A, so no reflection hides in U or V.
//
// Method: McAdams, Selle, Tamstorf, Teran, Sifakis 2011, "Computing the Singular Value Decomposition of
// 3×3 matrices with minimal branching and elementary floating point operations" (UW-Madison TR1690), §2-§4:
//   1. symmetric eigenanalysis of S = AᵀA by Jacobi sweeps with approximate Givens rotations, the
//      rotations accumulated as a quaternion for V (§2, Algorithm 2);
//   2. B = A V, columns sorted by decreasing norm with sign flips that keep V a rotation (§3);
//   3. QR factorisation B = U R by exact Givens rotations; R is diagonal up to the Jacobi residual and its
//      diagonal is sigma (§4, Algorithm 4).
// Every invocation runs the same instructions: a fixed sweep count and selects instead of data-dependent
// branches. No bit tricks: reciprocal square roots are inversesqrt().
//
// Range: S squares A and the Givens tests square S, so entries of A should lie roughly within
// [1e-9, 1e9] in magnitude (deformation gradients are O(1)).
//
// Quaternions are vec4(x, y, z, w) with w the scalar part.

// Jacobi sweeps over the three off-diagonal pairs; a program may inject another count with a #define
// to trade accuracy for speed. tests/gl/SvdTest.cpp measures the errors of the default.
#ifndef SVD3_JACOBI_SWEEPS
#define SVD3_JACOBI_SWEEPS 5
#endif

// Approximate Givens angles (§2.2): with γ = 3 + 2√2 = cot²(π/8), the test γ·sh² < ch² accepts the
// first-order angle only while the half angle stays below π/8; otherwise a rotation by π/4 is used.
const float SVD3_GAMMA = 5.828427124746190;        // 3 + 2*sqrt(2)
const float SVD3_COS_PI_OVER_8 = 0.9238795325112867;  // cos(pi/8)
const float SVD3_SIN_PI_OVER_8 = 0.3826834323650898;  // sin(pi/8)

// Threshold below which a QR Givens rotation is the identity (Algorithm 4). Kept tiny rather than the
// paper's 1e-6 so that small but nonzero entries of B are still eliminated; 1e-18 squared is 1e-36, still
// a normal float (> 1.2e-38), so the normalisation below never divides by zero.
const float SVD3_QR_EPSILON = 1e-18;

// Hamilton product a ⊗ b: the rotation of a after that of b, R(a ⊗ b) = R(a) R(b).
vec4 svd3_quatMultiply(vec4 a, vec4 b)
{
    return vec4(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}

// Rotation matrix of a unit quaternion.
mat3 svd3_quatToMat3(vec4 q)
{
    float xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
    float xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
    float wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    return mat3(vec3(1.0 - 2.0 * (yy + zz), 2.0 * (xy + wz), 2.0 * (xz - wy)),
                vec3(2.0 * (xy - wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz + wx)),
                vec3(2.0 * (xz + wy), 2.0 * (yz - wx), 1.0 - 2.0 * (xx + yy)));
}

// Algorithm 2: half-angle cosine and sine (ch, sh) of the rotation that approximately annihilates the
// off-diagonal entry of the symmetric 2×2 block [[s_pp, s_pq], [s_pq, s_qq]]. The exact Jacobi angle θ
// solves tan 2θ = 2 s_pq / (s_pp − s_qq); to first order θ/2 = s_pq / (2 (s_pp − s_qq)), which is what
// (ch, sh) ∝ (2 (s_pp − s_qq), s_pq) encodes. Large angles fall back to θ = π/4.
vec2 svd3_approxGivensQuaternion(float s_pp, float s_pq, float s_qq)
{
    float ch = 2.0 * (s_pp - s_qq);
    float sh = s_pq;
    bool firstOrderIsAccurate = SVD3_GAMMA * sh * sh < ch * ch;
    // When the test fails, ch² + sh² may be zero and ω infinite; the select discards that value.
    float omega = inversesqrt(ch * ch + sh * sh);
    return firstOrderIsAccurate ? omega * vec2(ch, sh) : vec2(SVD3_COS_PI_OVER_8, SVD3_SIN_PI_OVER_8);
}

// One Jacobi conjugation S ← Qᵀ S Q in the (p, q) plane, k being the third index (§2.1). Q rotates by θ
// about `axis` (e_k, with (p, q, k) a cyclic permutation of (0, 1, 2)), so in the (p, q) plane
// Q = [[c, −s], [s, c]] with c = cos θ = ch² − sh², s = sin θ = 2 ch sh. V accumulates as qV ← qV ⊗ q_Q.
void svd3_jacobiConjugation(inout float s_pp, inout float s_qq, inout float s_pq,
                            inout float s_pk, inout float s_qk, vec3 axis, inout vec4 qV)
{
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

// §2: the rotation V that (nearly) diagonalises S = AᵀA, as a unit quaternion. The symmetric S is held
// as its six distinct entries; each sweep visits the pairs (0,1), (1,2), (2,0) in cyclic order so that
// every rotation is about a coordinate axis with the same sign convention.
vec4 svd3_jacobiEigenanalysis(mat3 S)
{
    float s00 = S[0][0], s11 = S[1][1], s22 = S[2][2];
    float s01 = S[1][0], s02 = S[2][0], s12 = S[2][1];
    vec4 qV = vec4(0.0, 0.0, 0.0, 1.0);
    for (int sweep = 0; sweep < SVD3_JACOBI_SWEEPS; ++sweep) {
        svd3_jacobiConjugation(s00, s11, s01, s02, s12, vec3(0.0, 0.0, 1.0), qV);  // (p,q,k) = (0,1,2)
        svd3_jacobiConjugation(s11, s22, s12, s01, s02, vec3(1.0, 0.0, 0.0), qV);  // (p,q,k) = (1,2,0)
        svd3_jacobiConjugation(s22, s00, s02, s12, s01, vec3(0.0, 1.0, 0.0), qV);  // (p,q,k) = (2,0,1)
    }
    // Each factor is a unit quaternion; renormalise the rounding drift of twelve products.
    return qV * inversesqrt(dot(qV, qV));
}

// Swaps x and y when `swap` holds, negating one of them so that a matrix whose columns they are keeps
// its determinant (§3).
void svd3_conditionalNegatingSwap(bool swap, inout vec3 x, inout vec3 y)
{
    vec3 negatedX = -x;
    x = swap ? y : x;
    y = swap ? negatedX : y;
}

// §3: sorts the columns of B = A V by decreasing norm, applying the same swaps to V so B = A V still
// holds and det V stays +1.
void svd3_sortSingularValues(inout mat3 B, inout mat3 V)
{
    vec3 rho = vec3(dot(B[0], B[0]), dot(B[1], B[1]), dot(B[2], B[2]));
    bool swap = rho[0] < rho[1];
    svd3_conditionalNegatingSwap(swap, B[0], B[1]);
    svd3_conditionalNegatingSwap(swap, V[0], V[1]);
    rho.xy = swap ? rho.yx : rho.xy;

    swap = rho[0] < rho[2];
    svd3_conditionalNegatingSwap(swap, B[0], B[2]);
    svd3_conditionalNegatingSwap(swap, V[0], V[2]);
    rho.xz = swap ? rho.zx : rho.xz;

    swap = rho[1] < rho[2];
    svd3_conditionalNegatingSwap(swap, B[1], B[2]);
    svd3_conditionalNegatingSwap(swap, V[1], V[2]);
}

// Algorithm 4: (cos θ, sin θ) of the exact Givens rotation G = [[c, −s], [s, c]] with Gᵀ (a1, a2) =
// (ρ, 0), ρ = |(a1, a2)| ≥ 0. The paper forms the half-angle quaternion, tan(θ/2) = a2 / (a1 + ρ), and
// for a1 < 0 the equal (ρ − a1) / a2 by swapping ch and sh, so no cancellation occurs either way.
vec2 svd3_qrGivensRotation(float a1, float a2)
{
    float rho = sqrt(a1 * a1 + a2 * a2);
    float sh = rho > SVD3_QR_EPSILON ? a2 : 0.0;
    float ch = abs(a1) + max(rho, SVD3_QR_EPSILON);
    vec2 halfAngle = a1 < 0.0 ? vec2(sh, ch) : vec2(ch, sh);
    halfAngle *= inversesqrt(dot(halfAngle, halfAngle));
    return vec2(halfAngle.x * halfAngle.x - halfAngle.y * halfAngle.y, 2.0 * halfAngle.x * halfAngle.y);
}

// Applies a Givens rotation (c, s) to a pair of vectors: the rows p, q of B under B ← Gᵀ B, or equally
// the columns p, q of U under U ← U G.
void svd3_rotatePair(vec2 cs, inout vec3 x, inout vec3 y)
{
    vec3 rotatedX = cs.x * x + cs.y * y;
    y = cs.x * y - cs.y * x;
    x = rotatedX;
}

// §4: B = U R with U a rotation and R upper triangular with R[0][0], R[1][1] >= 0, by Givens rotations that
// zero the entries (1,0), (2,0), (2,1) in turn. Returns the diagonal of R; det R = det B, so the sign of
// the last entry is the sign of det B.
vec3 svd3_qrDecomposition(mat3 B, out mat3 U)
{
    mat3 rows = transpose(B);  // rows[i] is row i of B, so row operations act on whole vectors
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

void svd3(mat3 A, out mat3 U, out vec3 sigma, out mat3 V)
{
    V = svd3_quatToMat3(svd3_jacobiEigenanalysis(transpose(A) * A));
    mat3 B = A * V;
    svd3_sortSingularValues(B, V);
    sigma = svd3_qrDecomposition(B, U);
}
