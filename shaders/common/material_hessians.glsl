// The semi-implicit solve's material stiffness (docs/algorithm.md, "Semi-implicit steps"): the differential of the
// first Piola–Kirchhoff stress P = ∂Ψ/∂F in the direction δF, δP = ∂²Ψ/∂F² : δF (Stomakhin et al. 2013 §6), for
// the models with a Hessian: snow and the fixed corotated solid, and neo-Hookean. Water and sand have none, and the
// scene loader refuses them for a semi-implicit step.
//
// Every model here is isotropic, Ψ(F) = Ψ(σ) of the singular values of F = U Σ Vᵀ, and its Hessian takes a closed
// form in that frame (Stomakhin et al. 2012, "Energetically consistent invertible elasticity", §5; Smith et al.
// 2019, "Analytic eigensystems for isotropic distortion energies"): with δF̂ = Uᵀ δF V and ψ = ∂Ψ/∂σ,
//   δP̂ᵢᵢ = Σⱼ ∂²Ψ/∂σᵢ∂σⱼ δF̂ⱼⱼ, a 3×3 block on the diagonal, and for each pair of axes i ≠ j
//   (δP̂ᵢⱼ, δP̂ⱼᵢ) = [[a, b], [b, a]] (δF̂ᵢⱼ, δF̂ⱼᵢ), a 2×2 block with the eigenvalues
//   a + b = (ψᵢ − ψⱼ) / (σᵢ − σⱼ) on shear (δF̂ᵢⱼ = δF̂ⱼᵢ) and a − b = (ψᵢ + ψⱼ) / (σᵢ + σⱼ) on rotation.
// Compressed snow makes the rotation eigenvalue negative (fixed corotated: 2μ(1 − 2 / (σᵢ + σⱼ)) + λ(J − 1)σₖ), and
// β Δt² H then outweighs M at steps many times the elastic bound: the system is indefinite, and the conjugate
// residual method stalls or diverges on it. Each block is therefore projected onto the positive semi-definite
// matrices (its negative eigenvalues set to 0), as projected Newton methods do: the step is unchanged where the
// Hessian is definite, and elsewhere the solve damps the modes that would soften instead of amplifying them.
#include "common/materials.glsl"

layout(std430, binding = FIRN_BINDING_SOLVER_PARTICLES) buffer SolverParticlesBuffer {
  SolverParticle solverParticles[];
};

// Ψ's Hessian in the frame of F's singular values: ∂²Ψ/∂σ², and per pair of axes other than 1, 2, 3 (the pair
// (2, 3), then (3, 1), then (1, 2)) the 2×2 block's eigenvalues on shear and on rotation.
struct PrincipalHessian {
  mat3 scaling;
  vec3 shear;
  vec3 rotation;
};

// The symmetric matrix with `offDiagonal` (the entries of the pairs (2, 3), (3, 1), (1, 2)) off its diagonal.
mat3 pairMatrix(vec3 offDiagonal) {
  return mat3(0.0, offDiagonal.z, offDiagonal.y, offDiagonal.z, 0.0, offDiagonal.x, offDiagonal.y, offDiagonal.x, 0.0);
}

