#include "sim/Materials.h"

#include <cmath>

#include "scene/Scene.h"

namespace firn {

LameParameters lameParameters(double youngsModulusPa, double poissonRatio) {
  return {youngsModulusPa / (2.0 * (1.0 + poissonRatio)),
          youngsModulusPa * poissonRatio / ((1.0 + poissonRatio) * (1.0 - 2.0 * poissonRatio))};
}

double snowWaveSpeedMPerS(const SnowMaterial& material) {
  const LameParameters lame = lameParameters(material.youngsModulusPa, material.poissonRatio);
  const double hardening = std::exp(material.hardening * material.criticalCompression);
  return std::sqrt((lame.lambdaPa + 2.0 * lame.muPa) * hardening / material.densityKgPerM3);
}

double elasticStableDtS(const SnowMaterial& material, double cellSizeM) {
  return cellSizeM / snowWaveSpeedMPerS(material);
}

}  // namespace firn
