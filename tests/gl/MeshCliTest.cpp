// Meshes and point clouds from the command line: `firn voxelize`, and scenes with mesh and points bodies run
// end to end (docs/command-line.md: `firn voxelize MESH --spacing S --out FILE.ply`; docs/scene-format.md:
// `"shape": "mesh"`, `"shape": "points"`).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "Cli.h"
#include "io/Ply.h"

namespace {

namespace fs = std::filesystem;
using firn::test::freshDirectory;
using firn::test::Result;
using firn::test::runFirn;
using firn::test::writeScene;

constexpr double pi = 3.14159265358979323846;

// assets/meshes/torus.obj: R = 0.3 m, r = 0.1 m, 64 × 32 segments.
const fs::path kTorus = fs::path(FIRN_SOURCE_DIR) / "assets/meshes/torus.obj";

TEST(Voxelize, TorusMeshBecomesACloudOfItsVolume) {
  const fs::path out = freshDirectory("voxelize") / "torus.ply";
  const Result result = runFirn("voxelize " + kTorus.string() + " --spacing 0.01 --out " + out.string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const firn::PointCache cloud = firn::readPly(out);
  // The 32-segment tube's chords cut 1 − sin(2π/32)/(2π/32) = 0.6% of its area, and the lattice count of a
  // shape 20 spacings thick is good to about 1%: the issue's 3% holds with room.
  const double volumeM3 = double(cloud.size()) * 1e-6;
  EXPECT_NEAR(volumeM3 / (2 * pi * pi * 0.3 * 0.1 * 0.1), 1.0, 0.03) << cloud.size() << " particles";
  // Each particle carries the default density's share: 400 kg/m³ · s³.
  EXPECT_FLOAT_EQ(cloud.massesKg.front(), 4e-4f);
  EXPECT_NE(result.output.find("particles at spacing 0.01 m"), std::string::npos) << result.output;
}

TEST(Voxelize, PoissonDiskGivesTheSameVolumeAsTheLattice) {
  const fs::path out = freshDirectory("voxelize_poisson") / "torus.ply";
  const Result result = runFirn("voxelize " + kTorus.string() + " --cell-size 0.02 --particles-per-cell 8 " +
                                "--sampler poisson_disk --scale 0.5 --translate 1,1,1 --out " + out.string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const firn::PointCache cloud = firn::readPly(out);
  double massKg = 0;
  for (float m : cloud.massesKg) massKg += m;
  // Scaled by 0.5: R = 0.15 m, r = 0.05 m, 10 spacings of 1 cm across the tube; 3% as above.
  EXPECT_NEAR(massKg / (400 * 2 * pi * pi * 0.15 * 0.05 * 0.05), 1.0, 0.03);
  for (const glm::vec3& p : cloud.positionsM) {
    const double tubeDistanceM = std::hypot(std::hypot(p.x - 1.0, p.z - 1.0) - 0.15, p.y - 1.0);
    ASSERT_LE(tubeDistanceM, 0.05 + 1e-4) << "a particle outside the torus";
  }
}

TEST(Voxelize, BadInputIsExitTwoNamingTheProblem) {
  const fs::path folder = freshDirectory("voxelize_bad");
  Result result = runFirn("voxelize " + (folder / "absent.obj").string() + " --spacing 0.01 --out x.ply");
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_NE(result.output.find("absent.obj"), std::string::npos) << result.output;

  result = runFirn("voxelize " + kTorus.string() + " --out " + (folder / "x.ply").string());
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_NE(result.output.find("--spacing"), std::string::npos) << result.output;

  writeScene(folder, "broken.stl", "solid nothing\nthis is not an STL file\n");
  result = runFirn("voxelize " + (folder / "broken.stl").string() + " --spacing 0.01 --out " + (folder / "x.ply").string());
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_NE(result.output.find("broken.stl"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(folder / "x.ply"));
}

// A torus of snow (mesh body, 0.15 m ring) dropped on a ground plane, and the same particles as a points body
// (the cloud `firn voxelize` wrote): both run, and carry the cloud's particles and mass.
TEST(MeshScenes, MeshAndPointsBodiesRun) {
  const fs::path folder = freshDirectory("mesh_scene");
  const std::string common = R"(
    "grid": { "cells": [40, 24, 40], "cell_size": 0.02 },
    "time": { "dt": 5e-4, "frame_rate": 50, "frames": 2 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "colliders": [ { "type": "plane", "point": [0, 0.06, 0], "normal": [0, 1, 0], "boundary": "slip" } ],)";
  const fs::path meshScene = writeScene(folder, "mesh.json", "{" + common + R"(
    "bodies": [ { "shape": "mesh", "path": ")" + kTorus.string() + R"(", "scale": 0.5, "rotate_deg": [0, 45, 0],
                  "translate": [0.4, 0.2, 0.4], "material": "snow", "particles_per_cell": 4 } ] })");
  Result result = runFirn("run " + meshScene.string() + " --out " + (folder / "mesh").string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const firn::PointCache meshFrame = firn::readPly(folder / "mesh" / "frame_0002.ply");
  EXPECT_GT(meshFrame.size(), 1000u);

  // The same torus through `firn voxelize`, then as a points body taking its particles and masses as they are.
  result = runFirn("voxelize " + kTorus.string() + " --cell-size 0.02 --particles-per-cell 4 --scale 0.5 " +
                   "--translate 0.4,0.2,0.4 --out " + (folder / "torus.ply").string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const firn::PointCache cloud = firn::readPly(folder / "torus.ply");
  const fs::path pointsScene = writeScene(folder, "points.json", "{" + common + R"(
    "bodies": [ { "shape": "points", "path": "torus.ply", "material": "snow" } ] })");
  result = runFirn("run " + pointsScene.string() + " --out " + (folder / "points").string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const firn::PointCache pointsFrame = firn::readPly(folder / "points" / "frame_0002.ply");
  ASSERT_EQ(pointsFrame.size(), cloud.size());
  double cloudKg = 0, frameKg = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    cloudKg += cloud.massesKg[i];
    frameKg += pointsFrame.massesKg[i];
  }
  EXPECT_DOUBLE_EQ(frameKg, cloudKg);  // masses are carried, never changed
}

TEST(MeshScenes, MissingMeshIsExitTwoNamingThePath) {
  const fs::path folder = freshDirectory("mesh_missing");
  const fs::path scene = writeScene(folder, "scene.json", R"({
    "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 50, "frames": 1 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "mesh", "path": "meshes/gone.obj", "material": "snow" } ] })");
  const Result result = runFirn("run " + scene.string() + " --out " + (folder / "out").string());
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_NE(result.output.find("bodies[0].path"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find((folder / "meshes/gone.obj").string()), std::string::npos) << result.output;
}

}  // namespace
