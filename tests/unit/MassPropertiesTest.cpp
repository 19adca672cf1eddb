// A closed mesh's volume, centroid and inertia (voxelizer/MassProperties.h) against boxes and a sphere whose values
// are known in closed form.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>

#include "voxelizer/MassProperties.h"

namespace firn::voxelizer {
namespace {

constexpr double pi = 3.14159265358979323846;
// Boxes are sums of a dozen exactly placed triangles' terms: their rounding is a few ε of the largest term.
constexpr double kExactRelative = 1e-12;

void expectNear(const glm::dvec3& actual, const glm::dvec3& expected, double tolerance) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(actual[i], expected[i], tolerance) << "component " << i;
}

void expectNear(const glm::dmat3& actual, const glm::dmat3& expected, double tolerance) {
  for (int column = 0; column < 3; ++column) {
    for (int row = 0; row < 3; ++row) {
      EXPECT_NEAR(actual[column][row], expected[column][row], tolerance) << "row " << row << ", column " << column;
    }
  }
}

// A solid box of edges a, b, c about its centre: V/12 diag(b² + c², a² + c², a² + b²) per unit density.
glm::dmat3 boxInertia(const glm::dvec3& edgesM) {
  const glm::dvec3 squared = edgesM * edgesM;
  const double volumeM3 = edgesM.x * edgesM.y * edgesM.z;
  glm::dmat3 inertia(0.0);
  inertia[0][0] = volumeM3 / 12 * (squared.y + squared.z);
  inertia[1][1] = volumeM3 / 12 * (squared.x + squared.z);
  inertia[2][2] = volumeM3 / 12 * (squared.x + squared.y);
  return inertia;
}

TEST(MassProperties, UnitCubeIsExact) {
  const MassProperties cube = massProperties(boxMesh(glm::dvec3(0.0), glm::dvec3(1.0)));
  EXPECT_NEAR(cube.volumeM3, 1.0, kExactRelative);
  expectNear(cube.centroidM, glm::dvec3(0.5), kExactRelative);
  expectNear(cube.inertiaPerDensityM5, glm::dmat3(1.0 / 6), kExactRelative / 6);
}

TEST(MassProperties, BoxAwayFromTheOriginIsExact) {
  const glm::dvec3 minM(10, -3, 2), edgesM(2, 3, 5);
  const MassProperties box = massProperties(boxMesh(minM, minM + edgesM));
  EXPECT_NEAR(box.volumeM3, 30.0, 30.0 * kExactRelative);
  expectNear(box.centroidM, minM + 0.5 * edgesM, 11.0 * kExactRelative);
  const glm::dmat3 expected = boxInertia(edgesM);
  expectNear(box.inertiaPerDensityM5, expected, expected[0][0] * kExactRelative);
}

// The inscribed polyhedron P lies between the ball of the sphere's radius r and the ball of radius ρ, the least
// distance from the centre to a face's plane. ∫(y² + z²) dV and the volume grow with the region, so each is bracketed
// by the balls' values 8/15 π ρ⁵ … 8/15 π r⁵ (4/3 π ρ³ … 4/3 π r³); with 64 segments and 32 rings ρ is within
// 1 − cos(π/32) ≈ 0.5 % of r, so the bracket is within about 2.4 % of the sphere's inertia.
TEST(MassProperties, TessellatedSphereIsWithinItsTessellation) {
  const double radiusM = 0.7;
  const TriangleMesh sphere = uvSphere(radiusM, 32, 64);
  double insideRadiusM = radiusM;
  for (const glm::uvec3& triangle : sphere.triangles) {
    const glm::dvec3 &a = sphere.vertices[triangle.x], &b = sphere.vertices[triangle.y], &c = sphere.vertices[triangle.z];
    insideRadiusM = std::min(insideRadiusM, std::abs(glm::dot(glm::normalize(glm::cross(b - a, c - a)), a)));
  }
  ASSERT_GT(insideRadiusM, radiusM * std::cos(pi / 32) * (1 - 1e-12));

  const MassProperties measured = massProperties(sphere);
  EXPECT_GE(measured.volumeM3, 4.0 / 3 * pi * std::pow(insideRadiusM, 3));
  EXPECT_LE(measured.volumeM3, 4.0 / 3 * pi * std::pow(radiusM, 3));
  // Symmetric about the centre through every axis: the centroid and the products of inertia vanish to rounding.
  expectNear(measured.centroidM, glm::dvec3(0.0), 1e-12 * radiusM);
  const double leastM5 = 8.0 / 15 * pi * std::pow(insideRadiusM, 5), mostM5 = 8.0 / 15 * pi * std::pow(radiusM, 5);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_GE(measured.inertiaPerDensityM5[axis][axis], leastM5) << "axis " << axis;
    EXPECT_LE(measured.inertiaPerDensityM5[axis][axis], mostM5) << "axis " << axis;
    EXPECT_NEAR(measured.inertiaPerDensityM5[axis][(axis + 1) % 3], 0.0, 1e-12 * mostM5) << "axis " << axis;
  }
}