#if defined(FIRN_MATERIAL_SNOW) || defined(FIRN_MATERIAL_FIXED_COROTATED)
// Ψ = μ Σ(σᵢ − 1)² + λ/2 (J − 1)² (Stomakhin 2013 eq. 6 in singular values), ψᵢ = 2μ(σᵢ − 1) + λ(J − 1) J/σᵢ:
// ∂²Ψ/∂σᵢ∂σⱼ = 2μ δᵢⱼ + λ (J/σᵢ)(J/σⱼ) + λ(J − 1) σₖ (i ≠ j), shear 2μ − λ(J − 1)σₖ and rotation
// 2μ(1 − 2 / (σᵢ + σⱼ)) + λ(J − 1)σₖ. J/σᵢ is the product of the other two: nothing divides by a singular value.
PrincipalHessian fixedCorotatedHessian(vec3 sigma, float mu, float lambda) {
  float J = sigma.x * sigma.y * sigma.z;
  vec3 others = vec3(sigma.y * sigma.z, sigma.z * sigma.x, sigma.x * sigma.y);  // J/σᵢ
  // An inverted F (σ₃ < 0) can make a pair's sum negative: its sign is kept, and only a sum within 1e-6 of zero,
  // where the rotation of F is undefined, is held there so that the block stays finite.
  vec3 pairSums = vec3(sigma.y + sigma.z, sigma.z + sigma.x, sigma.x + sigma.y);
  vec3 pairSigns = mix(vec3(1.0), vec3(-1.0), lessThan(pairSums, vec3(0.0)));
  pairSums = pairSigns * max(abs(pairSums), vec3(1e-6));
  PrincipalHessian h;
  h.scaling = 2.0 * mu * mat3(1.0) + lambda * outerProduct(others, others) + lambda * (J - 1.0) * pairMatrix(sigma);
  h.shear = 2.0 * mu - lambda * (J - 1.0) * sigma;
  h.rotation = 2.0 * mu * (1.0 - 2.0 / pairSums) + lambda * (J - 1.0) * sigma;
  return h;
}
#endif

#ifdef FIRN_MATERIAL_NEO_HOOKEAN
// P = μ(F − F⁻ᵀ) + λ ln J F⁻ᵀ, so ψᵢ = μ(σᵢ − 1/σᵢ) + λ ln J / σᵢ: ∂²Ψ/∂σᵢ∂σⱼ = μ δᵢⱼ + (μ − λ ln J) δᵢⱼ / σᵢ² +
// λ / (σᵢσⱼ), shear μ + (μ − λ ln J) / (σᵢσⱼ) and rotation μ − (μ − λ ln J) / (σᵢσⱼ), σᵢσⱼ = J/σₖ.
PrincipalHessian neoHookeanHessian(vec3 sigma, float mu, float lambda) {
  vec3 inverse = 1.0 / sigma;
  float logJ = logAccurate(sigma.x * sigma.y * sigma.z);
  vec3 pairProducts = vec3(sigma.y * sigma.z, sigma.z * sigma.x, sigma.x * sigma.y);
  PrincipalHessian h;
  h.scaling = mu * mat3(1.0) + (mu - lambda * logJ) * diagonal(inverse * inverse) + lambda * outerProduct(inverse, inverse);
  h.shear = mu + (mu - lambda * logJ) / pairProducts;
  h.rotation = mu - (mu - lambda * logJ) / pairProducts;
  return h;
}
#endif

// The nearest positive semi-definite matrix to the symmetric S: S itself when its leading minors are positive
// (Sylvester's criterion), otherwise S with its negative eigenvalues set to 0 (svd3.glsl's Jacobi eigenanalysis).
mat3 positiveSemiDefinite(mat3 S) {
  float minor2 = S[0][0] * S[1][1] - S[1][0] * S[1][0];
  if (S[0][0] > 0.0 && minor2 > 0.0 && determinant(S) > 0.0) return S;
  mat3 Q = svd3_quatToMat3(svd3_jacobiEigenanalysis(S));
  mat3 D = transpose(Q) * S * Q;
  return Q * diagonal(max(vec3(D[0][0], D[1][1], D[2][2]), vec3(0.0))) * transpose(Q);
}

// Snow's Lamé parameters as hardened at J_P (eq. 7); the other models' as they are.
vec2 currentLameParameters(MaterialParams m, float plasticJ) {
  return m.model.x == MODEL_SNOW ? hardenedLameParameters(m, plasticJ) : m.elastic.xy;
}

