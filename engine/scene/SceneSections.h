#pragma once
// The readers of the scene file's larger sections (docs/scene-format.md), each in a file of its own:
// SceneMaterials.cpp, SceneBodies.cpp, SceneColliders.cpp and SceneSurface.cpp. SceneLoader.cpp reads the top
// level and the small sections (grid, time, solver, camera) and calls these. Internal to engine/scene.
#include <filesystem>
#include <vector>

#include <glm/vector_relational.hpp>

#include "scene/JsonChecker.h"
#include "scene/Scene.h"

namespace firn::scenefile {

// "materials": an object of named materials, in the file's order.
std::vector<Material> readMaterials(const json::Object& materials);

// One element of "bodies"; mesh and points files are read here, relative to `sceneFolder`.
Body readBody(const json::Object& body, const GridSpec& grid, const std::vector<Material>& materials,
              const std::filesystem::path& sceneFolder);

// One element of "colliders".
Collider readCollider(const json::Object& collider);

// "surface": the reconstruction of the snow's surface (SceneSurface.cpp).
SurfaceSpec readSurface(const json::Object& surface);

// Box bodies and box colliders alike.
inline void checkBoxCorners(const json::Object& box, const glm::dvec3& minM, const glm::dvec3& maxM) {
  if (!glm::all(glm::lessThan(minM, maxM))) {
    box.fail("max", "must exceed \"min\" on every axis (min " + json::describePoint(minM) + ", max " +
                        json::describePoint(maxM) + ")");
  }
}

}  // namespace firn::scenefile