TEST(MassProperties, TurnedBoxHasTheTurnedTensor) {
  const glm::dvec3 edgesM(0.4, 1.0, 2.5), centerM(1.5, -0.5, 3.0);
  const glm::dmat3 rotation = rotationMatrix(glm::dvec3(30, -50, 110));
  TriangleMesh box = boxMesh(-0.5 * edgesM, 0.5 * edgesM);
  for (glm::dvec3& vertex : box.vertices) vertex = centerM + rotation * vertex;

  const MassProperties turned = massProperties(box);
  EXPECT_NEAR(turned.volumeM3, 1.0, kExactRelative);
  expectNear(turned.centroidM, centerM, 3.0 * kExactRelative);
  const glm::dmat3 expected = rotation * boxInertia(edgesM) * glm::transpose(rotation);
  // The rotated corners carry a few ε of rounding each, the tensor's terms a few more.
  expectNear(turned.inertiaPerDensityM5, expected, 1e-11 * expected[2][2]);
}

TEST(MassProperties, InwardMeshIsMeasuredAsItsOutwardTwin) {
  const TriangleMesh outward = uvSphere(1.3, 12, 24);
  TriangleMesh inward = outward;
  for (glm::uvec3& triangle : inward.triangles) std::swap(triangle.y, triangle.z);

  const MassProperties out = massProperties(outward), in = massProperties(inward);
  EXPECT_GT(in.volumeM3, 0);
  EXPECT_DOUBLE_EQ(in.volumeM3, out.volumeM3);
  expectNear(in.centroidM, out.centroidM, 1e-15);
  expectNear(in.inertiaPerDensityM5, out.inertiaPerDensityM5, 1e-14 * out.inertiaPerDensityM5[0][0]);
}

TEST(MassProperties, OpenMeshIsRefused) {
  TriangleMesh box = boxMesh(glm::dvec3(0.0), glm::dvec3(1.0));
  box.triangles.pop_back();
  try {
    massProperties(box);
    FAIL() << "an open mesh was measured";
  } catch (const MeshError& error) {
    EXPECT_NE(std::string(error.what()).find("open"), std::string::npos) << error.what();
  }
}

// One face of a cube turned inward (its two triangles wound the other way): closed, but the four edges around that face
// join triangles that face opposite ways, and the divergence theorem would subtract the face's part of the volume
// (about the cube's centre each face adds a sixth: a cube of volume 1 would measure 2/3). Refused, naming the count.
TEST(MassProperties, InconsistentlyOrientedMeshIsRefused) {
  TriangleMesh box = boxMesh(glm::dvec3(0.0), glm::dvec3(1.0));
  for (std::size_t t = box.triangles.size() - 2; t < box.triangles.size(); ++t) {
    std::swap(box.triangles[t].y, box.triangles[t].z);
  }
  EXPECT_EQ(measureSurface(box).boundaryEdges, 0u);
  EXPECT_EQ(measureSurface(box).misorientedEdges, 4u);
  EXPECT_EQ(measureSurface(boxMesh(glm::dvec3(0.0), glm::dvec3(1.0))).misorientedEdges, 0u);
  try {
    massProperties(box);
    FAIL() << "an inconsistently oriented mesh was measured";
  } catch (const MeshError& error) {
    EXPECT_NE(std::string(error.what()).find("not consistently oriented (4 edges join triangles wound opposite ways)"),
              std::string::npos)
        << error.what();
  }
}

TEST(MassProperties, MeshEnclosingNoVolumeIsRefused) {
  // A square and the same square facing the other way: closed, and flat.
  TriangleMesh flat;
  flat.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  flat.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 2, 1}, {0, 3, 2}};
  try {
    massProperties(flat);
    FAIL() << "a flat mesh was measured";
  } catch (const MeshError& error) {
    EXPECT_NE(std::string(error.what()).find("no volume"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace firn::voxelizer