// A particle's stiffness for the step (solver_prepare.comp): its model's Hessian at F, in F's frame, projected
// (test builds with FIRN_SOLVER_UNPROJECTED_HESSIAN keep it as it is, to compare it with the force's difference).
SolverParticle principalStiffness(mat3 F, MaterialParams m, float plasticJ) {
  mat3 U, V;
  vec3 sigma;
  svd3(F, U, sigma, V);
  vec2 lame = currentLameParameters(m, plasticJ);
  PrincipalHessian h;
#if defined(FIRN_MATERIAL_SNOW) || defined(FIRN_MATERIAL_FIXED_COROTATED)
  if (m.model.x == MODEL_SNOW || m.model.x == MODEL_FIXED_COROTATED) h = fixedCorotatedHessian(sigma, lame.x, lame.y);
#endif
#ifdef FIRN_MATERIAL_NEO_HOOKEAN
  if (m.model.x == MODEL_NEO_HOOKEAN) h = neoHookeanHessian(sigma, lame.x, lame.y);
#endif
#ifndef FIRN_SOLVER_UNPROJECTED_HESSIAN
  h.scaling = positiveSemiDefinite(h.scaling);
  h.shear = max(h.shear, vec3(0.0));
  h.rotation = max(h.rotation, vec3(0.0));
#endif
  vec3 same = 0.5 * (h.shear + h.rotation);
  SolverParticle s;
  s.left = U;
  s.singularValues = vec4(sigma, 0.0);
  s.scalingDiagonal = vec4(h.scaling[0][0], h.scaling[1][1], h.scaling[2][2], 0.0);
  s.scalingOffDiagonal = vec4(h.scaling[2][1], h.scaling[0][2], h.scaling[1][0], 0.0);
  s.pairSame = vec4(same, 0.0);
  s.pairCross = vec4(0.5 * (h.shear - h.rotation), 0.0);
  // xyz: what couples two axes in a node's stiffness block (stiffnessBlockForm); w: 2μ + λ, the stiffness the
  // explicit stress's float rounding scales with (the solve's floor, solver_residual.comp).
  s.blockCoupling = vec4(s.scalingOffDiagonal.xyz + s.pairCross.xyz, 2.0 * lame.y + lame.x);
  return s;
}

// δP Fᵀ (Pa) of a particle's stiffness for the velocity gradient G = Σᵢ uᵢ ∇wᵢᵀ over Δt, δF = Δt G F. In F's frame
// δF̂ = Uᵀ δF V = Δt Uᵀ G U Σ, and δP Fᵀ = U δP̂ Σ Uᵀ: V drops out.
mat3 stressDifferentialTimesFT(SolverParticle s, mat3 velocityGradient, float dtS) {
  mat3 U = s.left;
  vec3 sigma = s.singularValues.xyz;
  mat3 dF = dtS * transpose(U) * velocityGradient * U * diagonal(sigma);
  vec3 scaled = vec3(dF[0][0], dF[1][1], dF[2][2]);
  vec3 scaledStress = s.scalingDiagonal.xyz * scaled + pairMatrix(s.scalingOffDiagonal.xyz) * scaled;
  // The pairs (2, 3), (3, 1), (1, 2): entry (i, j) of a mat3 is m[j][i].
  vec3 upper = vec3(dF[2][1], dF[0][2], dF[1][0]);  // δF̂₂₃, δF̂₃₁, δF̂₁₂
  vec3 lower = vec3(dF[1][2], dF[2][0], dF[0][1]);  // δF̂₃₂, δF̂₁₃, δF̂₂₁
  vec3 upperStress = s.pairSame.xyz * upper + s.pairCross.xyz * lower;
  vec3 lowerStress = s.pairSame.xyz * lower + s.pairCross.xyz * upper;
  mat3 dP = mat3(scaledStress.x, lowerStress.z, upperStress.y,
                 upperStress.z, scaledStress.y, lowerStress.x,
                 lowerStress.y, upperStress.x, scaledStress.z);
  return U * dP * diagonal(sigma) * transpose(U);
}

