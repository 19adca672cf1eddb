// The surface's settings and files without a GPU: the scene's "surface" section, the mesh PLY as another reader
// (assimp, as Blender's and Houdini's importers do) sees it, and the VDB writer's bytes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>

#include <openvdb/openvdb.h>

#include "io/SurfaceMesh.h"
#include "io/Vdb.h"
#include "scene/Scene.h"
#include "voxelizer/Mesh.h"
#include "support/TestFiles.h"

namespace {

namespace fs = std::filesystem;
using firn::test::fileBytes;
using firn::test::freshDirectory;

const std::string kScene = R"({
  "grid": { "cells": [16, 16, 16], "cell_size": 0.05 },
  "time": { "dt": 1e-3 },
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "sphere", "center": [0.4, 0.4, 0.4], "radius": 0.1, "material": "snow" } ])";

// A unit tetrahedron, counter-clockwise seen from outside.
firn::SurfaceMesh tetrahedron() {
  firn::SurfaceMesh mesh;
  mesh.positionsM = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const glm::vec3& p : mesh.positionsM) mesh.normals.push_back(glm::normalize(p - glm::vec3(0.25f)));
  mesh.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  return mesh;
}

TEST(SurfaceSection, DefaultsAndValues) {
  const firn::Scene defaults = firn::parseScene(kScene + "}", "surface.json");
  EXPECT_EQ(defaults.surface.resolution, 2);
  EXPECT_EQ(defaults.surface.smoothing, 3);
  EXPECT_EQ(defaults.surface.iso, 0.5);
  const firn::Scene given =
      firn::parseScene(kScene + R"(, "surface": { "resolution": 3, "smoothing": 2.5, "iso": 0.4 } })", "surface.json");
  EXPECT_EQ(given.surface.resolution, 3);
  EXPECT_EQ(given.surface.smoothing, 2.5);
  EXPECT_EQ(given.surface.iso, 0.4);
}

TEST(MeshPly, AssimpReadsTheMeshItWrites) {
  const fs::path path = freshDirectory("ply") / "tetrahedron.ply";
  firn::writeMeshPly(path, tetrahedron());
  const firn::voxelizer::TriangleMesh read = firn::voxelizer::loadMesh(path);
  ASSERT_EQ(read.triangles.size(), 4u);
  // assimp may give each triangle its own corners; the corners it reads are the tetrahedron's.
  for (const glm::uvec3& triangle : read.triangles) {
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 corner = read.vertices[triangle[k]];
      EXPECT_NEAR(corner.x + corner.y + corner.z, glm::length(corner) > 0 ? 1.0 : 0.0, 1e-6);
    }
  }
  EXPECT_FALSE(fs::exists(path.string() + ".part"));
}

TEST(MeshPly, RefusesWhatItMustNotWrite) {
  const fs::path folder = freshDirectory("ply_bad");
  firn::SurfaceMesh notFinite = tetrahedron();
  notFinite.positionsM[2].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(firn::writeMeshPly(folder / "nan.ply", notFinite), std::invalid_argument);
  firn::SurfaceMesh dangling = tetrahedron();
  dangling.indices[5] = 4;
  EXPECT_THROW(firn::writeMeshPly(folder / "dangling.ply", dangling), std::invalid_argument);
  EXPECT_FALSE(fs::exists(folder / "nan.ply"));
  EXPECT_FALSE(fs::exists(folder / "dangling.ply"));
}

