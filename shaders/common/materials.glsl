// The constitutive models (docs/algorithm.md, Material models): for each, the deformation update of one particle
// and its Kirchhoff stress τ = (∂Ψ/∂F) Fᵀ, which P2G turns into nodal forces. Only the models a scene uses are
// compiled in (FIRN_MATERIAL_* defines), so a snow-only scene carries no code for the others.
#include "common/shared_functions.h"
#include "common/svd3.glsl"

struct MaterialUpdate {
  mat3 deformation;        // F after the step (F_E for snow and sand); water keeps none
  float state;             // ParticlePlasticState.plasticJ: snow J_P, water J, sand q
  float volumeCorrection;  // ParticlePlasticState.volumeCorrection: sand V_c
  mat3 kirchhoffStress;    // τ (Pa)
  // Snow: what the change of J_P's hardening did to the elastic energy density the new F_E holds (J/m³), Ψ₀(F_E)
  // (e^{ξ(1−J_P')} − e^{ξ(1−J_P)}): energy the model's hardening gives (compaction) or takes (loosening), which the
  // energy audit counts as such (common/energy.glsl). 0 for the other models.
  float hardeningEnergyDensity;
};

mat3 diagonal(vec3 d) { return mat3(d.x, 0.0, 0.0, 0.0, d.y, 0.0, 0.0, 0.0, d.z); }

// ln x to a few ulps of ln x also where x is near 1, for the strains of the models (Hencky's ln Σ, ln J): GLSL lets
// log(x) be off by 2⁻²¹ absolutely for x in [0.5, 2] (GLSL 4.30 §8.2), the whole of a strain of 1e-7 and more. Sand
// at rest (Σ ≈ 1 ± 1e-7) would take strains of that size and its volume correction would sum them every step.
// Within 1/32 of 1, x − 1 is exact (Sterbenz) and the series ln(1 + y) = y − y²/2 + y³/3 − y⁴/4 + y⁵/5 is off by less
// than y⁶/6 < 2e-10 absolutely, 5e-9 relatively.
float logAccurate(float x) {
  float y = x - 1.0;
  if (abs(y) >= 1.0 / 32.0) return log(x);
  return y * (1.0 - y * (0.5 - y * (1.0 / 3.0 - y * (0.25 - y * 0.2))));
}
vec3 logAccurate(vec3 x) { return vec3(logAccurate(x.x), logAccurate(x.y), logAccurate(x.z)); }

// F̂ = (I + Δt ∇v) F (Stomakhin 2013 eq. 8; Blažević 2022 eq. 3.19).
mat3 advanceDeformation(mat3 F, mat3 velocityGradient, float dtS) { return (mat3(1.0) + dtS * velocityGradient) * F; }

#if defined(FIRN_MATERIAL_SNOW) || defined(FIRN_MATERIAL_FIXED_COROTATED)
// The fixed corotated stress (Stomakhin 2013 eq. 6; Blažević 2022 eq. 4.8): ∂Ψ/∂F Fᵀ = 2μ(F − R)Fᵀ + λ(J − 1)J I for
// F = U Σ Vᵀ and R = U Vᵀ, so R Fᵀ = U Σ Uᵀ.
mat3 fixedCorotatedStress(mat3 F, mat3 U, vec3 sigma, float mu, float lambda) {
  float J = sigma.x * sigma.y * sigma.z;
  return 2.0 * mu * (F * transpose(F) - U * diagonal(sigma) * transpose(U)) + lambda * (J - 1.0) * J * mat3(1.0);
}
#endif

// Snow's Lamé parameters hardened at J_P (eq. 7): μ = μ0 e^{ξ(1−J_P)}, λ = λ0 e^{ξ(1−J_P)}.
vec2 hardenedLameParameters(MaterialParams m, float plasticJ) {
  return m.elastic.xy * snowHardening(m.elastic.z, plasticJ);
}

