// The snow's surface from the command line, as a pipeline takes it in (docs/command-line.md: `firn run --mesh
// --vdb --render surface`): the mesh file closed and in place, the VDB file read back through OpenVDB with both
// grids where they should be, two runs giving the same bytes, bad settings and a full disk refused cleanly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include "Cli.h"
#include "MeshChecks.h"

namespace {

namespace fs = std::filesystem;
using firn::test::fileBytes;
using firn::test::freshDirectory;
using firn::test::Result;
using firn::test::runFirn;
using firn::test::writeScene;

// A resting ball of R = 0.25 m (5 cells of h = 0.05 m) at 8 particles per cell: 4,200 particles. The surface's
// nodes are h / 2 = 0.025 m apart (surface.resolution 2, the default).
constexpr double kCellM = 0.05;
constexpr double kRadiusM = 0.25;
constexpr double kVoxelM = kCellM / 2;
const glm::dvec3 kCentreM(0.6, 0.6, 0.6);
const char* const kBallScene = R"({
  "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
  "time": { "dt": 1e-3, "frame_rate": 50, "frames": 1 },
  "gravity": [0, 0, 0],
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.25, "material": "snow" } ],
  "camera": { "position": [0.6, 0.6, 1.8], "target": [0.6, 0.6, 0.6], "fov_deg": 40 } })";

// Reads a binary PLY as writeMeshPly writes it, checking its header line by line.
firn::SurfaceMesh readSurfacePly(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::vector<std::string> header;
  while (std::getline(in, line) && line != "end_header") header.push_back(line);
  std::size_t vertices = 0, faces = 0;
  const std::vector<std::string> expected = {
      "ply", "format binary_little_endian 1.0", "comment written by Firn: the snow's surface", "element vertex *",
      "property float x", "property float y", "property float z", "property float nx", "property float ny",
      "property float nz", "property float vx", "property float vy", "property float vz", "element face *",
      "property list uchar uint vertex_indices"};
  EXPECT_EQ(header.size(), expected.size());
  for (std::size_t i = 0; i < std::min(header.size(), expected.size()); ++i) {
    if (expected[i].back() == '*') {
      EXPECT_EQ(header[i].rfind(expected[i].substr(0, expected[i].size() - 1), 0), 0u) << header[i];
      (expected[i].rfind("element vertex", 0) == 0 ? vertices : faces) = std::stoul(header[i].substr(expected[i].size() - 1));
    } else {
      EXPECT_EQ(header[i], expected[i]);
    }
  }
  firn::SurfaceMesh mesh;
  for (std::size_t v = 0; v < vertices; ++v) {
    float values[9];
    in.read(reinterpret_cast<char*>(values), sizeof values);
    mesh.positionsM.emplace_back(values[0], values[1], values[2]);
    mesh.normals.emplace_back(values[3], values[4], values[5]);
    mesh.velocitiesMPerS.emplace_back(values[6], values[7], values[8]);
  }
  firn::test::readPlyTriangles(in, faces, mesh.indices);
  return mesh;
}

class SurfaceCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { openvdb::initialize(); }
};