// The same frame gives the same bytes (OpenVDB's random archive id is replaced by one derived from the content),
// and OpenVDB reads the file back: the density only where it reaches the iso level, on the lattice's voxels.
TEST(Vdb, SameFrameSameBytesAndReadBack) {
  firn::VdbFrame frame;
  frame.density.originM = {1.0, 2.0, 3.0};
  frame.density.spacingM = 0.1;
  frame.density.firstNode = {-2, 0, 5};
  frame.density.nodeCounts = {3, 3, 3};
  frame.density.values.assign(27, 0.25f);
  frame.density.values[13] = 1.0f;  // the middle node, (−1, 1, 6)
  frame.isoLevel = 0.5f;
  frame.surface = tetrahedron();
  frame.frame = 7;
  frame.timeS = 0.25;
  const fs::path folder = freshDirectory("vdb");
  firn::writeVdb(folder / "a.vdb", frame);
  firn::writeVdb(folder / "b.vdb", frame);
  EXPECT_EQ(fileBytes(folder / "a.vdb"), fileBytes(folder / "b.vdb"));

  openvdb::initialize();
  openvdb::io::File file((folder / "a.vdb").string());
  file.open();
  const openvdb::FloatGrid::Ptr density = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
  const openvdb::FloatGrid::Ptr surface = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("surface"));
  EXPECT_FALSE(file.hasGrid("v")) << "no velocities given, no v grid";
  file.close();
  ASSERT_TRUE(density && surface);
  EXPECT_EQ(density->activeVoxelCount(), 1u);
  EXPECT_EQ(density->tree().getValue(openvdb::Coord(-1, 1, 6)), 1.0f);
  const openvdb::Vec3d middle = density->transform().indexToWorld(openvdb::Coord(-1, 1, 6));
  EXPECT_NEAR((middle - openvdb::Vec3d(0.9, 2.1, 3.6)).length(), 0.0, 1e-12);
  EXPECT_EQ(density->metaValue<int>("frame"), 7);
  EXPECT_EQ(density->metaValue<float>("iso_level"), 0.5f);
  // The tetrahedron's inside, (0.2, 0.2, 0.2), is negative; outside it positive.
  const openvdb::Coord inside = surface->transform().worldToIndexCellCentered(openvdb::Vec3d(0.2, 0.2, 0.2));
  const openvdb::Coord outside = surface->transform().worldToIndexCellCentered(openvdb::Vec3d(0.9, 0.9, 0.9));
  EXPECT_LT(surface->tree().getValue(inside), 0.0f);
  EXPECT_GT(surface->tree().getValue(outside), 0.0f);
}

// With velocities the mesh's vertices carry vx vy vz after the normals, and the header says so.
TEST(MeshPly, VelocitiesFollowTheNormals) {
  firn::SurfaceMesh mesh = tetrahedron();
  mesh.velocitiesMPerS = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {-1, -2, -3}};
  const fs::path folder = freshDirectory("ply_velocity");
  firn::writeMeshPly(folder / "moving.ply", mesh);
  const std::string bytes = fileBytes(folder / "moving.ply");
  const std::size_t body = bytes.find("end_header\n") + std::string("end_header\n").size();
  EXPECT_NE(bytes.find("property float nz\nproperty float vx\nproperty float vy\nproperty float vz\nelement face 4\n"),
            std::string::npos);
  ASSERT_EQ(bytes.size(), body + 4 * 9 * sizeof(float) + 4 * 13);
  float last[3];
  std::memcpy(last, bytes.data() + body + (3 * 9 + 6) * sizeof(float), sizeof last);
  EXPECT_EQ(last[0], -1.0f);
  EXPECT_EQ(last[2], -3.0f);
  mesh.velocitiesMPerS.pop_back();
  EXPECT_THROW(firn::writeMeshPly(folder / "ragged.ply", mesh), std::invalid_argument);
  EXPECT_FALSE(fs::exists(folder / "ragged.ply"));
}

// The v grid: a vector grid of the velocities at the voxels where the density reaches kVdbVelocityMinimumDensity,
// beyond the density's own voxels (those at the iso level), on the same transform.
TEST(Vdb, VelocityGridWhereTheDensityReachesOnePercent) {
  firn::VdbFrame frame;
  frame.density.spacingM = 0.1;
  frame.density.nodeCounts = {3, 1, 1};
  frame.density.values = {0.005f, 0.02f, 0.9f};  // below 1%, above it, above the iso level
  frame.velocityMPerS = {{9, 9, 9}, {0.5f, -1, 2}, {0.25f, 0, -4}};
  frame.surface = tetrahedron();
  const fs::path folder = freshDirectory("vdb_velocity");
  firn::writeVdb(folder / "v.vdb", frame);
  openvdb::initialize();
  openvdb::io::File file((folder / "v.vdb").string());
  file.open();
  const openvdb::Vec3SGrid::Ptr v = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("v"));
  file.close();
  ASSERT_TRUE(v);
  EXPECT_EQ(v->getVectorType(), openvdb::VEC_CONTRAVARIANT_RELATIVE);
  EXPECT_EQ(v->activeVoxelCount(), 2u);
  EXPECT_FALSE(v->tree().isValueOn(openvdb::Coord(0, 0, 0)));
  EXPECT_EQ(v->tree().getValue(openvdb::Coord(1, 0, 0)), openvdb::Vec3s(0.5f, -1, 2));
  EXPECT_EQ(v->tree().getValue(openvdb::Coord(2, 0, 0)), openvdb::Vec3s(0.25f, 0, -4));
  EXPECT_EQ(v->metaValue<std::string>("units"), "meters");
  frame.velocityMPerS.pop_back();
  EXPECT_THROW(firn::writeVdb(folder / "ragged.vdb", frame), std::invalid_argument);
}

}  // namespace
