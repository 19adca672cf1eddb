// The scene file's "rigid_bodies": spheres, boxes and meshes that the snow pushes and that push the snow
// (docs/scene-format.md), with their mass, centre of mass and inertia derived from the shape and a mass or a
// density, each checked to lie inside the simulation interior and clear of the others.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/vector_relational.hpp>

#include "io/Text.h"
#include "scene/SceneObjects.h"
#include "scene/SceneSections.h"

namespace firn::scenefile {

using json::Interval;
using json::Object;
using json::Value;
using json::describePoint;

namespace {

// The box around the body at t = 0.
voxelizer::Bounds boundingBox(const RigidBody& body) {
  switch (body.shape) {
    case RigidShape::Sphere: return {body.centerM - body.radiusM, body.centerM + body.radiusM};
    case RigidShape::Box: {
      // A turned box's corners reach |R| h from its centre on each world axis.
      const glm::dmat3 rotation = voxelizer::rotationMatrix(body.rotateDeg);
      glm::dvec3 reachM(0.0);
      for (int axis = 0; axis < 3; ++axis) reachM += glm::abs(rotation[axis]) * body.halfExtentsM[axis];
      return {body.centerM - reachM, body.centerM + reachM};
    }
    case RigidShape::Mesh: return voxelizer::bounds(*body.mesh);
  }
  return {body.centerM, body.centerM};
}

// The shape's mass properties (SceneObjects.h); a mesh that encloses no definite volume, or whose faces disagree on
// which way is out, fails at "path".
voxelizer::MassProperties readShapeMassProperties(const Object& object, const RigidBody& body) {
  try {
    return shapeMassProperties(body);
  } catch (const voxelizer::MeshError& error) {
    object.fail("path", body.resolvedPath.string() + ": " + error.what() +
                            " (a rigid body needs a closed, consistently oriented mesh)");
  }
}

// Exactly one of "mass" and "density" gives the mass; the other follows from the volume. The mass and the inertia's
// moments are 32-bit floats on the GPU, so each must be a normal float.
void readMass(const Object& object, RigidBody& body, const voxelizer::MassProperties& shape) {
  if (object.has("mass") == object.has("density")) {
    object.fail(object.has("mass") ? "density" : "mass",
                object.has("mass") ? "a rigid body takes \"mass\" or \"density\", not both (remove one)"
                                   : "required key is missing: a rigid body needs \"mass\" (kg) or \"density\" (kg/m³)");
  }
  const std::string key = object.has("mass") ? "mass" : "density";
  const double densityKgPerM3 = object.has("mass") ? object.number("mass", Interval::greaterThan(0)) / shape.volumeM3
                                                   : object.number("density", Interval::greaterThan(0));
  setUniformDensity(body, shape, densityKgPerM3);
  const auto isNormalFloat = [](double value) {
    return value >= double(std::numeric_limits<float>::min()) && value <= double(std::numeric_limits<float>::max());
  };
  const double leastMomentKgM2 = std::min({body.inertiaKgM2[0][0], body.inertiaKgM2[1][1], body.inertiaKgM2[2][2]});
  const double mostMomentKgM2 = std::max({body.inertiaKgM2[0][0], body.inertiaKgM2[1][1], body.inertiaKgM2[2][2]});
  if (!isNormalFloat(body.massKg) || !isNormalFloat(leastMomentKgM2) || !isNormalFloat(mostMomentKgM2)) {
    object.fail(key, "gives a mass of " + formatApproximately(body.massKg) + " kg and moments of inertia " +
                         formatApproximately(leastMomentKgM2) + " to " + formatApproximately(mostMomentKgM2) +
                         " kg m², outside what the GPU's 32-bit floats hold (volume " +
                         formatApproximately(body.volumeM3) + " m³)");
  }
}

RigidBody readRigidBody(const Object& object, const GridSpec& grid, const std::filesystem::path& sceneFolder) {
  RigidBody body;
  body.shape = object.required("shape").choice<RigidShape>(
      {{"sphere", RigidShape::Sphere}, {"box", RigidShape::Box}, {"mesh", RigidShape::Mesh}});
  const auto keysWith = [](std::vector<std::string> keys) {
    for (const char* common : {"shape", "mass", "density", "velocity", "angular_velocity", "friction", "boundary"}) {
      keys.push_back(common);
    }
    return keys;
  };
  switch (body.shape) {
    case RigidShape::Sphere:
      object.checkKeys(keysWith({"center", "radius"}), "a sphere rigid body");
      body.centerM = object.vec3("center");
      body.radiusM = object.number("radius", Interval::greaterThan(0));
      break;
    case RigidShape::Box: {
      object.checkKeys(keysWith({"center", "size", "rotate_deg"}), "a box rigid body");
      body.centerM = object.vec3("center");
      const glm::dvec3 sizeM = object.vec3("size");
      if (!glm::all(glm::greaterThan(sizeM, glm::dvec3(0.0)))) {
        object.fail("size", "every edge must be longer than 0 (got " + describePoint(sizeM) + ")");
      }
      body.halfExtentsM = 0.5 * sizeM;
      body.rotateDeg = object.vec3("rotate_deg", body.rotateDeg);
      break;
    }
    case RigidShape::Mesh: {
      object.checkKeys(keysWith({"path", "scale", "rotate_deg", "translate", "resolution"}), "a mesh rigid body");
      body.fieldResolution = object.number("resolution", body.fieldResolution, fieldResolutionAllowed());
      PlacedMesh placed = readPlacedMesh(object, sceneFolder, grid.cellSizeM / body.fieldResolution);
      body.path = std::move(placed.path);
      body.resolvedPath = std::move(placed.resolvedPath);
      body.mesh = std::move(placed.mesh);
      break;
    }
  }
  readMass(object, body, readShapeMassProperties(object, body));
  body.velocityMPerS = object.vec3("velocity", body.velocityMPerS);
  body.angularVelocityRadPerS = object.vec3("angular_velocity", body.angularVelocityRadPerS);
  body.friction = object.number("friction", body.friction, Interval::atLeast(0));
  body.boundary = object.choice<Boundary>(
      "boundary", body.boundary, {{"sticky", Boundary::Sticky}, {"slip", Boundary::Slip}, {"separate", Boundary::Separate}});

  const voxelizer::Bounds box = boundingBox(body);
  checkInsideInterior(object, "rigid body", box.minM, box.maxM, grid);
  return body;
}

// Whether two bodies share space at t = 0: two spheres exactly, any other pair by its bounding boxes.
bool overlapAtStart(const RigidBody& a, const RigidBody& b) {
  if (a.shape == RigidShape::Sphere && b.shape == RigidShape::Sphere) {
    return glm::length(a.centerM - b.centerM) < a.radiusM + b.radiusM;
  }
  const voxelizer::Bounds boxA = boundingBox(a), boxB = boundingBox(b);
  return glm::all(glm::lessThan(boxA.minM, boxB.maxM)) && glm::all(glm::lessThan(boxB.minM, boxA.maxM));
}

}  // namespace

std::vector<RigidBody> readRigidBodies(const Value& rigidBodies, const GridSpec& grid,
                                       const std::filesystem::path& sceneFolder) {
  if (!rigidBodies.json().is_array()) {
    rigidBodies.fail("expected an array of rigid bodies (got " + json::describeValue(rigidBodies.json()) + ")");
  }
  std::vector<RigidBody> bodies;
  for (std::size_t i = 0; i < rigidBodies.json().size(); ++i) {
    const Value element = rigidBodies.element(i);
    const RigidBody& body = bodies.emplace_back(readRigidBody(Object(element), grid, sceneFolder));
    for (std::size_t other = 0; other < i; ++other) {
      if (!overlapAtStart(bodies[other], body)) continue;
      const bool spheres = body.shape == RigidShape::Sphere && bodies[other].shape == RigidShape::Sphere;
      const voxelizer::Bounds box = boundingBox(body), otherBox = boundingBox(bodies[other]);
      element.fail("overlaps rigid_bodies[" + std::to_string(other) + "] at the start (" +
                   (spheres ? "the two spheres intersect"
                            : "their bounding boxes, " + describeBox(box.minM, box.maxM) + " and " +
                                  describeBox(otherBox.minM, otherBox.maxM) + ", overlap") +
                   "): bodies meet each other at their surfaces, and two that start sharing space would be thrown "
                   "apart; move them apart (touching is fine)");
    }
  }
  return bodies;
}

}  // namespace firn::scenefile
