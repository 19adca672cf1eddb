// The moving objects of a run as files a DCC replays beside the snow (docs/command-line.md, bodies.csv and Object
// meshes): bodies.csv's row per frame for a keyframed collider, whose pose at a keyframe's time is the keyframe's;
// with --mesh, its mesh where that pose puts it; no rows for a collider that stays; and a resumed run's rows.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "Cli.h"
#include "MeshChecks.h"
#include "scene/Scene.h"
#include "scene/SceneObjects.h"
#include "voxelizer/Mesh.h"

namespace {

namespace fs = std::filesystem;
using firn::test::fileBytes;
using firn::test::freshDirectory;
using firn::test::readCsv;
using firn::test::Result;
using firn::test::runFirn;
using firn::test::writeScene;

// 1,536 particles of snow on a ground plane (colliders[0]) in a 16³ grid; a paddle (colliders[1], a box about its
// centre (0.4, 0.5, 0.4)) above the snow with keyframes at 0, 0.125 and 0.25 s, the times of frames 0, 2 and 4 at
// 16 frames a second; a sphere that stays (colliders[2]); and a sphere translating at 0.4 m/s (colliders[3]).
const char* const kPaddleScene = R"({
  "grid": { "cells": [16, 16, 16], "cell_size": 0.05 },
  "time": { "dt": 1e-3, "frame_rate": 16, "frames": 4 },
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "box", "min": [0.2, 0.1, 0.2], "max": [0.6, 0.25, 0.6], "material": "snow" } ],
  "colliders": [
    { "type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0] },
    { "type": "box", "min": [0.3, 0.45, 0.3], "max": [0.5, 0.55, 0.5], "boundary": "sticky",
      "keyframes": [ { "time_s": 0 },
                     { "time_s": 0.125, "translate": [0.05, -0.05, 0], "rotate_deg": [0, 90, 0] },
                     { "time_s": 0.25, "translate": [0.1, -0.05, 0.025], "rotate_deg": [30, 90, 0] } ] },
    { "type": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.05 },
    { "type": "sphere", "center": [0.15, 0.6, 0.15], "radius": 0.05, "velocity": [0.4, 0, 0] } ] })";

const glm::dvec3 kPivotM(0.4, 0.5, 0.4);
const glm::dvec3 kBallCentreM(0.15, 0.6, 0.15);

const std::vector<std::string> kHeader = {
    "frame",      "time_s",     "object",     "kind",         "x_m",          "y_m",
    "z_m",        "qw",         "qx",         "qy",           "qz",           "vx_m_per_s",
    "vy_m_per_s", "vz_m_per_s", "wx_rad_per_s", "wy_rad_per_s", "wz_rad_per_s", "fx_n",         "fy_n",
    "fz_n",       "work_j"};

double degrees(double deg) { return deg * glm::pi<double>() / 180; }

// R = R_z R_y R_x (docs/scene-format.md, rotate_deg) as a quaternion: q_y q_x, here without z.
glm::dquat turnYX(double yDeg, double xDeg) {
  return glm::angleAxis(degrees(yDeg), glm::dvec3(0, 1, 0)) * glm::angleAxis(degrees(xDeg), glm::dvec3(1, 0, 0));
}

struct CsvPose {
  glm::dvec3 positionM;
  glm::dquat orientation;
  glm::dvec3 velocityMPerS;
  glm::dvec3 angularVelocityRadPerS;
};

double number(const std::string& cell) { return std::strtod(cell.c_str(), nullptr); }

CsvPose poseOf(const std::vector<std::string>& row) {
  return {{number(row[4]), number(row[5]), number(row[6])},
          glm::dquat(number(row[7]), number(row[8]), number(row[9]), number(row[10])),
          {number(row[11]), number(row[12]), number(row[13])},
          {number(row[14]), number(row[15]), number(row[16])}};
}

// Poses are written as the shortest text that reads back as the same double, and the collider's pose at a keyframe's
// time is the keyframe's translation added to the pivot and its rotation as a quaternion (a matrix's, normalised):
// each within a few doubles' rounding of 1 (1e-12).
constexpr double kRoundingTolerance = 1e-12;

void expectPose(const CsvPose& pose, const glm::dvec3& positionM, const glm::dquat& orientation, const glm::dvec3& velocityMPerS,
                int frame) {
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(pose.positionM[axis], positionM[axis], kRoundingTolerance) << "frame " << frame << " axis " << axis;
    EXPECT_NEAR(pose.velocityMPerS[axis], velocityMPerS[axis], kRoundingTolerance) << "frame " << frame << " axis " << axis;
  }
  // q and −q are the same turn; the file keeps each object's sign continuous from frame to frame.
  const glm::dquat expected = glm::dot(pose.orientation, orientation) < 0 ? -orientation : orientation;
  for (int component = 0; component < 4; ++component) {
    EXPECT_NEAR(pose.orientation[component], expected[component], kRoundingTolerance)
        << "frame " << frame << " component " << component;
  }
}