// The surface mesh as a file: the resting ball of RestingSphereGivesAClosedMeshOfItsVolumeWhereItIs, coarser
// (5 cells across its radius): closed, outward, within half a simulation cell of the sphere and of its volume
// within 5% (the issue's bounds; the same estimates as there).
TEST_F(SurfaceCli, MeshFileIsAClosedSurfaceOfTheBall) {
  const fs::path folder = freshDirectory("surface_mesh");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const Result result = runFirn("run " + scene.string() + " --frames 0 --no-ply --mesh --out " + (folder / "out").string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const firn::SurfaceMesh mesh = readSurfacePly(folder / "out" / "frame_0000_surface.ply");
  ASSERT_GT(mesh.triangleCount(), 500u);
  EXPECT_EQ(firn::test::edgesNotSharedByTwoOrientedTriangles(mesh), 0u);
  EXPECT_EQ(firn::test::componentCount(mesh), 1u);
  EXPECT_NEAR(firn::test::enclosedVolumeM3(mesh) / (4.0 / 3.0 * M_PI * std::pow(kRadiusM, 3)), 1.0, 0.05);
  for (const glm::vec3& p : mesh.positionsM) {
    ASSERT_NEAR(glm::length(glm::dvec3(p) - kCentreM), kRadiusM, 0.5 * kCellM);
  }
  EXPECT_FALSE(fs::exists(folder / "out" / "frame_0000.vdb")) << "--mesh alone writes no VDB";
}

// The VDB cache read back through OpenVDB: both grids, on voxels h / 2 apart, with their units; the level set a
// proper narrow band whose zero crossing along every ray from the centre lies within a voxel of the sphere (the
// mesh it is made from lies within half a cell, and the crossing of a sampled signed distance within a voxel of
// that: the bound is the mesh's 0.5 h = 1 voxel, with the distance field's interpolation inside it); the density
// 1 ± 5% at the centre (snow at its rest density; the jittered lattice's density varies by less).
TEST_F(SurfaceCli, VdbFileHoldsDensityAndALevelSetOfTheBall) {
  const fs::path folder = freshDirectory("surface_vdb");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const Result result = runFirn("run " + scene.string() + " --frames 0 --no-ply --vdb --out " + (folder / "out").string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  openvdb::io::File file((folder / "out" / "frame_0000.vdb").string());
  file.open();
  const openvdb::FloatGrid::Ptr density = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
  const openvdb::FloatGrid::Ptr surface = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("surface"));
  file.close();
  ASSERT_TRUE(density && surface);
  for (const openvdb::FloatGrid::Ptr& grid : {density, surface}) {
    EXPECT_NEAR(grid->transform().voxelSize()[0], kVoxelM, 1e-9);
    EXPECT_EQ(grid->metaValue<std::string>("units"), "meters");
    EXPECT_NEAR(grid->metaValue<double>("voxel_size_m"), kVoxelM, 1e-12);
  }
  EXPECT_EQ(density->getGridClass(), openvdb::GRID_FOG_VOLUME);
  EXPECT_EQ(surface->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_NEAR(surface->background(), 3 * kVoxelM, 1e-6) << "a narrow band of 3 voxels";

  const openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> distance(*surface);
  const openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> fraction(*density);
  EXPECT_NEAR(fraction.wsSample(openvdb::Vec3d(kCentreM.x, kCentreM.y, kCentreM.z)), 1.0, 0.05);
  int rays = 0;
  for (int dx = -1; dx <= 1; ++dx) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dz = -1; dz <= 1; ++dz) {
        if (dx == 0 && dy == 0 && dz == 0) continue;
        const glm::dvec3 direction = glm::normalize(glm::dvec3(dx, dy, dz));
        const auto sample = [&](double r) {
          const glm::dvec3 p = kCentreM + r * direction;
          return distance.wsSample(openvdb::Vec3d(p.x, p.y, p.z));
        };
        double crossingM = -1;
        const double stepM = kVoxelM / 8;
        for (double r = 0; r < 2 * kRadiusM; r += stepM) {
          const double inner = sample(r), outer = sample(r + stepM);
          if (inner < 0 && outer >= 0) {
            crossingM = r + stepM * inner / (inner - outer);
            break;
          }
        }
        EXPECT_NEAR(crossingM, kRadiusM, kVoxelM) << "ray " << dx << dy << dz;
        EXPECT_LT(sample(0), 0) << "inside is negative";
        ++rays;
      }
    }
  }
  EXPECT_EQ(rays, 26);
}

