// The scene file's "colliders": planes, spheres and boxes the snow meets (docs/scene-format.md).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "scene/SceneSections.h"

namespace firn::scenefile {

using json::Interval;
using json::Object;

Collider readCollider(const Object& collider) {
  Collider result;
  result.shape = collider.required("type").choice<ColliderShape>(
      {{"plane", ColliderShape::Plane}, {"sphere", ColliderShape::Sphere}, {"box", ColliderShape::Box}}, {"mesh"});
  const std::vector<std::string> commonKeys = {"velocity", "friction", "boundary"};
  const auto keysWith = [&](std::vector<std::string> keys) {
    keys.insert(keys.end(), commonKeys.begin(), commonKeys.end());
    return keys;
  };
  switch (result.shape) {
    case ColliderShape::Plane: {
      collider.checkKeys(keysWith({"type", "point", "normal"}), {}, "a plane collider");
      result.pointM = collider.vec3("point");
      const glm::dvec3 normal = collider.vec3("normal");
      const double largestComponent = std::max({std::abs(normal.x), std::abs(normal.y), std::abs(normal.z)});
      if (largestComponent == 0) collider.fail("normal", "must not be the zero vector");
      // Scaled down first so that the length of a vector like [1e200, 0, 1e200] cannot overflow.
      result.normal = glm::normalize(normal / largestComponent);
      break;
    }
    case ColliderShape::Sphere:
      collider.checkKeys(keysWith({"type", "center", "radius"}), {}, "a sphere collider");
      result.centerM = collider.vec3("center");
      result.radiusM = collider.number("radius", Interval::greaterThan(0));
      break;
    case ColliderShape::Box:
      collider.checkKeys(keysWith({"type", "min", "max"}), {}, "a box collider");
      result.minM = collider.vec3("min");
      result.maxM = collider.vec3("max");
      checkBoxCorners(collider, result.minM, result.maxM);
      break;
  }
  result.velocityMPerS = collider.vec3("velocity", result.velocityMPerS);
  result.friction = collider.number("friction", result.friction, Interval::atLeast(0));
  result.boundary = collider.choice<Boundary>(
      "boundary", result.boundary,
      {{"sticky", Boundary::Sticky}, {"slip", Boundary::Slip}, {"separate", Boundary::Separate}});
  return result;
}

}  // namespace firn::scenefile
