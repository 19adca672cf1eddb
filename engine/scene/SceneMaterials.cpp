// The scene file's "materials": the keys of each material model, and snow's presets (docs/scene-format.md).
#include <string>
#include <vector>

#include "scene/SceneSections.h"

namespace firn::scenefile {

using json::Interval;
using json::Object;
using json::Value;
using json::describeValue;
using json::joinNames;

namespace {

const Material* findPreset(const std::string& name) {
  for (const Material& preset : snowPresets()) {
    if (preset.name == name) return &preset;
  }
  return nullptr;
}

// Snow: a preset supplies every number and explicit keys override it; without one, all are required.
void readSnow(const Object& material, Material& result) {
  material.checkKeys({"model", "preset", "youngs_modulus", "poisson_ratio", "density", "critical_compression",
                      "critical_stretch", "hardening"}, "a snow material");
  const bool hasPreset = material.has("preset");
  if (hasPreset) {
    const Value presetName = material.required("preset");
    const Material* preset = findPreset(presetName.string());
    if (preset == nullptr) {
      std::vector<std::string> names;
      for (const Material& known : snowPresets()) names.push_back(known.name);
      presetName.fail("unknown preset " + describeValue(presetName.json()) + " (presets: " + joinNames(names) + ")");
    }
    result = *preset;
  }
  const auto read = [&](const char* key, double& field, const Interval& allowed) {
    if (material.has(key)) {
      field = material.number(key, allowed);
    } else if (!hasPreset) {
      material.fail(key, "required key is missing (give it, or a \"preset\" that supplies it)");
    }
  };
  read("youngs_modulus", result.youngsModulusPa, Interval::greaterThan(0));
  // ν = 0.5 is incompressible: λ = Eν / ((1 + ν)(1 − 2ν)) diverges.
  read("poisson_ratio", result.poissonRatio, Interval::closedOpen(0, 0.5));
  read("density", result.densityKgPerM3, Interval::greaterThan(0));
  // θc = 1 would let a singular value be clamped to 0, a collapsed particle.
  read("critical_compression", result.criticalCompression, Interval::closedOpen(0, 1));
  read("critical_stretch", result.criticalStretch, Interval::atLeast(0));
  read("hardening", result.hardening, Interval::atLeast(0));
}

void readElasticConstants(const Object& material, Material& result) {
  result.youngsModulusPa = material.number("youngs_modulus", Interval::greaterThan(0));
  result.poissonRatio = material.number("poisson_ratio", Interval::closedOpen(0, 0.5));
  result.densityKgPerM3 = material.number("density", Interval::greaterThan(0));
}

// Sand: a constant friction angle, or Klár 2016's hardening [h0, h1, h2, h3] (degrees, degrees, 1, degrees)
// with h0 > h3 ≥ 0 and h1, h2 ≥ 0 (Blažević 2022 §4.4.2); φ must stay below 90°, where the cone is a plane.
void readDruckerPrager(const Object& material, Material& result) {
  material.checkKeys({"model", "youngs_modulus", "poisson_ratio", "density", "friction_angle_deg", "hardening"}, "a drucker_prager material");
  readElasticConstants(material, result);
  if (const auto hardening = material.optional("hardening")) {
    if (material.has("friction_angle_deg")) {
      material.fail("friction_angle_deg", "give either friction_angle_deg (a constant angle) or hardening "
                                          "[h0, h1, h2, h3] (an angle h0 + (h1 q − h3) e^{−h2 q} that grows with q), not both");
    }
    if (!hardening->json().is_array() || hardening->json().size() != 4) {
      hardening->fail("expected [h0, h1, h2, h3] (got " + describeValue(hardening->json()) + ")");
    }
    result.hardeningH0Deg = hardening->element(0).number(Interval::closedOpen(0, 90));
    result.hardeningH1Deg = hardening->element(1).number(Interval::atLeast(0));
    result.hardeningH2 = hardening->element(2).number(Interval::atLeast(0));
    result.hardeningH3Deg = hardening->element(3).number(Interval::closedOpen(0, result.hardeningH0Deg));
  } else {
    result.hardeningH0Deg = material.number("friction_angle_deg", Interval::closedOpen(0, 90));
    result.hardeningH1Deg = result.hardeningH2 = result.hardeningH3Deg = 0;
  }
}

Material readMaterial(const Object& material, const std::string& name) {
  Material result;
  // With a preset (snow) the model is implied; without one it must be said, since the keys depend on it.
  if (!material.has("preset") || material.has("model")) {
    result.model = material.required("model").choice<MaterialModel>({{"snow", MaterialModel::Snow},
                                                                      {"fixed_corotated", MaterialModel::FixedCorotated},
                                                                      {"neo_hookean", MaterialModel::NeoHookean},
                                                                      {"water", MaterialModel::Water},
                                                                      {"drucker_prager", MaterialModel::DruckerPrager}});
  }
  switch (result.model) {
    case MaterialModel::Snow: readSnow(material, result); break;
    case MaterialModel::FixedCorotated:
    case MaterialModel::NeoHookean:
      material.checkKeys({"model", "youngs_modulus", "poisson_ratio", "density"},
                         result.model == MaterialModel::NeoHookean ? "a neo_hookean material" : "a fixed_corotated material");
      readElasticConstants(material, result);
      break;
    case MaterialModel::Water:
      material.checkKeys({"model", "density", "bulk_modulus", "gamma", "viscosity"}, "a water material");
      result.densityKgPerM3 = material.number("density", Interval::greaterThan(0));
      result.bulkModulusPa = material.number("bulk_modulus", Interval::greaterThan(0));
      // γ ≥ 1: the pressure must stiffen as water compresses (Blažević 2022 uses γ = 4 to 7).
      result.gamma = material.number("gamma", Interval::atLeast(1));
      result.viscosityPaS = material.number("viscosity", result.viscosityPaS, Interval::atLeast(0));
      break;
    case MaterialModel::DruckerPrager: readDruckerPrager(material, result); break;
  }
  result.name = name;
  return result;
}

}  // namespace

std::vector<Material> readMaterials(const Object& materials) {
  std::vector<Material> result;
  for (const auto& member : materials.value().json().items()) {
    if (member.key().empty()) materials.value().fail("a material name must not be empty");
    result.push_back(readMaterial(Object(materials.value().member(member.key())), member.key()));
  }
  if (result.empty()) materials.value().fail("at least one material is required");
  return result;
}

}  // namespace firn::scenefile