// The caches' velocities, for motion blur (docs/surfaces.md, Velocity): the ball of the tests above moving
// uniformly at v in free space. The velocity at a vertex, or a voxel of the VDB's `v` grid, is Σ V W v_p / Σ V W
// over the particles whose kernels reach it, a weighted mean, so it lies within the particles' own velocities
// (read from the frame's point cache) but for the fixed-point rounding of the two sums: each of the N
// contributions is rounded by at most ½ unit (2⁻²⁰) in Σ V W v_p and in Σ V W, so the mean is off by at most
// N (1 + |v|) / (2 f 2²⁰) where the field is f. N is at most the particles of a jittered lattice within the kernel
// radius R = 3 spacings: lattice points within R + √3/4 spacings, 4/3 π 3.433³ = 170. At a vertex f is the iso
// level ½; the `v` grid holds voxels down to f = 1%.
TEST_F(SurfaceCli, CachesCarryTheVelocityOfABallMovingUniformly) {
  const fs::path folder = freshDirectory("surface_velocity");
  const glm::dvec3 velocity(0.7, -0.3, 0.2);
  std::string scene = kBallScene;
  const std::string sphere = R"("radius": 0.25, "material": "snow")";
  scene.replace(scene.find(sphere), sphere.size(), sphere + R"(, "velocity": [0.7, -0.3, 0.2])");
  const fs::path scenePath = writeScene(folder, "ball.json", scene);
  const Result result = runFirn("run " + scenePath.string() + " --mesh --vdb --out " + (folder / "out").string());
  ASSERT_EQ(result.exitCode, 0) << result.output;

  // The particles' velocities in frame 1: their range per axis.
  std::ifstream points(folder / "out" / "frame_0001.ply", std::ios::binary);
  std::string line;
  std::size_t particles = 0;
  while (std::getline(points, line) && line != "end_header") {
    if (line.rfind("element vertex ", 0) == 0) particles = std::stoul(line.substr(15));
  }
  ASSERT_GT(particles, 4000u);
  glm::dvec3 lowest(1e9), highest(-1e9);
  for (std::size_t p = 0; p < particles; ++p) {
    float values[8];  // x y z vx vy vz mass plastic_j
    points.read(reinterpret_cast<char*>(values), sizeof values);
    const glm::dvec3 v(values[3], values[4], values[5]);
    lowest = glm::min(lowest, v);
    highest = glm::max(highest, v);
  }
  ASSERT_TRUE(points.good());
  EXPECT_LT(glm::length(highest - lowest), 1e-3) << "the ball moves as one";
  EXPECT_LT(glm::length(0.5 * (highest + lowest) - velocity), 1e-3) << "at the velocity it started with";
  const double contributions = 4.0 / 3.0 * M_PI * std::pow(3.0 + std::sqrt(3.0) / 4.0, 3);
  const auto roundingBound = [&](double field) {
    return contributions * (1.0 + glm::length(velocity)) / (2.0 * field * 1048576.0);
  };
  const auto expectWithin = [&](const glm::dvec3& v, double field, const std::string& where) {
    const double slack = roundingBound(field) + 1e-6;  // and the float division's last bits
    for (int axis = 0; axis < 3; ++axis) {
      ASSERT_GE(v[axis], lowest[axis] - slack) << where << " axis " << axis;
      ASSERT_LE(v[axis], highest[axis] + slack) << where << " axis " << axis;
    }
  };

  const firn::SurfaceMesh mesh = readSurfacePly(folder / "out" / "frame_0001_surface.ply");
  ASSERT_GT(mesh.triangleCount(), 500u);
  ASSERT_EQ(mesh.velocitiesMPerS.size(), mesh.positionsM.size());
  for (std::size_t i = 0; i < mesh.velocitiesMPerS.size(); ++i) {
    expectWithin(glm::dvec3(mesh.velocitiesMPerS[i]), 0.5, "vertex " + std::to_string(i));
  }

  openvdb::io::File file((folder / "out" / "frame_0001.vdb").string());
  file.open();
  const openvdb::Vec3SGrid::Ptr v = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("v"));
  const openvdb::FloatGrid::Ptr density = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
  file.close();
  ASSERT_TRUE(v && density);
  EXPECT_EQ(v->getVectorType(), openvdb::VEC_CONTRAVARIANT_RELATIVE);
  EXPECT_NEAR(v->transform().voxelSize()[0], kVoxelM, 1e-9);
  // Every voxel of the density (f ≥ ½) has a velocity, and the velocity reaches past it (f ≥ 1%).
  for (auto voxel = density->cbeginValueOn(); voxel; ++voxel) {
    ASSERT_TRUE(v->tree().isValueOn(voxel.getCoord())) << voxel.getCoord();
  }
  EXPECT_GT(v->activeVoxelCount(), density->activeVoxelCount());
  for (auto voxel = v->cbeginValueOn(); voxel; ++voxel) {
    const openvdb::Vec3s value = *voxel;
    expectWithin(glm::dvec3(value[0], value[1], value[2]), 0.01, "voxel");
  }
}

