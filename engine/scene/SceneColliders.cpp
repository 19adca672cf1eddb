// The scene file's "colliders": planes, spheres, boxes and meshes the snow meets (docs/scene-format.md).
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "io/Text.h"
#include "scene/ColliderMotion.h"
#include "scene/SceneSections.h"

namespace firn::scenefile {

using json::Interval;
using json::Object;
using json::Value;

namespace {

// Slerp turns the shorter way between two keyframes, so a half turn has no way and one near it a rounding's
// choice: a keyframe turns at most this far from the one before (a wider turn takes a keyframe between).
constexpr double kMostTurnBetweenKeyframesDeg = 179;

std::vector<ColliderKeyframe> readKeyframes(const Value& keyframes) {
  if (!keyframes.json().is_array() || keyframes.json().empty()) {
    keyframes.fail("expected a non-empty array of keyframes (got " + json::describeValue(keyframes.json()) + ")");
  }
  std::vector<ColliderKeyframe> result;
  for (std::size_t i = 0; i < keyframes.json().size(); ++i) {
    const Object keyframe(keyframes.element(i));
    keyframe.checkKeys({"time_s", "translate", "rotate_deg"}, "a collider keyframe");
    ColliderKeyframe& key = result.emplace_back();
    key.timeS = keyframe.number("time_s", Interval::atLeast(0));
    if (i > 0 && !(key.timeS > result[i - 1].timeS)) {
      keyframe.fail("time_s", "must be later than the keyframe before's (" + format("%.6g", result[i - 1].timeS) +
                                  " s)");
    }
    key.translateM = keyframe.vec3("translate", key.translateM);
    key.rotateDeg = keyframe.vec3("rotate_deg", key.rotateDeg);
    if (i > 0) {
      const double turnDeg = glm::degrees(turnBetweenRad(keyframeRotation(result[i - 1]), keyframeRotation(key)));
      if (turnDeg > kMostTurnBetweenKeyframesDeg) {
        keyframe.fail("rotate_deg", "turns " + format("%.6g", turnDeg) + " degrees from the keyframe before; at most " +
                                        format("%.6g", kMostTurnBetweenKeyframesDeg) +
                                        " (the motion turns the shorter way: add a keyframe between)");
      }
    }
  }
  return result;
}

}  // namespace

Collider readCollider(const Object& collider, const GridSpec& grid, const std::filesystem::path& sceneFolder) {
  Collider result;
  result.shape = collider.required("type").choice<ColliderShape>({{"plane", ColliderShape::Plane},
                                                                  {"sphere", ColliderShape::Sphere},
                                                                  {"box", ColliderShape::Box},
                                                                  {"mesh", ColliderShape::Mesh}});
  const std::vector<std::string> commonKeys = {"velocity", "keyframes", "pivot", "friction", "boundary"};
  const auto keysWith = [&](std::vector<std::string> keys) {
    keys.insert(keys.end(), commonKeys.begin(), commonKeys.end());
    return keys;
  };
  switch (result.shape) {
    case ColliderShape::Plane: {
      collider.checkKeys(keysWith({"type", "point", "normal"}), "a plane collider");
      result.pointM = collider.vec3("point");
      const glm::dvec3 normal = collider.vec3("normal");
      const double largestComponent = std::max({std::abs(normal.x), std::abs(normal.y), std::abs(normal.z)});
      if (largestComponent == 0) collider.fail("normal", "must not be the zero vector");
      // Scaled down first so that the length of a vector like [1e200, 0, 1e200] cannot overflow.
      result.normal = glm::normalize(normal / largestComponent);
      result.pivotM = result.pointM;
      break;
    }
    case ColliderShape::Sphere:
      collider.checkKeys(keysWith({"type", "center", "radius"}), "a sphere collider");
      result.centerM = collider.vec3("center");
      result.radiusM = collider.number("radius", Interval::greaterThan(0));
      result.pivotM = result.centerM;
      break;
    case ColliderShape::Box:
      collider.checkKeys(keysWith({"type", "min", "max"}), "a box collider");
      result.minM = collider.vec3("min");
      result.maxM = collider.vec3("max");
      checkBoxCorners(collider, result.minM, result.maxM);
      result.pivotM = 0.5 * (result.minM + result.maxM);
      break;
    case ColliderShape::Mesh: {
      collider.checkKeys(keysWith({"type", "path", "scale", "rotate_deg", "translate", "resolution"}), "a mesh collider");
      result.fieldResolution = collider.number("resolution", result.fieldResolution, fieldResolutionAllowed());
      PlacedMesh placed = readPlacedMesh(collider, sceneFolder, grid.cellSizeM / result.fieldResolution);
      result.path = std::move(placed.path);
      result.resolvedPath = std::move(placed.resolvedPath);
      const voxelizer::Bounds box = voxelizer::bounds(*placed.mesh);
      result.mesh = std::move(placed.mesh);
      result.pivotM = 0.5 * (box.minM + box.maxM);
      break;
    }
  }
  if (collider.has("velocity") && collider.has("keyframes")) {
    collider.fail("keyframes", "a collider moves either at its velocity or by keyframes, not both (remove "
                               "\"velocity\" or \"keyframes\")");
  }
  result.velocityMPerS = collider.vec3("velocity", result.velocityMPerS);
  if (const auto keyframes = collider.optional("keyframes")) result.keyframes = readKeyframes(*keyframes);
  result.pivotM = collider.vec3("pivot", result.pivotM);
  result.friction = collider.number("friction", result.friction, Interval::atLeast(0));
  result.boundary = collider.choice<Boundary>(
      "boundary", result.boundary,
      {{"sticky", Boundary::Sticky}, {"slip", Boundary::Slip}, {"separate", Boundary::Separate}});
  return result;
}

}  // namespace firn::scenefile