#ifdef FIRN_MATERIAL_SNOW
// Stomakhin 2013: SVD F̂_E = U Σ Vᵀ, Σ clamped to [1 − θc, 1 + θs] (eq. 10–11), J_P ← J_P det F̂_E / det F_E,
// then the fixed corotated stress of the new F_E with hardened Lamé parameters (eq. 6–7).
MaterialUpdate updateSnow(mat3 F, float plasticJ, mat3 velocityGradient, float dtS, MaterialParams m) {
  mat3 U, V;
  vec3 sigma;
  svd3(advanceDeformation(F, velocityGradient, dtS), U, sigma, V);
  vec3 clamped = clamp(sigma, vec3(m.plastic.x), vec3(m.plastic.y));
  MaterialUpdate result;
  result.deformation = U * diagonal(clamped) * transpose(V);
  result.state = plasticJ * (sigma.x * sigma.y * sigma.z) / (clamped.x * clamped.y * clamped.z);
  result.volumeCorrection = 0.0;
  vec2 lame = hardenedLameParameters(m, result.state);
  result.kirchhoffStress = fixedCorotatedStress(result.deformation, U, clamped, lame.x, lame.y);
  result.hardeningEnergyDensity = 0.0;
  if (result.state != plasticJ) {
    result.hardeningEnergyDensity =
        fixedCorotatedEnergyDensity(m.elastic.x, m.elastic.y, clamped.x, clamped.y, clamped.z) *
        (snowHardening(m.elastic.z, result.state) - snowHardening(m.elastic.z, plasticJ));
  }
  return result;
}
#endif

// A purely elastic solid's update: F advanced, no scalar state.
MaterialUpdate elasticUpdate(mat3 F, mat3 kirchhoffStress) {
  MaterialUpdate result;
  result.deformation = F;
  result.state = 1.0;
  result.volumeCorrection = 0.0;
  result.kirchhoffStress = kirchhoffStress;
  result.hardeningEnergyDensity = 0.0;
  return result;
}

#ifdef FIRN_MATERIAL_FIXED_COROTATED
MaterialUpdate updateFixedCorotated(mat3 F, mat3 velocityGradient, float dtS, MaterialParams m) {
  mat3 Fn = advanceDeformation(F, velocityGradient, dtS);
  mat3 U, V;
  vec3 sigma;
  svd3(Fn, U, sigma, V);
  return elasticUpdate(Fn, fixedCorotatedStress(Fn, U, sigma, m.elastic.x, m.elastic.y));
}
#endif

#ifdef FIRN_MATERIAL_NEO_HOOKEAN
// Blažević 2022 eq. 4.5: ∂Ψ/∂F = μ(F − F⁻ᵀ) + λ ln J F⁻ᵀ (the thesis prints F − Fᵀ; the derivative of −μ ln J is
// −μ F⁻ᵀ), so τ = μ(F Fᵀ − I) + λ ln J I: no SVD. An inverted F (J ≤ 0) gives a non-finite τ, which the
// watchdog reports.
mat3 neoHookeanStress(mat3 F, float mu, float lambda) {
  return mu * (F * transpose(F) - mat3(1.0)) + lambda * logAccurate(determinant(F)) * mat3(1.0);
}

MaterialUpdate updateNeoHookean(mat3 F, mat3 velocityGradient, float dtS, MaterialParams m) {
  mat3 Fn = advanceDeformation(F, velocityGradient, dtS);
  return elasticUpdate(Fn, neoHookeanStress(Fn, m.elastic.x, m.elastic.y));
}
#endif

#ifdef FIRN_MATERIAL_WATER
// Blažević 2022 §4.1: only J = det F is kept, J ← (1 + Δt tr ∇v) J; p = −∂Ψ/∂J = k(J^−γ − 1), τ = −p J I. The
// optional viscous stress is Newtonian, σ = η(∇v + ∇vᵀ), so τ = J η(∇v + ∇vᵀ).
MaterialUpdate updateWater(float J, mat3 velocityGradient, float dtS, MaterialParams m) {
  MaterialUpdate result;
  float newJ = (1.0 + dtS * (velocityGradient[0][0] + velocityGradient[1][1] + velocityGradient[2][2])) * J;
  // J^−γ as exp(−γ ln J): pow takes its logarithm with log's absolute error, a pressure of k γ 2⁻²¹ at rest.
  float pressure = m.fluid.x * (exp(-m.fluid.y * logAccurate(newJ)) - 1.0);
  result.kirchhoffStress = -pressure * newJ * mat3(1.0) +
                           newJ * m.fluid.z * (velocityGradient + transpose(velocityGradient));
  result.deformation = mat3(1.0);
  result.state = newJ;
  result.volumeCorrection = 0.0;
  result.hardeningEnergyDensity = 0.0;
  return result;
}
#endif

