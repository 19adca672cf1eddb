#include "sim/Materials.h"

#include <cmath>

#include "scene/Scene.h"

namespace firn {

LameParameters lameParameters(double youngsModulusPa, double poissonRatio) {
  return {youngsModulusPa / (2.0 * (1.0 + poissonRatio)),
          youngsModulusPa * poissonRatio / ((1.0 + poissonRatio) * (1.0 - 2.0 * poissonRatio))};
}

double snowWaveSpeedMPerS(const SnowMaterial& material, double lambdaScale, double muScale) {
  const LameParameters lame = lameParameters(material.youngsModulusPa, material.poissonRatio);
  const double hardening = std::exp(material.hardening * material.criticalCompression);
  return std::sqrt((lambdaScale * lame.lambdaPa + 2.0 * muScale * lame.muPa) * hardening / material.densityKgPerM3);
}

double elasticStableDtS(const SnowMaterial& material, double cellSizeM, double lambdaScale, double muScale) {
  return cellSizeM / snowWaveSpeedMPerS(material, lambdaScale, muScale);
}

namespace {

gpu::MaterialParams gpuMaterial(const SnowMaterial& material, double lambdaScale, double muScale) {
  const LameParameters lame = lameParameters(material.youngsModulusPa, material.poissonRatio);
  return {glm::vec4(float(muScale * lame.muPa), float(lambdaScale * lame.lambdaPa), float(material.hardening),
                    float(material.densityKgPerM3)),
          glm::vec4(float(1.0 - material.criticalCompression), float(1.0 + material.criticalStretch), 0, 0)};
}

}  // namespace

MaterialTable buildMaterialTable(const Scene& scene) {
  MaterialTable table;
  for (const SnowMaterial& material : scene.materials) table.entries.push_back(gpuMaterial(material, 1, 1));
  for (const Body& body : scene.bodies) {
    if (body.lambdaScale == 1 && body.muScale == 1) {
      table.bodyEntry.push_back(static_cast<std::uint32_t>(body.materialIndex));
      continue;
    }
    table.bodyEntry.push_back(static_cast<std::uint32_t>(table.entries.size()));
    table.entries.push_back(
        gpuMaterial(scene.materials.at(std::size_t(body.materialIndex)), body.lambdaScale, body.muScale));
  }
  return table;
}

}  // namespace firn
