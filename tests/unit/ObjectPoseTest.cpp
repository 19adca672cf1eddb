// Placing an object's mesh by its pose (engine/scene/SceneObjects.h): world = positionM + orientation · p, the
// triangles kept, and poses that are not finite recognised, which stop a run (docs/command-line.md, bodies.csv).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>

#include "scene/SceneObjects.h"
#include "voxelizer/Mesh.h"

namespace {

// A quarter turn about y takes +x to −z and +z to +x; then the position is added. Exact but for the rounding of
// cos and sin of π/4 in the quaternion (a few 1e-16).
constexpr double kRounding = 1e-15;

TEST(ObjectPose, PosedMeshTurnsThenMovesEachVertexAndKeepsTheTriangles) {
  firn::ObjectPose pose;
  pose.positionM = {1, 2, 3};
  pose.orientation = glm::angleAxis(glm::half_pi<double>(), glm::dvec3(0, 1, 0));
  firn::voxelizer::TriangleMesh rest;
  rest.vertices = {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}};
  rest.triangles = {{0, 1, 2}};
  const firn::voxelizer::TriangleMesh placed = firn::posedMesh(rest, pose);
  ASSERT_EQ(placed.vertices.size(), 3u);
  const glm::dvec3 expected[] = {{1, 2, 2}, {2, 2, 3}, {1, 3, 3}};
  for (std::size_t v = 0; v < 3; ++v) {
    for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(placed.vertices[v][axis], expected[v][axis], kRounding) << v;
    EXPECT_EQ(placed.vertices[v], firn::worldPoint(pose, rest.vertices[v]));
  }
  EXPECT_EQ(placed.triangles, rest.triangles);
}

TEST(ObjectPose, AnyNumberThatIsNotFiniteMakesThePoseNotFinite) {
  EXPECT_TRUE(firn::isFinite(firn::ObjectPose{}));
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  firn::ObjectPose pose;
  pose.positionM.y = nan;
  EXPECT_FALSE(firn::isFinite(pose));
  pose = {};
  pose.orientation.w = nan;
  EXPECT_FALSE(firn::isFinite(pose));
  pose = {};
  pose.orientation.z = inf;
  EXPECT_FALSE(firn::isFinite(pose));
  pose = {};
  pose.velocityMPerS.x = -inf;
  EXPECT_FALSE(firn::isFinite(pose));
  pose = {};
  pose.angularVelocityRadPerS.z = nan;
  EXPECT_FALSE(firn::isFinite(pose));
}

}  // namespace
