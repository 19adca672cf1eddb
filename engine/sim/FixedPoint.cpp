#include "sim/FixedPoint.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "Error.h"
#include "gpu/Materials.h"
#include "scene/Scene.h"

namespace firn {

double maxParticlesPerCell(const Scene& scene) {
  double densest = 0;
  for (const Body& body : scene.bodies) densest = std::max(densest, body.particlesPerCell);
  return densest;
}

FixedPointScale fixedPointScaleFor(const Scene& scene, const std::vector<ParticleSeed>& particles) {
  double referenceMassKg = 0;
  for (const ParticleSeed& particle : particles) referenceMassKg = std::max(referenceMassKg, double(particle.massKg));
  FixedPointScale scale =
      deriveFixedPointScale(referenceMassKg, maxParticlesPerCell(scene), scene.grid.cellSizeM, scene.time.dtS);
  scale.solverFractionBits =
      deriveSolverFractionBits(scale, stiffestBody(scene).waveSpeedMPerS, scene.grid.cellSizeM, scene.time.dtS);
  return scale;
}

int deriveSolverFractionBits(const FixedPointScale& scale, double waveSpeedMPerS, double cellSizeM, double dtS) {
  constexpr double kHardeningMargin = 256;
  constexpr int kMaximumFractionBits = 50;
  const double courantNumber = waveSpeedMPerS * dtS / cellSizeM;
  const double bound = scale.maxNodeValue() * std::max(1.0, courantNumber * courantNumber) * kHardeningMargin;
  return std::min(62 - static_cast<int>(std::ceil(std::log2(bound))), kMaximumFractionBits);
}

double FixedPointScale::unitsPerValue() const { return std::ldexp(1.0, fractionBits); }
double FixedPointScale::maxNodeValue() const { return std::ldexp(1.0, 31 - fractionBits); }
double FixedPointScale::resolution() const { return std::ldexp(1.0, -fractionBits); }

FixedPointScale deriveFixedPointScale(double referenceMassKg, double maxParticlesPerCell, double cellSizeM, double dtS) {
  constexpr int kMinimumFractionBits = 8;
  constexpr int kMaximumFractionBits = 30;
  const double bound = maxParticlesPerCell * kFixedPointCompressionMargin * kFixedPointVelocityMarginCellsPerStep;
  const int integerBits = static_cast<int>(std::ceil(std::log2(std::max(bound, 1.0))));
  const int fractionBits = std::min(31 - integerBits, kMaximumFractionBits);
  if (fractionBits < kMinimumFractionBits) {
    throw InputError("particles_per_cell: " + std::to_string(maxParticlesPerCell) +
                     " particles per cell leave fewer than 8 bits of fixed-point resolution; use fewer particles "
                     "per cell or solver.atomics \"float\"");
  }
  FixedPointScale scale;
  scale.referenceMassKg = referenceMassKg;
  scale.momentumUnitKgMPerS = referenceMassKg * cellSizeM / dtS;
  scale.fractionBits = fractionBits;
  return scale;
}

}  // namespace firn
