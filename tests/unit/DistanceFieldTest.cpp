// The signed distance field bake (voxelizer/DistanceField.h): the lattice, distances against analytic fields and
// against every triangle's distance, the winding number's sign on closed, flipped, open and thin meshes, and the
// same bytes for any thread count.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "support/TestMeshes.h"
#include "voxelizer/DistanceField.h"
#include "voxelizer/WindingNumber.h"

namespace firn::voxelizer {
namespace {

// Distances are stored as 32-bit floats: 2⁻²⁴ ≈ 6e-8 relative, under 1e-7 m for the metre-sized meshes here, with
// the double arithmetic before it far below that. 1e-6 m (or 1e-6 relative) leaves a factor of ten.
constexpr double floatStorageToleranceM = 1e-6;
// The bake's sign is WindingNumber::inside, the hierarchy's w; the tests compare with the exact sum. The
// hierarchy's error reached 0.0075 in the measurements WindingNumber.h reports; where the exact |w| lies that close
// to 0.5 either sign is right.
constexpr double fastWindingErrorBound = 0.01;

glm::dvec3 samplePositionM(const DistanceField& field, int x, int y, int z) {
  return field.originM + field.spacingM * glm::dvec3(x, y, z);
}

template <typename Visit>
void forEachSample(const DistanceField& field, const Visit& visit) {
  for (int z = 0; z < field.samples.z; ++z) {
    for (int y = 0; y < field.samples.y; ++y) {
      for (int x = 0; x < field.samples.x; ++x) visit(x, y, z, samplePositionM(field, x, y, z));
    }
  }
}

// The box [lowM, highM] as 12 triangles, counter-clockwise seen from outside.
TriangleMesh box(const glm::dvec3& lowM, const glm::dvec3& highM) {
  TriangleMesh mesh;
  for (int corner = 0; corner < 8; ++corner) {
    mesh.vertices.emplace_back(corner & 1 ? highM.x : lowM.x, corner & 2 ? highM.y : lowM.y,
                               corner & 4 ? highM.z : lowM.z);
  }
  // Per face, its four corners counter-clockwise seen from outside, as two triangles.
  const unsigned faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& face : faces) {
    mesh.triangles.emplace_back(face[0], face[1], face[2]);
    mesh.triangles.emplace_back(face[0], face[2], face[3]);
  }
  return mesh;
}

// The exact signed distance to the box: Euclidean outside, minus the distance to the nearest face inside.
double boxDistanceM(const glm::dvec3& pointM, const glm::dvec3& lowM, const glm::dvec3& highM) {
  const glm::dvec3 centreM = 0.5 * (lowM + highM);
  const glm::dvec3 q = glm::abs(pointM - centreM) - 0.5 * (highM - lowM);
  return glm::length(glm::max(q, 0.0)) + std::min(std::max({q.x, q.y, q.z}), 0.0);
}

// The box without its +x face (the last two triangles).
TriangleMesh openBox(const glm::dvec3& lowM, const glm::dvec3& highM) {
  TriangleMesh mesh = box(lowM, highM);
  mesh.triangles.resize(10);
  return mesh;
}

TriangleMesh flipped(TriangleMesh mesh) {
  for (glm::uvec3& triangle : mesh.triangles) std::swap(triangle.y, triangle.z);
  return mesh;
}

// The distance to a triangle computed differently from the bake (which walks Ericson's Voronoi regions): the
// projection onto the plane if it falls inside (all three edge tests agree with the normal), else the nearest of
// the three edges as clamped segments.
double segmentDistanceM(const glm::dvec3& pointM, const glm::dvec3& startM, const glm::dvec3& endM) {
  const glm::dvec3 alongM = endM - startM;
  const double lengthSquared = glm::dot(alongM, alongM);
  const double fraction =
      lengthSquared > 0 ? std::clamp(glm::dot(pointM - startM, alongM) / lengthSquared, 0.0, 1.0) : 0;
  return glm::length(pointM - (startM + fraction * alongM));
}

double bruteTriangleDistanceM(const glm::dvec3& pointM, const glm::dvec3& aM, const glm::dvec3& bM,
                              const glm::dvec3& cM) {
  const glm::dvec3 normal = glm::cross(bM - aM, cM - aM);
  const double normalLength = glm::length(normal);
  if (normalLength > 0) {
    const glm::dvec3 unit = normal / normalLength;
    const glm::dvec3 projectedM = pointM - glm::dot(pointM - aM, unit) * unit;
    const bool insideAll = glm::dot(glm::cross(bM - aM, projectedM - aM), normal) >= 0 &&
                           glm::dot(glm::cross(cM - bM, projectedM - bM), normal) >= 0 &&
                           glm::dot(glm::cross(aM - cM, projectedM - cM), normal) >= 0;
    if (insideAll) return std::abs(glm::dot(pointM - aM, unit));
  }
  return std::min(
      {segmentDistanceM(pointM, aM, bM), segmentDistanceM(pointM, bM, cM), segmentDistanceM(pointM, cM, aM)});
}

double bruteDistanceM(const glm::dvec3& pointM, const TriangleMesh& mesh) {
  double nearestM = std::numeric_limits<double>::infinity();
  for (const glm::uvec3& t : mesh.triangles) {
    nearestM =
        std::min(nearestM, bruteTriangleDistanceM(pointM, mesh.vertices[t.x], mesh.vertices[t.y], mesh.vertices[t.z]));
  }
  return nearestM;
}

// A closed, star-shaped blob: a coarse UV sphere whose vertices lie at radii drawn from mt19937 (its sequence is
// fixed by the standard; the scaling is done here so no library's distribution enters), plus a free triangle
// floating outside, one crossing the blob, and two degenerate ones (a repeated vertex, three collinear).
TriangleMesh randomishMesh() {
  TriangleMesh mesh = test::uvSphere(1.0, 7, 11);
  std::mt19937 random(20260127);
  const auto unit = [&] {
    return double(random() - std::mt19937::min()) / double(std::mt19937::max() - std::mt19937::min());
  };
  for (glm::dvec3& vertexM : mesh.vertices) vertexM *= 0.3 + 0.2 * unit();
  const auto addTriangle = [&](const glm::dvec3& aM, const glm::dvec3& bM, const glm::dvec3& cM) {
    const auto first = unsigned(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), {aM, bM, cM});
    mesh.triangles.emplace_back(first, first + 1, first + 2);
  };
  addTriangle({0.55, -0.2, 0.1}, {0.7, 0.25, -0.15}, {0.6, 0.05, 0.4});
  addTriangle({-0.6, -0.5, 0.05}, {0.1, -0.1, -0.2}, {-0.2, 0.3, 0.3});
  addTriangle({-0.4, 0.5, -0.4}, {-0.4, 0.5, -0.4}, {-0.1, 0.45, -0.3});
  // Binary fractions, so that the three corners are collinear in doubles too, not just on paper.
  addTriangle({0.25, -0.5, 0.25}, {0.375, -0.4375, 0.3125}, {0.625, -0.3125, 0.4375});
  return mesh;
}

