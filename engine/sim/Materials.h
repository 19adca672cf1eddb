#pragma once
// Material parameter conversions, one tested function each.

namespace firn {

struct SnowMaterial;

struct LameParameters {
  double muPa;      // shear modulus μ
  double lambdaPa;  // Lamé's first parameter λ
};

// μ = E / (2(1 + ν)), λ = E ν / ((1 + ν)(1 − 2ν)) (Stomakhin 2013 §7; seed 001 §4.2).
LameParameters lameParameters(double youngsModulusPa, double poissonRatio);

// Speed of the fastest elastic (pressure) wave, sqrt((λ + 2μ) / ρ), at the stiffest state the snow can reach:
// hardening grows the moduli by e^{ξ θc} at the compression limit J_P = 1 − θc.
double snowWaveSpeedMPerS(const SnowMaterial& material);

// The explicit step's elastic stability bound Δt < h / c (CFL on the elastic wave).
double elasticStableDtS(const SnowMaterial& material, double cellSizeM);

}  // namespace firn
