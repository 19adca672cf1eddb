// The snow presets a scene may name, the models' names, and the built-in scene `firn run` uses with no SCENE.
#include "scene/Scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>

namespace firn {

const std::vector<Material>& snowPresets() {
  // Fields: name, E (Pa), ν, ρ (kg/m³), θc, θs, ξ. Sources:
  // - stomakhin: Stomakhin et al. 2013, table 2, the reference snow.
  // - dry: powder; Stomakhin's lower critical compression and stretch, so it crumbles rather than deforms.
  // - wet: chunky; larger θc and θs per Blažević 2022 and Snow thesis 2015, so it deforms plastically before it
  //   breaks.
  // - icy: Snow thesis 2015's snowball parameters (E = 5e6, ν = 0.3, ξ = 30, θs = 2e-3), high E and hardening.
  // - slushy: Stomakhin's lower E and lower hardening, so it flows.
  static const std::vector<Material> presets = {
      {"stomakhin", 1.4e5, 0.2, 400, 2.5e-2, 7.5e-3, 10},
      {"dry", 1.4e5, 0.2, 300, 1.9e-2, 5.0e-3, 10},
      {"wet", 1.4e5, 0.2, 500, 4.0e-2, 1.5e-2, 10},
      {"icy", 5e6, 0.3, 600, 2.5e-2, 2.0e-3, 30},
      {"slushy", 4.8e4, 0.25, 600, 3.0e-2, 1.0e-2, 5},
  };
  return presets;
}

double GridSpec::positionResolutionM() const {
  const glm::dvec3 farthest = glm::max(glm::abs(originM), glm::abs(originM + glm::dvec3(cells) * cellSizeM));
  const double largest = std::max({farthest.x, farthest.y, farthest.z});
  if (!(largest < double(std::numeric_limits<float>::max()))) return std::numeric_limits<double>::infinity();
  const auto coordinate = float(largest);
  return double(std::nextafter(coordinate, std::numeric_limits<float>::infinity())) - double(coordinate);
}

std::string sceneFileName(const Scene& scene) {
  return scene.sourcePath.empty() ? kBuiltInSceneName : scene.sourcePath.string();
}

const char* modelName(MaterialModel model) {
  switch (model) {
    case MaterialModel::Snow: return "snow";
    case MaterialModel::FixedCorotated: return "fixed_corotated";
    case MaterialModel::NeoHookean: return "neo_hookean";
    case MaterialModel::Water: return "water";
    case MaterialModel::DruckerPrager: return "drucker_prager";
  }
  return "unknown";
}

Scene defaultScene() {
  // The asset file, parsed like any other, so the built-in scene obeys exactly the rules a user's file does.
  Scene scene = parseScene(embeddedSceneFiles().at("snowball_wall.json"), kBuiltInSceneName);
  scene.sourcePath.clear();
  return scene;
}

}  // namespace firn