bool sameBytes(const DistanceField& first, const DistanceField& second) {
  return first.samples == second.samples && first.distancesM.size() == second.distancesM.size() &&
         std::memcmp(first.distancesM.data(), second.distancesM.data(), first.distancesM.size() * sizeof(float)) == 0;
}

TEST(DistanceField, LatticeCoversTheBoxAndMarginInWholeSteps) {
  const Bounds meshBox{{-0.5, 0.0, 1.0}, {0.5, 0.3, 1.01}};
  const double spacingM = 0.04;
  const double marginM = 0.1;
  const DistanceField lattice = distanceFieldLattice(meshBox, spacingM, marginM);
  EXPECT_TRUE(lattice.distancesM.empty());  // counted, not allocated
  EXPECT_EQ(lattice.spacingM, spacingM);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_DOUBLE_EQ(lattice.originM[axis], meshBox.minM[axis] - marginM);
    const double lastM = lattice.originM[axis] + spacingM * (lattice.samples[axis] - 1);
    // The last sample reaches the grown box, and one step fewer would not: exact to rounding (1e-12 m).
    EXPECT_GE(lastM, meshBox.maxM[axis] + marginM - 1e-12) << "axis " << axis;
    EXPECT_LT(lastM - spacingM, meshBox.maxM[axis] + marginM - 1e-12) << "axis " << axis;
  }
  // x: 1.2 m in steps of 0.04 m is 30 steps exactly, which rounding must not make 31.
  EXPECT_EQ(lattice.samples.x, 31);
}