// Deterministic output: every file two runs write (stats.csv and run.json aside, which record wall-clock times, and
// run.json the transfers' timing and the command line) is the same bytes: the particles (fixed-point sums), the mesh (integer splat, places fixed by a prefix scan), the VDB (its
// archive id derived from the content) and the surface's pictures.
TEST_F(SurfaceCli, TwoRunsWriteTheSameBytes) {
  const fs::path folder = freshDirectory("surface_twice");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  for (const char* run : {"a", "b"}) {
    const Result result = runFirn("run " + scene.string() + " --mesh --vdb --png --render surface --width 96 --height 64 --out " +
                                  (folder / run).string());
    ASSERT_EQ(result.exitCode, 0) << result.output;
  }
  int compared = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder / "a")) {
    const std::string name = entry.path().filename().string();
    if (name == "stats.csv" || name == "run.json") continue;
    EXPECT_EQ(fileBytes(entry.path()), fileBytes(folder / "b" / name)) << name;
    ++compared;
  }
  EXPECT_EQ(compared, 2 * 4) << "frames 0 and 1: point cache, surface mesh, VDB and picture";
}

// Bad surface settings are bad input naming the key, before anything is simulated: a value out of its range
// (the scene's rules), and a kernel too wide for the reconstruction cells (a rule of the particles' spacing).
TEST_F(SurfaceCli, BadSettingsExitTwoNamingTheKey) {
  const fs::path folder = freshDirectory("surface_bad");
  const std::string ball = kBallScene;
  const auto withSurface = [&](const std::string& surface) {
    return ball.substr(0, ball.rfind('}')) + R"(, "surface": )" + surface + "}";
  };
  const struct {
    const char* surface;
    const char* key;
    const char* problem;
  } cases[] = {
      {R"({ "resolution": 0 })", "surface.resolution", "[1, 8]"},
      {R"({ "smoothing": 1 })", "surface.smoothing", "[2, 6]"},
      {R"({ "iso": 1 })", "surface.iso", "(0, 1)"},
      {R"({ "iso_level": 0.5 })", "surface", "iso"},
      // 8 nodes per cell and 6 spacings of h/2: a kernel 24 reconstruction cells wide, twice the most.
      {R"({ "resolution": 8, "smoothing": 6 })", "surface.resolution", "at most 12"},
  };
  int index = 0;
  for (const auto& bad : cases) {
    const fs::path scene = writeScene(folder, "bad" + std::to_string(index) + ".json", withSurface(bad.surface));
    const fs::path out = folder / ("out" + std::to_string(index++));
    const Result result = runFirn("run " + scene.string() + " --render surface --png --out " + out.string());
    EXPECT_EQ(result.exitCode, 2) << result.output;
    EXPECT_NE(result.output.find(scene.string() + ": " + bad.key), std::string::npos) << result.output;
    EXPECT_NE(result.output.find(bad.problem), std::string::npos) << result.output;
    EXPECT_FALSE(fs::exists(out / "stats.csv")) << "nothing simulated: " << bad.surface;
  }
}

// A disk that fills while a cache is written: the write fails (a file-size limit makes it fail as a full disk
// would, with the limit's signal ignored so that write(2) reports EFBIG), the run stops with exit 2 naming the
// file, and neither the cache nor a part of it is left behind. The limit, 64 blocks (32 KiB in dash, Debian's
// /bin/sh, 64 KiB in bash), holds stats.csv but neither this ball's VDB cache (75 KB) nor its mesh (93 KB).
TEST_F(SurfaceCli, AFullDiskLeavesNoTruncatedCache) {
  const fs::path folder = freshDirectory("surface_full");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const struct {
    const char* option;
    const char* file;
    const char* what;
  } caches[] = {{"--vdb", "frame_0000.vdb", "VDB cache"}, {"--mesh", "frame_0000_surface.ply", "surface mesh"}};
  for (const auto& cache : caches) {
    const fs::path out = folder / (std::string("out") + cache.option);
    const Result result = runFirn("run " + scene.string() + " --frames 0 --no-ply " + cache.option + " --out " +
                                      out.string(),
                                  "trap '' XFSZ; ulimit -f 64;");
    EXPECT_EQ(result.exitCode, 2) << result.output;
    EXPECT_NE(result.output.find(cache.file + std::string(": cannot write ") + cache.what), std::string::npos)
        << result.output;
    EXPECT_TRUE(fs::exists(out / "stats.csv"));
    EXPECT_FALSE(fs::exists(out / cache.file));
    EXPECT_FALSE(fs::exists(out / (cache.file + std::string(".part"))));
  }
}

}  // namespace
