// The semi-implicit solve's material derivatives (docs/algorithm.md, "Semi-implicit steps"): for each model with a
// Hessian, the differential of the first Piola–Kirchhoff stress P = ∂Ψ/∂F in the direction δF,
// δP = ∂²Ψ/∂F² : δF (Stomakhin et al. 2013 §6 and their technical report, "Derivation of the Hessian"). Snow and
// the fixed corotated solid share one; neo-Hookean has its own; water and sand have none, and the scene loader
// refuses them for a semi-implicit step.
#include "common/materials.glsl"

layout(std430, binding = FIRN_BINDING_SOLVER_PARTICLES) buffer SolverParticleBuffer { SolverParticle solverParticles[]; };

// [y]×, the matrix of the cross product y × (·).
mat3 crossMatrix(vec3 y) { return mat3(0.0, y.z, -y.y, -y.z, 0.0, y.x, y.y, -y.x, 0.0); }

// A : B.
float contract(mat3 a, mat3 b) { return dot(a[0], b[0]) + dot(a[1], b[1]) + dot(a[2], b[2]); }

// J F⁻ᵀ, the cofactor matrix: its columns are the cross products of F's other two columns (defined for any F).
mat3 cofactor(mat3 F) { return mat3(cross(F[1], F[2]), cross(F[2], F[0]), cross(F[0], F[1])); }
mat3 cofactorDifferential(mat3 F, mat3 dF) {
  return mat3(cross(dF[1], F[2]) + cross(F[1], dF[2]), cross(dF[2], F[0]) + cross(F[2], dF[0]),
              cross(dF[0], F[1]) + cross(F[0], dF[1]));
}

#if defined(FIRN_MATERIAL_SNOW) || defined(FIRN_MATERIAL_FIXED_COROTATED)
// What the derivative of R needs, once per step: for F = R S (polar; F = U Σ Vᵀ, R = U Vᵀ, S = V Σ Vᵀ), R and
// K = (tr(S) I − S)⁻¹ = V diag(1 / (σ₂ + σ₃), 1 / (σ₁ + σ₃), 1 / (σ₁ + σ₂)) Vᵀ. A pair of singular values summing to
// nearly 0 (an inverted solid) leaves R's derivative undefined; the sum is held at 1e-6.
SolverParticle polarDerivativeSystem(mat3 F) {
  mat3 U, V;
  vec3 sigma;
  svd3(F, U, sigma, V);
  vec3 pairSums = vec3(sigma.y + sigma.z, sigma.x + sigma.z, sigma.x + sigma.y);
  SolverParticle result;
  result.rotation = U * transpose(V);
  result.rotationDerivative = V * diagonal(1.0 / max(pairSums, vec3(1e-6))) * transpose(V);
  return result;
}

// δR: RᵀδR is skew, [y]×, and the derivative of F = R S gives Rᵀ δF − δFᵀ R = [y]× S + S [y]× = [(tr(S) I − S) y]×,
// so y = K b with [b]× = Rᵀ δF − (Rᵀ δF)ᵀ.
mat3 rotationDifferential(SolverParticle polar, mat3 dF) {
  mat3 b = transpose(polar.rotation) * dF;
  vec3 axial = vec3(b[1][2] - b[2][1], b[2][0] - b[0][2], b[0][1] - b[1][0]);
  return polar.rotation * crossMatrix(polar.rotationDerivative * axial);
}

// Ψ = μ‖F − R‖² + λ/2 (J − 1)², P = 2μ(F − R) + λ(J − 1) J F⁻ᵀ (Stomakhin 2013 eq. 6), so
// δP = 2μ(δF − δR) + λ (J F⁻ᵀ : δF) J F⁻ᵀ + λ(J − 1) δ(J F⁻ᵀ).
mat3 fixedCorotatedStressDifferential(mat3 F, mat3 dF, SolverParticle polar, float mu, float lambda) {
  mat3 C = cofactor(F);
  float J = dot(F[0], C[0]);
  return 2.0 * mu * (dF - rotationDifferential(polar, dF)) + lambda * contract(C, dF) * C +
         lambda * (J - 1.0) * cofactorDifferential(F, dF);
}
#endif

#ifdef FIRN_MATERIAL_NEO_HOOKEAN
// P = μ(F − F⁻ᵀ) + λ ln J F⁻ᵀ, with δ(F⁻ᵀ) = −F⁻ᵀ δFᵀ F⁻ᵀ and δ ln J = tr(F⁻¹ δF):
// δP = μ δF + (μ − λ ln J) F⁻ᵀ δFᵀ F⁻ᵀ + λ tr(F⁻¹ δF) F⁻ᵀ.
mat3 neoHookeanStressDifferential(mat3 F, mat3 dF, float mu, float lambda) {
  mat3 inverseF = inverse(F);
  mat3 inverseTransposeF = transpose(inverseF);
  mat3 inverseTimesDF = inverseF * dF;
  float traceTerm = inverseTimesDF[0][0] + inverseTimesDF[1][1] + inverseTimesDF[2][2];
  return mu * dF + (mu - lambda * log(determinant(F))) * inverseTransposeF * transpose(dF) * inverseTransposeF +
         lambda * traceTerm * inverseTransposeF;
}
#endif

// Snow's Lamé parameters as hardened at J_P (eq. 7); the other models' as they are.
vec2 currentLameParameters(MaterialParams m, float plasticJ) {
  float hardening = m.model.x == MODEL_SNOW ? exp(m.elastic.z * (1.0 - plasticJ)) : 1.0;
  return m.elastic.xy * hardening;
}

// δP of particle p's material at its F in the direction δF.
mat3 stressDifferential(uint p, mat3 F, mat3 dF, MaterialParams m, float plasticJ) {
  vec2 lame = currentLameParameters(m, plasticJ);
  switch (m.model.x) {
#if defined(FIRN_MATERIAL_SNOW) || defined(FIRN_MATERIAL_FIXED_COROTATED)
    case MODEL_SNOW:
    case MODEL_FIXED_COROTATED: return fixedCorotatedStressDifferential(F, dF, solverParticles[p], lame.x, lame.y);
#endif
#ifdef FIRN_MATERIAL_NEO_HOOKEAN
    case MODEL_NEO_HOOKEAN: return neoHookeanStressDifferential(F, dF, lame.x, lame.y);
#endif
  }
  return mat3(0.0);  // unreachable: the scene loader refuses the models without one
}