TEST(DistanceField, RejectsEmptyMeshesAndBadSpacingOrMargin) {
  const TriangleMesh cube = box(glm::dvec3(0.0), glm::dvec3(1.0));
  EXPECT_THROW(bakeDistanceField(TriangleMesh{}, 0.1, 0.1), MeshError);
  TriangleMesh verticesOnly = cube;
  verticesOnly.triangles.clear();
  EXPECT_THROW(bakeDistanceField(verticesOnly, 0.1, 0.1), MeshError);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double infinity = std::numeric_limits<double>::infinity();
  for (const double bad : {0.0, -0.1, nan, infinity}) {
    EXPECT_THROW(bakeDistanceField(cube, bad, 0.1), MeshError) << "spacing " << bad;
    EXPECT_THROW(bakeDistanceField(cube, 0.1, bad), MeshError) << "margin " << bad;
  }
  TriangleMesh pastTheEnd = cube;
  pastTheEnd.triangles.emplace_back(0, 1, 8);
  EXPECT_THROW(bakeDistanceField(pastTheEnd, 0.1, 0.1), MeshError);
}

// The box's field is known in closed form everywhere, inside and out, edges and corners included. The tolerance,
// 1e-5 m, is the requirement for colliders; what the bake can reach is float storage, 1e-7 m here.
TEST(DistanceField, CubeEqualsTheAnalyticBoxField) {
  const glm::dvec3 lowM(-0.4, -0.3, 0.1);
  const glm::dvec3 highM(0.6, 0.7, 1.1);
  const DistanceField field = bakeDistanceField(box(lowM, highM), 0.047, 0.2);
  ASSERT_EQ(field.distancesM.size(), field.sampleCount());
  int insideCount = 0;
  double worstM = 0;
  forEachSample(field, [&](int x, int y, int z, const glm::dvec3& pointM) {
    const double expectedM = boxDistanceM(pointM, lowM, highM);
    worstM = std::max(worstM, std::abs(field.at(x, y, z) - expectedM));
    insideCount += expectedM < 0;
  });
  EXPECT_LE(worstM, 1e-5);
  EXPECT_GT(insideCount, 1000);  // 21³ samples lie inside
}

// The same triangles facing inward: w = −1 inside, and |w| ≥ 0.5 still marks it inside.
TEST(DistanceField, FlippedCubeGivesTheSameField) {
  const glm::dvec3 lowM(-0.4, -0.3, 0.1);
  const glm::dvec3 highM(0.6, 0.7, 1.1);
  const DistanceField outward = bakeDistanceField(box(lowM, highM), 0.047, 0.2);
  const DistanceField inward = bakeDistanceField(flipped(box(lowM, highM)), 0.047, 0.2);
  ASSERT_EQ(inward.samples, outward.samples);
  for (std::size_t sample = 0; sample < outward.sampleCount(); ++sample) {
    ASSERT_NEAR(inward.distancesM[sample], outward.distancesM[sample], floatStorageToleranceM) << "sample " << sample;
  }
}