// An object's mesh as the run writes it: binary PLY of float x y z and triangles, the header checked line by line.
struct ObjectMesh {
  std::vector<glm::dvec3> verticesM;
  std::vector<std::uint32_t> indices;
};

ObjectMesh readObjectPly(const fs::path& path, const std::string& comment) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::string> header;
  for (std::string line; std::getline(in, line) && line != "end_header";) header.push_back(line);
  EXPECT_EQ(header.size(), 9u) << path;
  if (header.size() != 9) return {};
  EXPECT_EQ(header[0], "ply");
  EXPECT_EQ(header[1], "format binary_little_endian 1.0");
  EXPECT_EQ(header[2], "comment written by Firn: " + comment);
  EXPECT_EQ(header[3].rfind("element vertex ", 0), 0u);
  EXPECT_EQ(header[4], "property float x");
  EXPECT_EQ(header[5], "property float y");
  EXPECT_EQ(header[6], "property float z");
  EXPECT_EQ(header[7].rfind("element face ", 0), 0u);
  EXPECT_EQ(header[8], "property list uchar uint vertex_indices");
  const std::size_t vertices = std::stoul(header[3].substr(15)), faces = std::stoul(header[7].substr(13));
  ObjectMesh mesh;
  for (std::size_t v = 0; v < vertices; ++v) {
    float xyz[3];
    in.read(reinterpret_cast<char*>(xyz), sizeof xyz);
    mesh.verticesM.emplace_back(xyz[0], xyz[1], xyz[2]);
  }
  firn::test::readPlyTriangles(in, faces, mesh.indices);
  return mesh;
}

// The run's files are 32-bit floats: within 0.8 m of the origin a coordinate rounds by at most 2⁻²⁵ m (3e-8 m),
// well inside the 1 µm a DCC's replay needs.
constexpr double kMeshToleranceM = 1e-6;

TEST(ObjectExportCli, KeyframedColliderHasARowPerFrameAtItsKeyframesPoses) {
  const fs::path folder = freshDirectory("object_export");
  const fs::path scene = writeScene(folder, "paddle.json", kPaddleScene);
  const fs::path out = folder / "out";
  const Result result = runFirn("run " + scene.string() + " --no-ply --mesh --out " + out.string());
  ASSERT_EQ(result.exitCode, 0) << result.output;

  const auto allRows = readCsv(out / "bodies.csv");
  ASSERT_EQ(allRows.size(), 11u) << "the header and frames 0 to 4 of the paddle and the rolling ball (the plane and "
                                    "the other sphere stay)";
  EXPECT_EQ(allRows[0], kHeader);
  // Per frame, the moving colliders in the scene's order.
  std::vector<std::vector<std::string>> rows = {allRows[0]};
  for (int frame = 0; frame <= 4; ++frame) {
    for (int object = 0; object < 2; ++object) {
      const std::vector<std::string>& row = allRows[std::size_t(2 * frame + object) + 1];
      ASSERT_EQ(row.size(), kHeader.size());
      EXPECT_EQ(row[0], std::to_string(frame));
      EXPECT_EQ(number(row[1]), frame / 16.0);
      EXPECT_EQ(row[2], object == 0 ? "colliders[1]" : "colliders[3]");
      EXPECT_EQ(row[3], "collider");
      if (object == 0) rows.push_back(row);
    }
    // The ball without keyframes: its centre moved by v t, unturned.
    expectPose(poseOf(allRows[std::size_t(2 * frame) + 2]), kBallCentreM + glm::dvec3(0.4, 0, 0) * (frame / 16.0),
               glm::dquat(1, 0, 0, 0), glm::dvec3(0.4, 0, 0), frame);
  }
  // At each keyframe's time the keyframe's pose, and the velocity of the segment it begins (none after the last).
  expectPose(poseOf(rows[1]), kPivotM, glm::dquat(1, 0, 0, 0), glm::dvec3(0.05, -0.05, 0) / 0.125, 0);
  expectPose(poseOf(rows[3]), kPivotM + glm::dvec3(0.05, -0.05, 0), turnYX(90, 0), glm::dvec3(0.05, 0, 0.025) / 0.125, 2);
  expectPose(poseOf(rows[5]), kPivotM + glm::dvec3(0.1, -0.05, 0.025), turnYX(90, 30), glm::dvec3(0.0), 4);
  // Between keyframes 0 and 1 it turns about y at 90° per 0.125 s.
  const CsvPose halfway = poseOf(rows[2]);
  EXPECT_NEAR(halfway.angularVelocityRadPerS.y, degrees(90) / 0.125, kRoundingTolerance);
  expectPose(halfway, kPivotM + glm::dvec3(0.025, -0.025, 0), turnYX(45, 0), glm::dvec3(0.05, -0.05, 0) / 0.125, 1);

  // The paddle's mesh at every frame, the rest mesh (its frame's, about the pivot) where the row's pose puts it; none
  // for the plane or the sphere.
  const firn::Scene parsed = firn::loadScene(scene);
  const firn::SceneObject paddle = firn::sceneObjects(parsed).at(1);
  ASSERT_EQ(paddle.name, "colliders[1]");
  for (int frame = 0; frame <= 4; ++frame) {
    char name[32];
    std::snprintf(name, sizeof name, "colliders_1_%04d.ply", frame);
    const ObjectMesh mesh = readObjectPly(out / name, "colliders[1] at frame " + std::to_string(frame));
    ASSERT_EQ(mesh.verticesM.size(), paddle.meshM.vertices.size()) << name;
    ASSERT_EQ(mesh.indices.size(), 3 * paddle.meshM.triangles.size()) << name;
    const CsvPose pose = poseOf(rows[std::size_t(frame) + 1]);
    for (std::size_t v = 0; v < mesh.verticesM.size(); ++v) {
      const glm::dvec3 expectedM = pose.positionM + pose.orientation * paddle.meshM.vertices[v];
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_NEAR(mesh.verticesM[v][axis], expectedM[axis], kMeshToleranceM) << name << " vertex " << v;
      }
    }
    for (std::size_t t = 0; t < paddle.meshM.triangles.size(); ++t) {
      for (int corner = 0; corner < 3; ++corner) EXPECT_EQ(mesh.indices[3 * t + std::size_t(corner)], paddle.meshM.triangles[t][corner]);
    }
  }
  // Frame 0 is the box as the scene gives it.
  const ObjectMesh rest = readObjectPly(out / "colliders_1_0000.ply", "colliders[1] at frame 0");
  for (const glm::dvec3& vertexM : rest.verticesM) {
    EXPECT_NEAR(std::abs(vertexM.x - 0.4), 0.1, kMeshToleranceM);
    EXPECT_NEAR(std::abs(vertexM.y - 0.5), 0.05, kMeshToleranceM);
    EXPECT_NEAR(std::abs(vertexM.z - 0.4), 0.1, kMeshToleranceM);
  }
  EXPECT_TRUE(fs::exists(out / "colliders_3_0004.ply"));
  EXPECT_FALSE(fs::exists(out / "colliders_0_0000.ply"));
  EXPECT_FALSE(fs::exists(out / "colliders_2_0000.ply"));
}

