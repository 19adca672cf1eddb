#pragma once
// Material parameter conversions, one tested function each.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "gpu/GpuLayout.h"

namespace firn {

struct Scene;
struct Material;

struct LameParameters {
  double muPa;      // shear modulus μ
  double lambdaPa;  // Lamé's first parameter λ
};

// μ = E / (2(1 + ν)), λ = E ν / ((1 + ν)(1 − 2ν)) (Stomakhin 2013 §7; Blažević 2022 eq. 4.4).
LameParameters lameParameters(double youngsModulusPa, double poissonRatio);

// Speed of the fastest elastic (pressure) wave: sqrt((λ + 2μ) / ρ) for solids and sand, at the stiffest state
// snow can reach (hardening grows its moduli by e^{ξ θc} at the compression limit J_P = 1 − θc), and
// sqrt(k γ / ρ) for water (dp/dJ at rest). A body's lambda_scale and mu_scale scale λ and μ.
double waveSpeedMPerS(const Material& material, double lambdaScale = 1, double muScale = 1);

// The same wave in a particle whose snow has compacted to `plasticJ` (hardened by e^{ξ(1 − J_P)}, without limit: J_P
// falls below 1 − θc as compaction goes on); other models do not harden, and give waveSpeedMPerS.
double hardenedWaveSpeedMPerS(const Material& material, double plasticJ, double lambdaScale = 1, double muScale = 1);

// The explicit step's elastic stability bound Δt < h / c (CFL on the elastic wave).
double elasticStableDtS(const Material& material, double cellSizeM, double lambdaScale = 1, double muScale = 1);

// The body whose material, as that body uses it (its Lamé scales included), carries the fastest elastic wave:
// the scene's elastic stability bound is h / waveSpeedMPerS.
struct StiffestBody {
  int bodyIndex = -1;
  double waveSpeedMPerS = 0;
};
StiffestBody stiffestBody(const Scene& scene);

// The materials as the GPU sees them: the scene's, in order, then one variant for each body whose
// lambda_scale or mu_scale is not 1 (Blažević 2022 §6.2's per-body modifiers), so no shader needs a per-body table.
struct MaterialTable {
  std::vector<gpu::MaterialParams> entries;
  std::vector<std::size_t> entryMaterial;  // the scene material each entry is, or is a variant of
  std::vector<std::uint32_t> bodyEntry;    // the entry each body's particles use
};
MaterialTable buildMaterialTable(const Scene& scene);

}  // namespace firn