#ifdef FIRN_MATERIAL_DRUCKER_PRAGER
// Klár et al. 2016 sand (Blažević 2022 §4.4): Hencky elasticity Ψ = μ tr((ln Σ)²) + λ/2 (tr ln Σ)² (eq. 4.12) on
// F_E, whose log-strain ε = ln Σ + V_c/3 is projected onto the Drucker–Prager cone of friction coefficient α
// (eq. 4.14–4.15), with hardening q (eq. 4.16–4.18) and the log-volume correction V_c of the pseudocode 7.
float frictionCoefficient(float q, MaterialParams m) {
  float phi = m.plastic.x + (m.plastic.y * q - m.plastic.w) * exp(-m.plastic.z * q);  // eq. 4.17 (radians)
  float s = sin(phi);
  return sqrt(2.0 / 3.0) * 2.0 * s / (3.0 - s);  // eq. 4.18
}

MaterialUpdate updateDruckerPrager(mat3 F, float q, float volumeCorrection, mat3 velocityGradient, float dtS,
                                   MaterialParams m) {
  mat3 U, V;
  vec3 sigma;
  svd3(advanceDeformation(F, velocityGradient, dtS), U, sigma, V);
  // A singular value at or below 0 (an inverted cell) has no logarithm; such compression is far outside the
  // model, so it is held at 1e-4 instead of turning the particle into NaN.
  sigma = max(sigma, vec3(1e-4));
  float mu = m.elastic.x;
  float lambda = m.elastic.y;
  vec3 logSigmaTrial = logAccurate(sigma);
  vec3 epsilon = logSigmaTrial + volumeCorrection / 3.0;
  float traceEpsilon = epsilon.x + epsilon.y + epsilon.z;
  vec3 deviatoric = epsilon - traceEpsilon / 3.0;
  float deviatoricNorm = length(deviatoric);
  vec3 projected = sigma;  // case 1: inside the cone
  float plasticIncrement = 0.0;
  if (deviatoricNorm == 0.0 || traceEpsilon > 0.0) {
    projected = vec3(1.0);  // case 2: expansion, to the cone's tip: no stress
    plasticIncrement = length(epsilon);
  } else {
    float deltaGamma = deviatoricNorm + (3.0 * lambda + 2.0 * mu) / (2.0 * mu) * traceEpsilon * frictionCoefficient(q, m);
    if (deltaGamma > 0.0) {  // case 3: onto the cone's surface
      projected = exp(epsilon - deltaGamma * deviatoric / deviatoricNorm);
      plasticIncrement = deltaGamma;
    }
  }
  MaterialUpdate result;
  result.deformation = U * diagonal(projected) * transpose(V);
  // V_c collects the volume the projection removed, so that loosened sand must be compressed back before it
  // bears load again.
  // τ = U (2μ ln Σ + λ tr(ln Σ) I) Uᵀ for the Hencky energy (eq. 4.13).
  vec3 logSigma = logAccurate(projected);
  result.volumeCorrection = volumeCorrection + (logSigmaTrial.x + logSigmaTrial.y + logSigmaTrial.z) -
                            (logSigma.x + logSigma.y + logSigma.z);
  result.state = q + plasticIncrement;
  result.kirchhoffStress = U * diagonal(2.0 * mu * logSigma + lambda * (logSigma.x + logSigma.y + logSigma.z)) * transpose(U);
  result.hardeningEnergyDensity = 0.0;  // sand's hardening moves its cone, not its elastic moduli
  return result;
}
#endif