// The UV sphere's polyhedron lies between the sphere of radius r and the one of radius r_in, the nearest any face's
// plane comes to the centre; a signed distance only grows as its set shrinks, so |x| − r ≤ φ ≤ |x| − r_in. Its
// deviation from |x| − r is at most the chord error r − r_in (here 2.1 mm), plus float storage.
TEST(DistanceField, SphereEqualsItsRadialDistanceWithinTheChordError) {
  const double radiusM = 0.5;
  const TriangleMesh sphere = test::uvSphere(radiusM, 24, 48);
  double innerRadiusM = radiusM;
  for (const glm::uvec3& t : sphere.triangles) {
    const glm::dvec3 normal = glm::normalize(
        glm::cross(sphere.vertices[t.y] - sphere.vertices[t.x], sphere.vertices[t.z] - sphere.vertices[t.x]));
    innerRadiusM = std::min(innerRadiusM, glm::dot(normal, sphere.vertices[t.x]));
  }
  const double chordErrorM = radiusM - innerRadiusM;
  ASSERT_GT(chordErrorM, 0.001);
  ASSERT_LT(chordErrorM, 0.003);
  const DistanceField field = bakeDistanceField(sphere, 0.04, 0.12);
  int insideCount = 0;
  forEachSample(field, [&](int x, int y, int z, const glm::dvec3& pointM) {
    const double phiM = field.at(x, y, z);
    ASSERT_GE(phiM, glm::length(pointM) - radiusM - floatStorageToleranceM) << x << ' ' << y << ' ' << z;
    ASSERT_LE(phiM, glm::length(pointM) - innerRadiusM + floatStorageToleranceM) << x << ' ' << y << ' ' << z;
    insideCount += phiM < 0;
  });
  EXPECT_GT(insideCount, 1000);  // about 4/3 π 12.5³ ≈ 8,000 samples
}

// The band, the sweeps and the relaxation against every triangle's distance at every sample, on a mesh with no
// regular structure, a crossing triangle, a loose one and degenerate ones. 1e-6 relative: float storage (6e-8),
// with the absolute floor for samples on the surface.
TEST(DistanceField, EqualsTheNearestOfAllTrianglesAtEverySample) {
  const TriangleMesh mesh = randomishMesh();
  const DistanceField field = bakeDistanceField(mesh, 0.037, 0.15);
  ASSERT_GT(field.sampleCount(), 20000u);
  forEachSample(field, [&](int x, int y, int z, const glm::dvec3& pointM) {
    const double expectedM = bruteDistanceM(pointM, mesh);
    ASSERT_NEAR(std::abs(field.at(x, y, z)), expectedM, 1e-6 * std::max(expectedM, field.spacingM))
        << x << ' ' << y << ' ' << z;
  });
}

// Without the free triangles the blob is closed: w is 1 inside and 0 outside, and every sample's sign must be the
// exact winding number's (all triangles' solid angles, no hierarchy), whether it was evaluated or its region's.
TEST(DistanceField, SignIsTheExactWindingNumbersOnAClosedMesh) {
  TriangleMesh blob = randomishMesh();
  blob.triangles.resize(blob.triangles.size() - 4);
  const WindingNumber winding(blob);
  const DistanceField field = bakeDistanceField(blob, 0.037, 0.15);
  int insideCount = 0;
  forEachSample(field, [&](int x, int y, int z, const glm::dvec3& pointM) {
    const double phiM = field.at(x, y, z);
    const double w = winding.exactAt(pointM);
    // On the surface either sign is right; within the fast winding number's error of 0.5 either answer is.
    if (phiM == 0 || std::abs(std::abs(w) - 0.5) <= fastWindingErrorBound) return;
    ASSERT_EQ(phiM < 0, std::abs(w) >= 0.5) << x << ' ' << y << ' ' << z << " w " << w;
    insideCount += phiM < 0;
  });
  EXPECT_GT(insideCount, 500);
}

