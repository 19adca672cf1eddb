// The voxelizer: mesh loading and placement, the generalized winding number, and the lattice and Poisson-disk
// samplers. Meshes are made here (UV sphere, torus) and written to files so that loading is exercised too.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>
#include <gtest/gtest.h>

#include "support/TestMeshes.h"
#include "voxelizer/Voxelizer.h"

namespace firn::voxelizer {
namespace {

constexpr double pi = 3.14159265358979323846;

// A folder of this process's own, removed with everything in it when the test ends.
class TemporaryDirectory {
 public:
  TemporaryDirectory()
      : path_(std::filesystem::temp_directory_path() / ("firn_voxelizer_test_" + std::to_string(getpid()))) {
    std::filesystem::create_directories(path_);
  }
  ~TemporaryDirectory() { std::filesystem::remove_all(path_); }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

using test::torus;
using test::uvSphere;

void writeObj(const std::filesystem::path& path, const TriangleMesh& mesh) {
  std::ofstream out(path);
  out.precision(17);
  for (const glm::dvec3& vertex : mesh.vertices) out << "v " << vertex.x << ' ' << vertex.y << ' ' << vertex.z << '\n';
  for (const glm::uvec3& triangle : mesh.triangles) {
    out << "f " << triangle.x + 1 << ' ' << triangle.y + 1 << ' ' << triangle.z + 1 << '\n';
  }
}

void appendLittleEndian(std::string& out, std::uint32_t bits, int bytes) {
  for (int byte = 0; byte < bytes; ++byte) out.push_back(static_cast<char>((bits >> (8 * byte)) & 0xFFu));
}

void appendLittleEndian(std::string& out, float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  appendLittleEndian(out, bits, 4);
}

// Binary STL: an 80-byte header (not starting with "solid", which marks ASCII STL), the triangle count, then per
// triangle a normal (zero: readers recompute it), three vertices and a 16-bit attribute.
void writeBinaryStl(const std::filesystem::path& path, const TriangleMesh& mesh) {
  std::string data(80, ' ');
  data.replace(0, 20, "binary STL from Firn");
  appendLittleEndian(data, static_cast<std::uint32_t>(mesh.triangles.size()), 4);
  for (const glm::uvec3& triangle : mesh.triangles) {
    for (int component = 0; component < 3; ++component) appendLittleEndian(data, 0.0f);
    for (int corner = 0; corner < 3; ++corner) {
      const glm::dvec3& vertex = mesh.vertices[triangle[corner]];
      for (int component = 0; component < 3; ++component) {
        appendLittleEndian(data, static_cast<float>(vertex[component]));
      }
    }
    appendLittleEndian(data, 0, 2);
  }
  std::ofstream(path, std::ios::binary).write(data.data(), static_cast<std::streamsize>(data.size()));
}

double particleVolumeM3(const std::vector<glm::dvec3>& particlesM, double spacingM) {
  return static_cast<double>(particlesM.size()) * spacingM * spacingM * spacingM;
}

// Sphere: R = 1 m, 24 rings by 48 segments (2208 triangles), s = R / 20.
constexpr double sphereRadiusM = 1.0;
constexpr double sphereSpacingM = 0.05;
const double sphereVolumeM3 = 4.0 / 3.0 * pi * sphereRadiusM * sphereRadiusM * sphereRadiusM;

// Tolerance for the filled volumes, the issue's 3%. It has to cover (1) the tessellation: the polyhedron is
// smaller than the analytic shape, by 0.7% for the sphere and 0.8% for the torus (signedVolume, asserted below
// 1% in each test); (2) the lattice count N s³ against the polyhedron's volume. Each lattice point is kept with
// the probability that its jittered position is inside, so the expected count is close to the volume over s³
// (the jitter smooths the shape's indicator over half a spacing before the lattice samples it); the draws are
// independent, so the spread is at most √(n / 4), n the lattice points within the jitter's reach of the
// surface: about 0.1% of the count here.
constexpr double volumeTolerance = 0.03;

TEST(Voxelizer, SphereFromObjFillsItsVolumeAndStaysInside) {
  const TemporaryDirectory directory;
  writeObj(directory / "sphere.obj", uvSphere(sphereRadiusM, 24, 48));
  const TriangleMesh mesh = loadMesh(directory / "sphere.obj");
  EXPECT_EQ(mesh.triangles.size(), 2208u);
  EXPECT_NEAR(signedVolume(mesh) / sphereVolumeM3, 1.0, 0.01);

  SamplingOptions options;
  options.spacingM = sphereSpacingM;
  const std::vector<glm::dvec3> particlesM = voxelize(mesh, options);
  EXPECT_NEAR(particleVolumeM3(particlesM, sphereSpacingM) / sphereVolumeM3, 1.0, volumeTolerance);
  for (const glm::dvec3& particleM : particlesM) {
    // The inside test sees each particle at its final, jittered and float-rounded position, so the jitter
    // adds nothing to the bound. The polyhedron's vertices lie on the sphere (up to the float rounding of
    // the vertices assimp reads, 2⁻²⁴ relative), so it lies in the ball: 1e-6 R covers the rounding.
    ASSERT_LE(glm::length(particleM), sphereRadiusM * (1 + 1e-6)) << particleM.x << ' ' << particleM.y << ' '
                                                                   << particleM.z;
  }
}

TEST(Voxelizer, TorusFromBinaryStlFillsItsVolumeAndStaysInside) {
  const double ringRadiusM = 1.0;
  const double tubeRadiusM = 0.4;
  const unsigned ringSegments = 64;
  const double spacingM = 0.05;
  const TemporaryDirectory directory;
  writeBinaryStl(directory / "torus.stl", torus(ringRadiusM, tubeRadiusM, ringSegments, 32));
  const TriangleMesh mesh = loadMesh(directory / "torus.stl");
  EXPECT_EQ(mesh.triangles.size(), 64u * 32u * 2u);
  const double torusVolumeM3 = 2 * pi * pi * ringRadiusM * tubeRadiusM * tubeRadiusM;
  EXPECT_NEAR(signedVolume(mesh) / torusVolumeM3, 1.0, 0.01);

  SamplingOptions options;
  options.spacingM = spacingM;
  const std::vector<glm::dvec3> particlesM = voxelize(mesh, options);
  EXPECT_NEAR(particleVolumeM3(particlesM, spacingM) / torusVolumeM3, 1.0, volumeTolerance);

  // How far a flat face strays from the torus. Take a triangle's vertices (ρ_i, u_i, z_i) in cylindrical
  // coordinates, all on the surface, with |u_i − u_m| ≤ π/n (n ring segments, u_m the middle azimuth). In
  // the meridian plane at u_m, (Σλρ_i, Σλz_i) lies in the tube's disk (a convex combination of points on its
  // circle), and a point Σλ_i x_i of the face has distance from the axis within
  // [Σλρ_i − (R + r)(1 − cos(π/n)), Σλρ_i + (R + r)² sin²(π/n) / (2 (R − r) cos(π/n))]
  // (the azimuthal components shorten it by at most the cosine and add at most B²/2A, B ≤ (R + r) sin(π/n),
  // A ≥ (R − r) cos(π/n)). So the face lies within r + δ of the tube's centre circle, δ the larger of the two.
  const double halfAngleRad = pi / ringSegments;
  const double inwardM = (ringRadiusM + tubeRadiusM) * (1 - std::cos(halfAngleRad));
  const double outwardM = std::pow((ringRadiusM + tubeRadiusM) * std::sin(halfAngleRad), 2) /
                          (2 * (ringRadiusM - tubeRadiusM) * std::cos(halfAngleRad));
  // 1e-6 m covers the float rounding of the STL's vertices; the jitter adds nothing (see the sphere test).
  const double allowedM = tubeRadiusM + std::max(inwardM, outwardM) + 1e-6;
  for (const glm::dvec3& particleM : particlesM) {
    const double fromRingM = std::hypot(std::hypot(particleM.x, particleM.y) - ringRadiusM, particleM.z);
    ASSERT_LE(fromRingM, allowedM) << particleM.x << ' ' << particleM.y << ' ' << particleM.z;
  }
}

TEST(Voxelizer, SameOptionsGiveIdenticalParticles) {
  const TriangleMesh mesh = uvSphere(sphereRadiusM, 12, 24);
  for (const Sampler sampler : {Sampler::Lattice, Sampler::PoissonDisk}) {
    SamplingOptions options;
    options.spacingM = 0.1;
    options.sampler = sampler;
    const std::vector<glm::dvec3> first = voxelize(mesh, options);
    EXPECT_FALSE(first.empty());
    // Exact equality: the draws come from a fixed seed and the parallel inside tests keep the order.
    EXPECT_EQ(first, voxelize(mesh, options));
  }
}

TEST(WindingNumber, IsOneInsideAndZeroOutsideAClosedMesh) {
  const WindingNumber windingNumber(torus(1.0, 0.4, 48, 24));
  // A closed, outward mesh winds once around its inside: the solid angles sum to 4π up to rounding.
  EXPECT_NEAR(windingNumber.exactAt({1.0, 0.0, 0.0}), 1.0, 1e-12);
  EXPECT_NEAR(windingNumber.exactAt({0.0, 0.0, 0.0}), 0.0, 1e-12);  // the hole
  EXPECT_NEAR(windingNumber.exactAt({3.0, 2.0, 1.0}), 0.0, 1e-12);
  EXPECT_TRUE(windingNumber.inside({0.0, -1.2, 0.1}));
  EXPECT_FALSE(windingNumber.inside({0.0, 0.5, 0.0}));
}

TEST(WindingNumber, AcceleratedAgreesWithExact) {
  const TriangleMesh mesh = torus(1.0, 0.4, 96, 48);  // 9216 triangles
  const WindingNumber windingNumber(mesh);
  const Bounds box = bounds(mesh);
  const glm::dvec3 marginM = 0.25 * (box.maxM - box.minM);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double largestErrorSeen = 0;
  for (int sample = 0; sample < 1000; ++sample) {
    const glm::dvec3 pointM = box.minM - marginM + glm::dvec3(unit(random), unit(random), unit(random)) *
                                                       (box.maxM - box.minM + 2.0 * marginM);
    const double error = std::abs(windingNumber.at(pointM) - windingNumber.exactAt(pointM));
    largestErrorSeen = std::max(largestErrorSeen, error);
    // The issue's bound; met empirically, for β = 2 with terms to second order: over 20,000 random points in
    // this box the largest error was 0.0075 and the mean 0.0011 (0.0065 and 0.0011 for a 70,000-triangle
    // torus). Far below the 0.5 that would flip an inside test.
    ASSERT_LE(error, 1e-2) << "at " << pointM.x << ' ' << pointM.y << ' ' << pointM.z;
  }
  // The hierarchy must be doing something: an exact evaluation would agree to rounding.
  EXPECT_GT(largestErrorSeen, 1e-9);
}

TEST(WindingNumber, SphereWithMissingFacesStillFills) {
  TriangleMesh mesh = uvSphere(sphereRadiusM, 24, 48);
  // Five holes: a cap triangle at the north pole, and triangles at scattered places on the bands.
  for (const std::size_t hole : {2000u, 1500u, 1000u, 517u, 0u}) {
    mesh.triangles.erase(mesh.triangles.begin() + static_cast<std::ptrdiff_t>(hole));
  }
  const WindingNumber windingNumber(mesh);
  // The centre sees the sphere less the holes' solid angle: 5 faces, none subtending more than twice the
  // average 4π / 2208.
  EXPECT_NEAR(windingNumber.exactAt(glm::dvec3(0.0)), 1.0, 5 * 2.0 / 2208);

  SamplingOptions options;
  options.spacingM = sphereSpacingM;
  // A hole of area A lowers w below 0.5 only within about √(A / 2π) of it (where its solid angle exceeds
  // 2π): a sliver of the volume. So the closed sphere's tolerance holds.
  EXPECT_NEAR(particleVolumeM3(voxelize(mesh, options), sphereSpacingM) / sphereVolumeM3, 1.0, volumeTolerance);
}

TEST(WindingNumber, ReversedOrDuplicatedFacesFillTheSameParticles) {
  const TriangleMesh mesh = uvSphere(sphereRadiusM, 24, 48);
  TriangleMesh reversed = mesh;
  for (glm::uvec3& triangle : reversed.triangles) std::swap(triangle.y, triangle.z);
  TriangleMesh duplicated = mesh;
  duplicated.triangles.insert(duplicated.triangles.end(), mesh.triangles.begin(), mesh.triangles.end());

  EXPECT_NEAR(WindingNumber(reversed).at(glm::dvec3(0.0)), -1.0, 1e-2);
  EXPECT_NEAR(WindingNumber(duplicated).at(glm::dvec3(0.0)), 2.0, 1e-2);
  EXPECT_LT(signedVolume(reversed), 0);

  SamplingOptions options;
  options.spacingM = sphereSpacingM;
  const std::vector<glm::dvec3> particlesM = voxelize(mesh, options);
  EXPECT_NEAR(particleVolumeM3(particlesM, sphereSpacingM) / sphereVolumeM3, 1.0, volumeTolerance);
  // A closed mesh's w is 0, ±1 or 2 up to rounding and the expansion's error (below 0.01), far from the
  // threshold |w| = 0.5: the same points pass, exactly.
  EXPECT_EQ(voxelize(reversed, options), particlesM);
  EXPECT_EQ(voxelize(duplicated, options), particlesM);
}

// Before sampling, the count comes from voxelizing on a coarse lattice of at most 32,768 points (Voxelizer.h). Its
// error is that of a lattice count at spacing c: the surface's share, about √(A/c²) points of the V/c³ counted,
// 1.3% for the sphere and 2% for the torus at these sizes; 5% holds with room. Poisson-disk sampling adds its
// surface layer of 0.17 A/s² (Samplers.h), itself good to 0.01 A/s².
TEST(Voxelizer, EstimateBeforeSamplingMatchesTheCount) {
  for (const TriangleMesh& mesh : {uvSphere(sphereRadiusM, 24, 48), torus(1.0, 0.4, 64, 32)}) {
    for (const Sampler sampler : {Sampler::Lattice, Sampler::PoissonDisk}) {
      SamplingOptions options;
      options.spacingM = sphereSpacingM;
      options.sampler = sampler;
      const SampleEstimate estimate = estimateVoxelize(mesh, options);
      const double counted = double(voxelize(mesh, options).size());
      EXPECT_NEAR(estimate.points / counted, 1.0, 0.05) << counted << " points";
      // The lattice tests every point of the box's lattice (and Poisson-disk sampling 30 per sample more).
      EXPECT_GE(estimate.insideTests, counted);
    }
  }
}

TEST(Voxelizer, SamplingStopsPastMaxPoints) {
  const TriangleMesh mesh = uvSphere(sphereRadiusM, 12, 24);
  for (const Sampler sampler : {Sampler::Lattice, Sampler::PoissonDisk}) {
    SamplingOptions options;
    options.spacingM = 0.1;  // about 4,200 points
    options.sampler = sampler;
    options.maxPoints = 1000;
    try {
      voxelize(mesh, options);
      FAIL() << "expected TooManySamples";
    } catch (const TooManySamples& tooMany) {
      EXPECT_EQ(tooMany.maxPoints(), 1000u);
    }
    double lastFraction = -1;
    options.maxPoints = 100000;
    options.progress = [&](double fraction) {
      EXPECT_GE(fraction, lastFraction);
      lastFraction = fraction;
    };
    EXPECT_GT(voxelize(mesh, options).size(), 1000u);
    // The lattice reports each batch, the last at the end; Poisson-disk sampling each row of seeds as it starts.
    EXPECT_GT(lastFraction, sampler == Sampler::Lattice ? 0.999 : 0.5);
  }
}

TEST(MeshSurface, FindsTheHolesOfOpenMeshes) {
  const TriangleMesh sphere = uvSphere(sphereRadiusM, 24, 48);
  EXPECT_EQ(measureSurface(sphere).boundaryEdges, 0u);
  // The polyhedron's area is a little under the sphere's, by about its volume's 0.7% deficit times 2/3... and
  // the rest: 2% covers a 24 × 48 tessellation.
  EXPECT_NEAR(measureSurface(sphere).areaM2 / (4 * pi), 1.0, 0.02);
  TriangleMesh holed = sphere;
  holed.triangles.erase(holed.triangles.begin() + 1000);  // a band triangle: its three edges border the hole
  EXPECT_EQ(measureSurface(holed).boundaryEdges, 3u);
  // Split vertices (an STL's three per triangle) are welded by position: a closed torus stays closed.
  const TriangleMesh closed = torus(1.0, 0.4, 32, 16);
  TriangleMesh split;
  for (const glm::uvec3& triangle : closed.triangles) {
    const auto first = static_cast<unsigned>(split.vertices.size());
    for (int corner = 0; corner < 3; ++corner) split.vertices.push_back(closed.vertices[triangle[corner]]);
    split.triangles.emplace_back(first, first + 1, first + 2);
  }
  EXPECT_EQ(measureSurface(split).boundaryEdges, 0u);
}

TEST(MeshSurface, SignedVolumeOfAnOpenMeshDoesNotDependOnItsPlacement) {
  TriangleMesh holed = uvSphere(sphereRadiusM, 24, 48);
  holed.triangles.resize(holed.triangles.size() / 2);  // the northern half: a bowl
  const double atOrigin = signedVolume(holed);
  // Measured about the box's centre, as a closed mesh's is anywhere (1e-9 m³ of rounding at 1000 m).
  EXPECT_NEAR(signedVolume(transformed(holed, {1, glm::dvec3(0.0), glm::dvec3(1000, -400, 30)})), atOrigin, 1e-9);
  // And it cannot exceed the box (the divergence-theorem sum about the origin would, far from it).
  const Bounds box = bounds(holed);
  EXPECT_LE(std::abs(atOrigin), (box.maxM.x - box.minM.x) * (box.maxM.y - box.minM.y) * (box.maxM.z - box.minM.z));
}

TEST(MeshChecks, FlatMeshesCannotBeFilled) {
  // A square of two triangles, turned off the axes so that no coordinate is constant.
  TriangleMesh square;
  square.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  square.triangles = {{0, 1, 2}, {0, 2, 3}};
  const TriangleMesh turned = transformed(square, {2, glm::dvec3(30, 40, 50), glm::dvec3(0.5)});
  const std::string problem = whyNotFillable(turned, measureSurface(turned), 0.01);
  EXPECT_NE(problem.find("the mesh is flat"), std::string::npos) << problem;
  EXPECT_NE(problem.find("encloses no volume"), std::string::npos) << problem;
  // A closed mesh is fillable; one far out where floats are coarser than the spacing is not.
  const TriangleMesh sphere = uvSphere(sphereRadiusM, 12, 24);
  EXPECT_EQ(whyNotFillable(sphere, measureSurface(sphere), 0.01), "");
  const TriangleMesh far = transformed(sphere, {1, glm::dvec3(0.0), glm::dvec3(5e6, 0, 0)});
  // Between 2²² and 2²³ m (4.2e6 to 8.4e6) floats are 0.5 m apart, more than a tenth of 1 m.
  EXPECT_NE(whyNotFillable(far, measureSurface(far), 1.0).find("0.5 m apart"), std::string::npos);
  // 1e308 m scaled, then moved 1e308 m: 2e308 overflows a double.
  const TriangleMesh overflowed = transformed(sphere, {1e308, glm::dvec3(0.0), glm::dvec3(1e308, 0, 0)});
  EXPECT_NE(whyNotFillable(overflowed, measureSurface(overflowed), 1.0).find("beyond the range of a double"),
            std::string::npos);
}

TEST(MeshChecks, NoParticlesSaysTheBoundsAndASpacingThatFills) {
  const TriangleMesh sphere = uvSphere(0.01, 12, 24);  // 2 cm across
  SamplingOptions options;
  options.spacingM = 0.1;
  ASSERT_TRUE(voxelize(sphere, options).empty());
  const std::string why = whyNoParticles(sphere, measureSurface(sphere), options.spacingM);
  EXPECT_NE(why.find("[-0.01, -0.01, -0.01] to [0.01, 0.01, 0.01] m"), std::string::npos) << why;
  EXPECT_NE(why.find("a spacing of 0.005 m or less would fill it"), std::string::npos) << why;
  // And that spacing does.
  options.spacingM = 0.005;
  EXPECT_FALSE(voxelize(sphere, options).empty());
}

// The cap of the unit sphere within `halfAngleDeg` of the pole: an open bowl whose winding number passes ½ only in
// the lens between it and its rim's plane, of thickness h = 1 − cos θ at the pole.
TriangleMesh sphericalCap(double halfAngleDeg) {
  const TriangleMesh sphere = uvSphere(sphereRadiusM, 180, 48);  // 1° rings
  const double minZ = std::cos(halfAngleDeg * pi / 180) - 1e-9;
  // The vertices are those of the cap (the sampler's box is the vertices' box): the first 1 + 48 per ring.
  const auto ringsInCap = static_cast<unsigned>(std::floor(halfAngleDeg + 1e-9));
  const auto capVertices = 1 + 48 * ringsInCap;
  TriangleMesh cap;
  cap.vertices.assign(sphere.vertices.begin(), sphere.vertices.begin() + capVertices);
  for (const glm::uvec3& triangle : sphere.triangles) {
    if (sphere.vertices[triangle.x].z >= minZ && sphere.vertices[triangle.y].z >= minZ &&
        sphere.vertices[triangle.z].z >= minZ) {
      cap.triangles.push_back(triangle);
    }
  }
  return cap;
}

TEST(MeshChecks, AnOpenMeshFilledOnlyAlongItsSurfaceIsASheet) {
  // A 3° cap: its lens is h = 1.37 mm thick at the pole, under the spacing of 2 mm, so the lattice has one layer of
  // points across it, about half of them inside the lens: an average layer of about half a spacing over its
  // 0.0086 m², under the one spacing that makes a sheet.
  const TriangleMesh shallow = sphericalCap(3);
  const MeshSurface shallowSurface = measureSurface(shallow);
  ASSERT_TRUE(shallowSurface.open());
  EXPECT_EQ(whyNotFillable(shallow, shallowSurface, 0.002), "");  // curved, not flat: the check before filling passes
  SamplingOptions options;
  options.spacingM = 0.002;
  const std::size_t shallowParticles = voxelize(shallow, options).size();
  EXPECT_GT(shallowParticles, 0u);
  EXPECT_NE(sheetWarning(shallowSurface, shallowParticles, options.spacingM).find("fills as a sheet"), std::string::npos)
      << shallowParticles << " particles";
  // A 15° cap at 5 mm: a lens 34 mm thick at the pole, 17 mm (3.4 spacings) on average. Open, but it does enclose
  // volume: no warning.
  const TriangleMesh deep = sphericalCap(15);
  options.spacingM = 0.005;
  const std::size_t deepParticles = voxelize(deep, options).size();
  EXPECT_EQ(sheetWarning(measureSurface(deep), deepParticles, options.spacingM), "") << deepParticles << " particles";
  const TriangleMesh sphere = uvSphere(sphereRadiusM, 24, 48);
  EXPECT_EQ(sheetWarning(measureSurface(sphere), 33000, sphereSpacingM), "");  // closed
}

// Rotations are exact up to the rounding of cos 90° (6e-17) and sin; 1e-12 allows for it.
TEST(VoxelizerMesh, RotationTurnsAboutXThenYThenZ) {
  const glm::dvec3 up(0, 1, 0);
  const glm::dvec3 aboutX = rotationMatrix({90, 0, 0}) * up;
  EXPECT_LT(glm::length(aboutX - glm::dvec3(0, 0, 1)), 1e-12);  // +y → +z
  // x first (+y → +z), then y (+z → +x).
  const glm::dvec3 aboutXThenY = rotationMatrix({90, 90, 0}) * up;
  EXPECT_LT(glm::length(aboutXThenY - glm::dvec3(1, 0, 0)), 1e-12);
  const glm::dvec3 aboutZ = rotationMatrix({0, 0, 90}) * glm::dvec3(1, 0, 0);
  EXPECT_LT(glm::length(aboutZ - glm::dvec3(0, 1, 0)), 1e-12);  // +x → +y
}

TEST(VoxelizerMesh, TransformScalesRotatesThenTranslates) {
  // Bounds need only vertices: the unit cube's eight corners.
  TriangleMesh cube;
  for (int corner = 0; corner < 8; ++corner) {
    cube.vertices.emplace_back(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
  }
  const Bounds scaled = bounds(transformed(cube, {2.0, glm::dvec3(0.0), {1, 2, 3}}));
  EXPECT_EQ(scaled.minM, glm::dvec3(1, 2, 3));
  EXPECT_EQ(scaled.maxM, glm::dvec3(3, 4, 5));
  // Rotated 90° about z, [0, 2]² in x and y becomes [−2, 0] × [0, 2]; then translated.
  const Bounds rotated = bounds(transformed(cube, {2.0, {0, 0, 90}, {1, 2, 3}}));
  EXPECT_LT(glm::length(rotated.minM - glm::dvec3(-1, 2, 3)), 1e-12);
  EXPECT_LT(glm::length(rotated.maxM - glm::dvec3(1, 4, 5)), 1e-12);
}

TEST(VoxelizerMesh, LoadsGltfWithNodeTransformsApplied) {
  const TemporaryDirectory directory;
  // A tetrahedron with outward faces, placed by a child node (scale 2) under a parent (translation x + 10).
  std::string buffer;  // 4 float32 vec3 corners, then 12 uint16 indices; glTF is little-endian
  for (const float coordinate : {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}) appendLittleEndian(buffer, coordinate);
  for (const std::uint32_t index : {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3}) appendLittleEndian(buffer, index, 2);
  std::ofstream(directory / "tetrahedron.bin", std::ios::binary)
      .write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  std::ofstream(directory / "tetrahedron.gltf") << R"({
    "asset": { "version": "2.0" },
    "scene": 0,
    "scenes": [{ "nodes": [0] }],
    "nodes": [{ "translation": [10, 0, 0], "children": [1] }, { "scale": [2, 2, 2], "mesh": 0 }],
    "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1 }] }],
    "buffers": [{ "uri": "tetrahedron.bin", "byteLength": 72 }],
    "bufferViews": [{ "buffer": 0, "byteOffset": 0, "byteLength": 48 },
                    { "buffer": 0, "byteOffset": 48, "byteLength": 24 }],
    "accessors": [{ "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                    "min": [0, 0, 0], "max": [1, 1, 1] },
                  { "bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR" }]
  })";
  const TriangleMesh mesh = loadMesh(directory / "tetrahedron.gltf");
  EXPECT_EQ(mesh.triangles.size(), 4u);
  const Bounds box = bounds(mesh);
  // Small integers and powers of two: exact.
  EXPECT_EQ(box.minM, glm::dvec3(10, 0, 0));
  EXPECT_EQ(box.maxM, glm::dvec3(12, 2, 2));
  EXPECT_DOUBLE_EQ(signedVolume(mesh), 8.0 / 6.0);  // (2³) times the unit tetrahedron's 1/6, faces kept outward
}

TEST(VoxelizerMesh, LoadFailuresAreBadInputNamingTheFile) {
  const TemporaryDirectory directory;
  const std::filesystem::path missing = directory / "missing.obj";
  try {
    loadMesh(missing);
    FAIL() << "expected MeshError";
  } catch (const MeshError& error) {
    EXPECT_EQ(std::string(error.what()).rfind(missing.string() + ": ", 0), 0u) << error.what();
  }
  const std::filesystem::path garbage = directory / "garbage.stl";
  std::ofstream(garbage) << "this is not a mesh\n";
  try {
    loadMesh(garbage);
    FAIL() << "expected MeshError";
  } catch (const MeshError& error) {
    EXPECT_EQ(std::string(error.what()).rfind(garbage.string() + ": cannot read mesh (", 0), 0u) << error.what();
  }
}

// The lattice sampler must give the particles Firn's scene bodies have always had (engine/scene/Sampling.cpp):
// this is that loop's arithmetic, written out once more to pin it.
TEST(Lattice, ReproducesSceneBodySamplingBitForBit) {
  const glm::dvec3 centerM(0.31, 0.47, 0.52);
  const double radiusM = 0.1;
  const double spacingM = 0.02 / std::cbrt(8.0);
  const glm::dvec3 originM(-0.02, 0.04, -0.06);
  const std::uint32_t seed = 0x4669726e + 3;
  auto inSphere = [&](const glm::dvec3& pointM) {
    const glm::dvec3 offsetM = pointM - centerM;
    return glm::dot(offsetM, offsetM) <= radiusM * radiusM;
  };

  std::vector<glm::vec3> expectedM;
  const glm::dvec3 firstIndexReal = glm::floor((centerM - radiusM - originM) / spacingM - 0.5 - 0.25);
  const glm::dvec3 lastIndexReal = glm::ceil((centerM + radiusM - originM) / spacingM - 0.5 + 0.25);
  const glm::ivec3 firstIndex(firstIndexReal);
  const glm::ivec3 lastIndex(lastIndexReal);
  std::mt19937 random(seed);
  auto jitterM = [&] { return (2 * (static_cast<double>(random()) / 4294967296.0) - 1) * 0.25 * spacingM; };
  for (int k = firstIndex.z; k <= lastIndex.z; ++k) {
    for (int j = firstIndex.y; j <= lastIndex.y; ++j) {
      for (int i = firstIndex.x; i <= lastIndex.x; ++i) {
        const double jitterXM = jitterM();
        const double jitterYM = jitterM();
        const double jitterZM = jitterM();
        const glm::dvec3 latticePointM = originM + (glm::dvec3(i, j, k) + 0.5) * spacingM;
        const glm::vec3 positionM(latticePointM + glm::dvec3(jitterXM, jitterYM, jitterZM));
        if (inSphere(glm::dvec3(positionM))) expectedM.push_back(positionM);
      }
    }
  }

  SamplingOptions options;
  options.spacingM = spacingM;
  options.seed = seed;
  options.latticeOriginM = originM;
  const std::vector<glm::dvec3> pointsM = samplePoints({centerM - radiusM, centerM + radiusM}, inSphere, options);
  // About 4,200 points from about 11,000 candidates: several threads' tasks of 1024.
  ASSERT_EQ(pointsM.size(), expectedM.size());
  EXPECT_GT(pointsM.size(), 4000u);
  for (std::size_t p = 0; p < pointsM.size(); ++p) {
    ASSERT_EQ(pointsM[p], glm::dvec3(expectedM[p])) << "point " << p;
    ASSERT_EQ(glm::vec3(pointsM[p]), expectedM[p]) << "point " << p;  // and exactly a float
  }
}

TEST(PoissonDisk, BulkDensityIsOnePerSpacingCubedAndNoTwoSamplesAreCloserThanR) {
  const double spacingM = 0.01;
  const double sideM = 24 * spacingM;
  SamplingOptions options;
  options.spacingM = spacingM;
  options.sampler = Sampler::PoissonDisk;
  const std::vector<glm::dvec3> samplesM =
      samplePoints({glm::dvec3(0.0), glm::dvec3(sideM)}, [](const glm::dvec3&) { return true; }, options);

  // Counted away from the faces, where samples pack more densely (Samplers.h): 3 s in from each.
  const double marginM = 3 * spacingM;
  const auto innerCount = std::count_if(samplesM.begin(), samplesM.end(), [&](const glm::dvec3& sampleM) {
    return glm::all(glm::greaterThanEqual(sampleM, glm::dvec3(marginM))) &&
           glm::all(glm::lessThanEqual(sampleM, glm::dvec3(sideM - marginM)));
  });
  const double innerVolumeM3 = std::pow(sideM - 2 * marginM, 3);
  // The calibration measured 1.0001 ± 0.0006 /s³ on 125,000-s³ cubes (Samplers.cpp). In this cube of
  // 5,832 s³ the density varies by 0.006 (standard deviation over seeds 1 to 16, measured), so the issue's
  // 5% is about 9 standard deviations.
  EXPECT_NEAR(static_cast<double>(innerCount) * spacingM * spacingM * spacingM / innerVolumeM3, 1.0, 0.05);

  // Sorted by x, a sample's neighbours within r lie in the next samples whose x is within r.
  const double radiusM = poissonDiskRadiusM(spacingM);
  std::vector<glm::dvec3> sortedM = samplesM;
  std::sort(sortedM.begin(), sortedM.end(), [](const glm::dvec3& a, const glm::dvec3& b) { return a.x < b.x; });
  double closestM = radiusM * 10;
  for (std::size_t a = 0; a < sortedM.size(); ++a) {
    for (std::size_t b = a + 1; b < sortedM.size() && sortedM[b].x - sortedM[a].x < radiusM; ++b) {
      closestM = std::min(closestM, glm::distance(sortedM[a], sortedM[b]));
    }
  }
  // Exact: the distances were checked between the float-rounded points that are returned.
  EXPECT_GE(closestM, radiusM);
}

TEST(PoissonDisk, FillsEveryDisconnectedPartOfAShape) {
  const double spacingM = 0.01;
  const glm::dvec3 firstCenterM(0.1, 0.1, 0.1);
  const glm::dvec3 secondCenterM(0.5, 0.5, 0.5);
  const double radiusM = 0.06;
  auto inEither = [&](const glm::dvec3& pointM) {
    return glm::distance(pointM, firstCenterM) <= radiusM || glm::distance(pointM, secondCenterM) <= radiusM;
  };
  SamplingOptions options;
  options.spacingM = spacingM;
  options.sampler = Sampler::PoissonDisk;
  const std::vector<glm::dvec3> samplesM = samplePoints({glm::dvec3(0.0), glm::dvec3(0.6)}, inEither, options);
  const auto inFirst = std::count_if(samplesM.begin(), samplesM.end(), [&](const glm::dvec3& sampleM) {
    return glm::distance(sampleM, firstCenterM) <= radiusM;
  });
  const auto inSecond = static_cast<std::ptrdiff_t>(samplesM.size()) - inFirst;
  // Each ball of radius 6 s should hold about V/s³ + 0.17 A/s² = 905 + 77 samples (Samplers.h); at least
  // 90% of V/s³ in each shows that both parts were filled, not just seeded.
  const double ballCount = 4.0 / 3.0 * pi * std::pow(radiusM / spacingM, 3);
  EXPECT_GE(static_cast<double>(inFirst), 0.9 * ballCount);
  EXPECT_GE(static_cast<double>(inSecond), 0.9 * ballCount);
}

}  // namespace
}  // namespace firn::voxelizer
