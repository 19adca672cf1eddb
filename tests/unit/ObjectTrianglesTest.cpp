// The renderer's triangles for the scene's objects (render/Geometry.h, objectTriangles): normals smoothed across the
// facets of a tessellated sphere, kept sharp at a box's edges, and facing the side the winding makes the front.
#include <cmath>
#include <utility>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "render/Geometry.h"
#include "scene/Scene.h"
#include "scene/SceneObjects.h"

namespace firn {
namespace {

// Float normals of unit vectors computed in double: a few units of 2⁻²⁴.
constexpr double kFloatTolerance = 1e-6;

Scene sceneWith(const RigidBody& body) {
  Scene scene;
  scene.rigidBodies.push_back(body);
  return scene;
}

SceneObject onlyObject(const Scene& scene) { return sceneObjects(scene).front(); }

TEST(ObjectTriangles, BoxEdgesStaySharp) {
  RigidBody box;
  box.shape = RigidShape::Box;
  box.halfExtentsM = {0.1, 0.2, 0.3};
  const SceneObject object = onlyObject(sceneWith(box));
  const std::vector<render::SurfaceVertex> vertices = render::objectTriangles(object);
  ASSERT_EQ(vertices.size(), 3 * object.meshM.triangles.size());
  for (std::size_t first = 0; first < vertices.size(); first += 3) {
    const glm::dvec3 a(vertices[first].positionM), b(vertices[first + 1].positionM), c(vertices[first + 2].positionM);
    const glm::dvec3 faceNormal = glm::normalize(glm::cross(b - a, c - a));
    // A box's faces meet at 90°, beyond the crease angle: each corner takes its own face's normal, which points out.
    EXPECT_GT(glm::dot(faceNormal, (a + b + c) / 3.0), 0.0);
    for (int corner = 0; corner < 3; ++corner) {
      EXPECT_NEAR(glm::distance(glm::dvec3(vertices[first + corner].normal), faceNormal), 0.0, kFloatTolerance);
    }
  }
}

// SceneObjects' sphere has 48 segments round and 24 rings: neighbouring facets turn by 7.5°, within the crease angle,
// so every corner's normal is the mean over the facets round its point, poles included (their 48 copies welded): the
// radial direction there to within the area weights' asymmetry, which is largest on the first ring round a pole,
// between the pole's small triangles and the ring's quads (measured 1.27°). A facet's own normal is up to 5.3° off
// the radial direction at its corners (half its 7.5° × 7.5° diagonal).
TEST(ObjectTriangles, SphereShadesRound) {
  RigidBody ball;
  ball.shape = RigidShape::Sphere;
  ball.radiusM = 0.25;
  const Scene scene = sceneWith(ball);
  for (const bool inward : {false, true}) {
    SceneObject object = onlyObject(scene);
    if (inward) {
      for (glm::uvec3& triangle : object.meshM.triangles) std::swap(triangle.y, triangle.z);
    }
    double largestAngleRad = 0;
    for (const render::SurfaceVertex& vertex : render::objectTriangles(object)) {
      const glm::dvec3 radial = glm::normalize(glm::dvec3(vertex.positionM));
      // Wound inward, the front faces inward, and so do the normals.
      const double cosine = glm::dot(glm::dvec3(vertex.normal), inward ? -radial : radial);
      largestAngleRad = std::max(largestAngleRad, std::acos(std::min(cosine, 1.0)));
    }
    EXPECT_LT(largestAngleRad, 2.0 * 3.14159265358979 / 180) << (inward ? "wound inward" : "wound outward");
  }
}

}  // namespace
}  // namespace firn