// One face missing: the inside reaches the outside through the hole, so the region that the surface does not
// cross has probes on both sides of w = 0.5 and is evaluated sample by sample. At the centre w = 5/6 (five faces
// of six, each 1/6 of the sphere of directions); within the middle half of the box w stays above 0.5.
TEST(DistanceField, OpenCubeStillHasAnInside) {
  const TriangleMesh openCube = openBox(glm::dvec3(-0.5), glm::dvec3(0.5));
  const WindingNumber winding(openCube);
  const DistanceField field = bakeDistanceField(openCube, 0.05, 0.15);
  int middleCount = 0;
  forEachSample(field, [&](int x, int y, int z, const glm::dvec3& pointM) {
    const double phiM = field.at(x, y, z);
    if (glm::all(glm::lessThanEqual(glm::abs(pointM), glm::dvec3(0.25)))) {
      EXPECT_LT(phiM, 0) << x << ' ' << y << ' ' << z;
      ++middleCount;
    }
    const double w = winding.exactAt(pointM);
    if (phiM != 0 && std::abs(std::abs(w) - 0.5) > fastWindingErrorBound) {
      ASSERT_EQ(phiM < 0, std::abs(w) >= 0.5) << x << ' ' << y << ' ' << z << " w " << w;
    }
  });
  EXPECT_GE(middleCount, 1000);  // 11³ samples
}

// φ by trilinear interpolation at a point of the lattice given in samples (as the shaders interpolate it).
double interpolatedM(const DistanceField& field, const glm::dvec3& latticePoint) {
  const glm::ivec3 cell = glm::min(glm::ivec3(glm::floor(latticePoint)), field.samples - 2);
  const glm::dvec3 f = latticePoint - glm::dvec3(cell);
  double phiM = 0;
  for (int k = 0; k < 8; ++k) {
    const glm::ivec3 corner(k & 1, (k >> 1) & 1, k >> 2);
    const glm::dvec3 weight = glm::mix(1.0 - f, f, glm::dvec3(corner));
    phiM += weight.x * weight.y * weight.z * field.at(cell.x + corner.x, cell.y + corner.y, cell.z + corner.z);
  }
  return phiM;
}

// steepestSlope bounds how fast the interpolated field changes (list_mirror_blocks.comp relies on it): between
// 20,000 random pairs of points of the lattice, |Δφ| never exceeds it times their distance. For a distance field
// it lies between 1 (straight out of a face the samples differ by a whole spacing) and √3 (no edge differs by
// more); where the sign flips away from the surface (an open cube's hole) it is steeper than √3.
TEST(DistanceField, SteepestSlopeBoundsTheInterpolation) {
  const DistanceField closed =
      bakeDistanceField(box(glm::dvec3(-0.4, -0.3, 0.1), glm::dvec3(0.6, 0.7, 1.1)), 0.047, 0.2);
  const DistanceField open = bakeDistanceField(openBox(glm::dvec3(-0.5), glm::dvec3(0.5)), 0.05, 0.15);
  const double closedSlope = steepestSlope(closed), openSlope = steepestSlope(open);
  EXPECT_GE(closedSlope, 1.0 - 1e-5);
  EXPECT_LE(closedSlope, std::sqrt(3.0) + 1e-5);
  EXPECT_GT(openSlope, std::sqrt(3.0));
  std::mt19937 random(7);
  for (const DistanceField* field : {&closed, &open}) {
    const double slope = steepestSlope(*field);
    std::uniform_real_distribution<double> along(0.0, 1.0);
    const glm::dvec3 highest = glm::dvec3(field->samples - 1);
    double steepestSeen = 0;
    for (int pair = 0; pair < 20000; ++pair) {
      const glm::dvec3 a = highest * glm::dvec3(along(random), along(random), along(random));
      // Half the pairs within a cell of each other, where the steepest cells show.
      const glm::dvec3 b = pair % 2 == 0 ? highest * glm::dvec3(along(random), along(random), along(random))
                                         : glm::clamp(a + glm::dvec3(along(random), along(random), along(random)) - 0.5,
                                                      glm::dvec3(0.0), highest);
      const double apartM = glm::length(b - a) * field->spacingM;
      if (apartM == 0) continue;
      steepestSeen = std::max(steepestSeen, std::abs(interpolatedM(*field, a) - interpolatedM(*field, b)) / apartM);
    }
    EXPECT_LE(steepestSeen, slope * (1 + 1e-9));
    EXPECT_GT(steepestSeen, 0.5 * slope);  // the bound is not loose by more than the sampling shows
  }
}

