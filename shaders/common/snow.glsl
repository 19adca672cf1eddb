// Stomakhin et al. 2013 snow: fixed corotated elasticity whose Lamé parameters harden with plastic
// compression, and plasticity by clamping the singular values of F_E.
#include "common/svd3.glsl"

struct SnowUpdate {
  mat3 elasticDeformation;  // F_E after clamping
  float plasticJ;           // J_P after the update
  mat3 kirchhoffStress;     // τ = (∂Ψ/∂F_E) F_Eᵀ (Pa)
};

// F̂_E = (I + Δt ∇v) F_E (eq. 8), SVD F̂_E = U Σ Vᵀ, Σ clamped to [1 − θc, 1 + θs] (eq. 10–11),
// J_P ← J_P det F̂_E / det F_E (only J_P of F_P is ever needed), then the stress of the new state.
SnowUpdate updateSnow(mat3 elasticDeformation, float plasticJ, mat3 velocityGradient, float dtS, MaterialParams m) {
  mat3 trial = (mat3(1.0) + dtS * velocityGradient) * elasticDeformation;
  mat3 U;
  vec3 sigma;
  mat3 V;
  svd3(trial, U, sigma, V);
  vec3 clamped = clamp(sigma, vec3(m.plastic.x), vec3(m.plastic.y));
  SnowUpdate result;
  result.elasticDeformation = U * mat3(clamped.x, 0.0, 0.0, 0.0, clamped.y, 0.0, 0.0, 0.0, clamped.z) * transpose(V);
  result.plasticJ = plasticJ * (sigma.x * sigma.y * sigma.z) / (clamped.x * clamped.y * clamped.z);

  // Hardening (eq. 7): μ = μ0 e^{ξ(1−J_P)}, λ = λ0 e^{ξ(1−J_P)}.
  float hardening = exp(m.elastic.z * (1.0 - result.plasticJ));
  float mu = m.elastic.x * hardening;
  float lambda = m.elastic.y * hardening;
  // ∂Ψ/∂F_E F_Eᵀ = 2μ(F_E − R_E)F_Eᵀ + λ(J_E − 1)J_E I with R_E = U Vᵀ, so R_E F_Eᵀ = U Σ Uᵀ (eq. 6).
  float elasticJ = clamped.x * clamped.y * clamped.z;
  mat3 F = result.elasticDeformation;
  mat3 rotatedStretch = U * mat3(clamped.x, 0.0, 0.0, 0.0, clamped.y, 0.0, 0.0, 0.0, clamped.z) * transpose(U);
  result.kirchhoffStress = 2.0 * mu * (F * transpose(F) - rotatedStretch) + lambda * (elasticJ - 1.0) * elasticJ * mat3(1.0);
  return result;
}