// The speed of the fastest elastic (pressure) wave in the particle's present state (m/s), for adaptive steps:
// sqrt((λ + 2μ) / ρ), with snow's moduli as hardened now, not at rest (compacted snow stiffens by
// e^{ξ(1 − J_P)}, by 148× at J_P = 0.5 with ξ = 10), and sqrt(k γ / ρ) for water.
float waveSpeed(MaterialParams m, float state) {
  if (m.model.x == MODEL_WATER) return waterWaveSpeed(m.fluid.x, m.fluid.y, m.elastic.w);
  float stiffening = m.model.x == MODEL_SNOW ? snowHardening(m.elastic.z, state) : 1.0;
  return pressureWaveSpeed(m.elastic.y, m.elastic.x, stiffening, m.elastic.w);
}

// The elastic strain energy density Ψ (J/m³) of the particle's state, of which its Kirchhoff stress is the derivative
// (shared_functions.h): snow's and the fixed corotated's from F's singular values (snow's moduli hardened at its J_P),
// the neo-Hookean's from tr FᵀF and ln J, water's from its J, sand's Hencky energy from F_E's (held at 1e-4 and above,
// as its update holds them). `F` is ignored by water. For the energy audit (common/energy.glsl), once a frame.
float strainEnergyDensity(mat3 F, ParticlePlasticState state, MaterialParams m) {
  if (m.model.x == MODEL_WATER) return waterEnergyDensity(m.fluid.x, m.fluid.y, logAccurate(state.plasticJ));
  if (m.model.x == MODEL_NEO_HOOKEAN) {
    float traceFtF = dot(F[0], F[0]) + dot(F[1], F[1]) + dot(F[2], F[2]);
    return neoHookeanEnergyDensity(m.elastic.x, m.elastic.y, traceFtF, logAccurate(determinant(F)));
  }
  mat3 U, V;
  vec3 sigma;
  svd3(F, U, sigma, V);
  if (m.model.x == MODEL_DRUCKER_PRAGER) {
    vec3 logSigma = logAccurate(max(sigma, vec3(1e-4)));
    return henckyEnergyDensity(m.elastic.x, m.elastic.y, logSigma.x, logSigma.y, logSigma.z);
  }
  vec2 lame = m.model.x == MODEL_SNOW ? hardenedLameParameters(m, state.plasticJ) : m.elastic.xy;
  return fixedCorotatedEnergyDensity(lame.x, lame.y, sigma.x, sigma.y, sigma.z);
}

// The update of the particle's material; `F` is ignored by water.
MaterialUpdate updateMaterial(mat3 F, ParticlePlasticState state, mat3 velocityGradient, float dtS, MaterialParams m) {
  switch (m.model.x) {
#ifdef FIRN_MATERIAL_SNOW
    case MODEL_SNOW: return updateSnow(F, state.plasticJ, velocityGradient, dtS, m);
#endif
#ifdef FIRN_MATERIAL_FIXED_COROTATED
    case MODEL_FIXED_COROTATED: return updateFixedCorotated(F, velocityGradient, dtS, m);
#endif
#ifdef FIRN_MATERIAL_NEO_HOOKEAN
    case MODEL_NEO_HOOKEAN: return updateNeoHookean(F, velocityGradient, dtS, m);
#endif
#ifdef FIRN_MATERIAL_WATER
    case MODEL_WATER: return updateWater(state.plasticJ, velocityGradient, dtS, m);
#endif
#ifdef FIRN_MATERIAL_DRUCKER_PRAGER
    case MODEL_DRUCKER_PRAGER:
      return updateDruckerPrager(F, state.plasticJ, state.volumeCorrection, velocityGradient, dtS, m);
#endif
  }
  // Unreachable: the host compiles in every model its materials use.
  MaterialUpdate unchanged;
  unchanged.deformation = F;
  unchanged.state = state.plasticJ;
  unchanged.volumeCorrection = state.volumeCorrection;
  unchanged.kirchhoffStress = mat3(0.0);
  unchanged.hardeningEnergyDensity = 0.0;
  return unchanged;
}