// Without a rigid body or a collider that moves there is nothing to replay: no bodies.csv and no object meshes.
TEST(ObjectExportCli, SceneWithoutMovingObjectsWritesNoBodiesFile) {
  const fs::path folder = freshDirectory("object_export_static");
  const fs::path scene = writeScene(folder, "still.json", R"({
    "grid": { "cells": [16, 16, 16], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 16, "frames": 4 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "box", "min": [0.2, 0.1, 0.2], "max": [0.6, 0.25, 0.6], "material": "snow" } ],
    "colliders": [ { "type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0] },
                   { "type": "box", "min": [0.3, 0.45, 0.3], "max": [0.5, 0.55, 0.5] } ] })");
  const fs::path out = folder / "out";
  const Result result = runFirn("run " + scene.string() + " --frames 0 --no-ply --mesh --out " + out.string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  EXPECT_TRUE(fs::exists(out / "stats.csv"));
  EXPECT_TRUE(fs::exists(out / "frame_0000_surface.ply"));
  EXPECT_FALSE(fs::exists(out / "bodies.csv"));
  EXPECT_FALSE(fs::exists(out / "colliders_1_0000.ply"));
}

// Resumed into its own folder from the checkpoint of frame 2, the run keeps the rows of frames 0 and 1 and writes
// frames 2 to 4 once each: the file is the uninterrupted run's, byte for byte (the poses are the scene's motion at
// the same times, and the quaternions' signs continue from the kept rows).
TEST(ObjectExportCli, ResumeInTheRunsOwnFolderKeepsTheEarlierRowsOnce) {
  const fs::path folder = freshDirectory("object_export_resume");
  const fs::path scene = writeScene(folder, "paddle.json", kPaddleScene);
  const fs::path out = folder / "out";
  Result result = runFirn("run " + scene.string() + " --no-ply --checkpoint-every 2 --out " + out.string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const std::string uninterrupted = fileBytes(out / "bodies.csv");
  result = runFirn("run " + scene.string() + " --no-ply --resume " + (out / "checkpoint_0002.firn").string() +
                   " --out " + out.string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  EXPECT_EQ(fileBytes(out / "bodies.csv"), uninterrupted);
  EXPECT_EQ(readCsv(out / "bodies.csv").size(), 11u);
}

}  // namespace
