#include "gpu/Materials.h"

#include <cmath>

#include "gpu/GpuFunctions.h"
#include "scene/Scene.h"

namespace firn {

LameParameters lameParameters(double youngsModulusPa, double poissonRatio) {
  return {youngsModulusPa / (2.0 * (1.0 + poissonRatio)),
          youngsModulusPa * poissonRatio / ((1.0 + poissonRatio) * (1.0 - 2.0 * poissonRatio))};
}

double waveSpeedMPerS(const Material& material, double lambdaScale, double muScale) {
  // Snow at the compression limit J_P = 1 − θc.
  return hardenedWaveSpeedMPerS(material, 1.0 - material.criticalCompression, lambdaScale, muScale);
}

double hardenedWaveSpeedMPerS(const Material& material, double plasticJ, double lambdaScale, double muScale) {
  if (material.model == MaterialModel::Water) {
    return gpu::waterWaveSpeed(material.bulkModulusPa, material.gamma, material.densityKgPerM3);
  }
  const LameParameters lame = lameParameters(material.youngsModulusPa, material.poissonRatio);
  const double hardening = material.model == MaterialModel::Snow ? gpu::snowHardening(material.hardening, plasticJ) : 1.0;
  return gpu::pressureWaveSpeed(lambdaScale * lame.lambdaPa, muScale * lame.muPa, hardening, material.densityKgPerM3);
}

double elasticStableDtS(const Material& material, double cellSizeM, double lambdaScale, double muScale) {
  return cellSizeM / waveSpeedMPerS(material, lambdaScale, muScale);
}

StiffestBody stiffestBody(const Scene& scene) {
  StiffestBody stiffest;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const Body& body = scene.bodies[i];
    const double speedMPerS =
        waveSpeedMPerS(scene.materials.at(std::size_t(body.materialIndex)), body.lambdaScale, body.muScale);
    if (speedMPerS > stiffest.waveSpeedMPerS) stiffest = {static_cast<int>(i), speedMPerS};
  }
  return stiffest;
}

namespace {

int modelCode(MaterialModel model) {
  switch (model) {
    case MaterialModel::Snow: return gpu::MODEL_SNOW;
    case MaterialModel::FixedCorotated: return gpu::MODEL_FIXED_COROTATED;
    case MaterialModel::NeoHookean: return gpu::MODEL_NEO_HOOKEAN;
    case MaterialModel::Water: return gpu::MODEL_WATER;
    case MaterialModel::DruckerPrager: return gpu::MODEL_DRUCKER_PRAGER;
  }
  return gpu::MODEL_SNOW;
}

gpu::MaterialParams gpuMaterial(const Material& material, double lambdaScale, double muScale) {
  gpu::MaterialParams params{};
  params.model.x = modelCode(material.model);
  const double radiansPerDegree = 3.14159265358979323846 / 180;
  switch (material.model) {
    case MaterialModel::Water:
      params.elastic.w = float(material.densityKgPerM3);
      params.fluid = glm::vec4(float(material.bulkModulusPa), float(material.gamma), float(material.viscosityPaS), 0);
      return params;
    case MaterialModel::DruckerPrager:
      params.plastic = glm::vec4(float(material.hardeningH0Deg * radiansPerDegree),
                                 float(material.hardeningH1Deg * radiansPerDegree), float(material.hardeningH2),
                                 float(material.hardeningH3Deg * radiansPerDegree));
      break;
    case MaterialModel::Snow:
      params.plastic = glm::vec4(float(1.0 - material.criticalCompression), float(1.0 + material.criticalStretch), 0, 0);
      params.elastic.z = float(material.hardening);
      break;
    case MaterialModel::FixedCorotated:
    case MaterialModel::NeoHookean: break;
  }
  const LameParameters lame = lameParameters(material.youngsModulusPa, material.poissonRatio);
  params.elastic.x = float(muScale * lame.muPa);
  params.elastic.y = float(lambdaScale * lame.lambdaPa);
  params.elastic.w = float(material.densityKgPerM3);
  return params;
}

}  // namespace

MaterialTable buildMaterialTable(const Scene& scene) {
  MaterialTable table;
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    table.entries.push_back(gpuMaterial(scene.materials[i], 1, 1));
    table.entryMaterial.push_back(i);
  }
  for (const Body& body : scene.bodies) {
    if (body.lambdaScale == 1 && body.muScale == 1) {
      table.bodyEntry.push_back(static_cast<std::uint32_t>(body.materialIndex));
      continue;
    }
    table.bodyEntry.push_back(static_cast<std::uint32_t>(table.entries.size()));
    table.entries.push_back(
        gpuMaterial(scene.materials.at(std::size_t(body.materialIndex)), body.lambdaScale, body.muScale));
    table.entryMaterial.push_back(std::size_t(body.materialIndex));
  }
  return table;
}

}  // namespace firn