// What a particle adds at a node of weight gradient ∇w (1/m) to H's 3×3 block there, per unit of its volume (Pa/m²):
// the block preconditioner's (common/solver.glsl). Moving the node at u changes F by δF = Δt u ∇wᵀ F, so
// δF̂ = Uᵀ δF V = Δt a ĝᵀ with a = Uᵀ u and ĝ = Vᵀ Fᵀ ∇w = Σ h, h = Uᵀ ∇w: rank one. The stiffness's quadratic form
// on a ĝᵀ is aᵀ B a, with B_kk = Σⱼ C_kj σⱼ² hⱼ² (C_kk = ∂²Ψ/∂σₖ², C_kj the a of the pair (k, j)'s [[a, b], [b, a]]
// block) and B_kl = c_kl σₖ σₗ hₖ hₗ (c_kl = ∂²Ψ/∂σₖ∂σₗ + b of the pair), and in the world's frame the block is
// U B Uᵀ = Σⱼ hⱼ² Mⱼ + Σ_{k<l} hₖ hₗ Q_kl, Mⱼ = Σₖ C_kj σⱼ² uₖ uₖᵀ and Q_kl = c_kl σₖ σₗ (uₖ uₗᵀ + uₗ uₖᵀ), uₖ U's
// columns: positive semi-definite as the stiffness is. The six symmetric matrices depend on the particle alone, so a
// node takes h and the 36 products of their entries with hⱼ², hₖ hₗ.
struct StiffnessBlockForm {
  mat3 frame;            // U
  mat3 squaresDiagonal;  // column j: Mⱼ's diagonal
  mat3 squaresOff;       // column j: Mⱼ's entries yz, zx, xy
  mat3 pairsDiagonal;    // column m, the pairs (2, 3), (3, 1), (1, 2): Q's diagonal
  mat3 pairsOff;         // and its entries yz, zx, xy
};

// The off-diagonal entries yz, zx, xy of a ⊗ b + b ⊗ a.
vec3 symmetricOffDiagonal(vec3 a, vec3 b) { return a.yzx * b.zxy + b.yzx * a.zxy; }

StiffnessBlockForm stiffnessBlockForm(SolverParticle s) {
  StiffnessBlockForm f;
  mat3 U = s.left;
  vec3 sigma = s.singularValues.xyz;
  vec3 same = s.pairSame.xyz;  // the pairs (2, 3), (3, 1), (1, 2)
  // C with its columns scaled by σⱼ².
  mat3 C = mat3(s.scalingDiagonal.x, same.z, same.y,
                same.z, s.scalingDiagonal.y, same.x,
                same.y, same.x, s.scalingDiagonal.z) * diagonal(sigma * sigma);
  f.frame = U;
  f.squaresDiagonal = mat3(U[0] * U[0], U[1] * U[1], U[2] * U[2]) * C;
  f.squaresOff = 0.5 * mat3(symmetricOffDiagonal(U[0], U[0]), symmetricOffDiagonal(U[1], U[1]),
                            symmetricOffDiagonal(U[2], U[2])) * C;
  vec3 coupling = s.blockCoupling.xyz * sigma.yzx * sigma.zxy;
  f.pairsDiagonal = mat3(2.0 * U[1] * U[2], 2.0 * U[2] * U[0], 2.0 * U[0] * U[1]) * diagonal(coupling);
  f.pairsOff = mat3(symmetricOffDiagonal(U[1], U[2]), symmetricOffDiagonal(U[2], U[0]),
                    symmetricOffDiagonal(U[0], U[1])) * diagonal(coupling);
  return f;
}

// The block at a node of weight gradient ∇w: its diagonal and its entries yz, zx, xy.
void stiffnessBlock(StiffnessBlockForm f, vec3 weightGradient, out vec3 blockDiagonal, out vec3 blockOff) {
  vec3 h = transpose(f.frame) * weightGradient;
  vec3 squares = h * h;
  vec3 products = h.yzx * h.zxy;  // h₂h₃, h₃h₁, h₁h₂
  blockDiagonal = f.squaresDiagonal * squares + f.pairsDiagonal * products;
  blockOff = f.squaresOff * squares + f.pairsOff * products;
}