// Two boxes in one mesh, overlapping: w = 2 where both hold a point, and |w| ≥ 0.5 keeps it inside. |φ| is the
// distance to the nearest triangle, the faces inside the other box included, so the nearer of the two boxes'
// surfaces (|box field|); the sign is the union's. Float storage bounds the difference.
TEST(DistanceField, OverlappingBoxesAreInsideWhereEitherIs) {
  const glm::dvec3 firstLowM(-0.5, -0.3, -0.3), firstHighM(0.2, 0.3, 0.3);
  const glm::dvec3 secondLowM(-0.1, -0.2, -0.4), secondHighM(0.5, 0.4, 0.2);
  TriangleMesh both = box(firstLowM, firstHighM);
  const TriangleMesh second = box(secondLowM, secondHighM);
  for (const glm::uvec3& triangle : second.triangles) both.triangles.push_back(triangle + glm::uvec3(8));
  both.vertices.insert(both.vertices.end(), second.vertices.begin(), second.vertices.end());
  const DistanceField field = bakeDistanceField(both, 0.043, 0.1);
  int overlapCount = 0;
  forEachSample(field, [&](int x, int y, int z, const glm::dvec3& pointM) {
    const double firstM = boxDistanceM(pointM, firstLowM, firstHighM);
    const double secondM = boxDistanceM(pointM, secondLowM, secondHighM);
    const double phiM = field.at(x, y, z);
    ASSERT_NEAR(std::abs(phiM), std::min(std::abs(firstM), std::abs(secondM)), floatStorageToleranceM)
        << x << ' ' << y << ' ' << z;
    if (std::min(std::abs(firstM), std::abs(secondM)) > floatStorageToleranceM) {
      ASSERT_EQ(phiM < 0, firstM < 0 || secondM < 0) << x << ' ' << y << ' ' << z;
    }
    overlapCount += firstM < 0 && secondM < 0;
  });
  EXPECT_GT(overlapCount, 100);  // about 0.3 × 0.5 × 0.5 m³ / 0.043³ m³ ≈ 940
}

// A wall 2 cm thick sampled every 1 cm, the samples halfway between the wall's faces and its centre: each lies
// 5 mm from both faces, with no sample beyond the band to carry the sign. Inside, φ = −5 mm (float storage).
TEST(DistanceField, OneCellThickWallHasAnInside) {
  const double thicknessM = 0.02;
  const double spacingM = thicknessM / 2;
  const TriangleMesh wall = box({-0.5, -0.5, 0.0}, {0.5, 0.5, thicknessM});
  const DistanceField field = bakeDistanceField(wall, spacingM, 3.5 * spacingM);
  int insideCount = 0;
  forEachSample(field, [&](int x, int y, int z, const glm::dvec3& pointM) {
    if (pointM.z <= 0 || pointM.z >= thicknessM) return;
    if (std::abs(pointM.x) > 0.5 - 2 * spacingM || std::abs(pointM.y) > 0.5 - 2 * spacingM) return;
    EXPECT_NEAR(field.at(x, y, z), -0.5 * spacingM, floatStorageToleranceM) << x << ' ' << y << ' ' << z;
    ++insideCount;
  });
  // Samples lie at x, y = −0.535 m + k 0.01 m: 96 per axis within 0.48 m of the centre, on two layers.
  EXPECT_EQ(insideCount, 2 * 96 * 96);
}

// Threads share the band by layers, the sweeps by lines and the relaxation and winding numbers by chunks, each
// written where only it writes: the bytes must not depend on how many there are. The open cube takes the
// sample-by-sample path of the sign too.
TEST(DistanceField, SameBytesForAnyThreadCount) {
  const TriangleMesh ring = test::torus(0.3, 0.12, 48, 24);
  const TriangleMesh openCube = openBox(glm::dvec3(-0.5), glm::dvec3(0.5));
  for (const TriangleMesh* mesh : {&ring, &openCube}) {
    const DistanceField single = bakeDistanceField(*mesh, 0.02, 0.06, 1);
    for (const unsigned threads : {2u, 3u, 7u}) {
      EXPECT_TRUE(sameBytes(single, bakeDistanceField(*mesh, 0.02, 0.06, threads))) << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace firn::voxelizer
