// Mesh colliders and rigid bodies in scenes (docs/scene-format.md, colliders and rigid_bodies): files found
// relative to the scene and placed, masses and inertia derived from the shape and a mass or density, their distance
// fields sized, and every bad key an InputError naming it.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "Error.h"
#include "scene/FieldLattice.h"
#include "scene/Scene.h"
#include "sim/SceneUpload.h"
#include "support/TestFiles.h"
#include "voxelizer/Mesh.h"

namespace firn {
namespace {

using Json = nlohmann::ordered_json;

constexpr double pi = 3.14159265358979323846;
// Closed forms and Eberly's integrals of a cube agree to a few ε of the largest term.
constexpr double kExactRelative = 1e-12;

// The unit cube [0, 1]³, faces counter-clockwise seen from outside; `open` leaves the top face out.
std::string cubeObj(bool open = false) {
  std::string obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
  obj += "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 4 1 5\nf 4 5 8\n";
  if (!open) obj += "f 3 4 8\nf 3 8 7\n";
  return obj;
}

class SceneRigidBodies : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = test::freshDirectory("scene_rigid_bodies");
    std::filesystem::create_directories(folder_ / "meshes");
    std::ofstream(folder_ / "meshes/cube.obj") << cubeObj();
    std::ofstream(folder_ / "meshes/open.obj") << cubeObj(true);
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }

  // A scene on a 1.28 m grid of 2 cm cells (interior 0.04 to 1.24 m) with one body of snow.
  static Json baseScene() {
    return Json::parse(R"({
      "grid": { "cells": [64, 64, 64], "cell_size": 0.02 },
      "time": { "dt": 1e-3, "frame_rate": 30, "frames": 1 },
      "materials": { "snow": { "preset": "stomakhin" } },
      "bodies": [ { "shape": "sphere", "center": [0.64, 1.0, 0.64], "radius": 0.1, "material": "snow" } ]
    })");
  }
  static Json withRigidBodies(const std::string& bodies) {
    Json scene = baseScene();
    scene["rigid_bodies"] = Json::parse(bodies);
    return scene;
  }

  std::filesystem::path sceneFile() const { return folder_ / "scene.json"; }
  Scene parse(const Json& scene) const { return parseScene(scene.dump(), sceneFile()); }

  // The message must read "<file>: <key path>: <problem>" and the problem must say `problemFragment`.
  void expectError(const Json& scene, const std::string& keyPath, const std::string& problemFragment) const {
    try {
      parse(scene);
      ADD_FAILURE() << "expected an InputError for " << scene.dump();
    } catch (const InputError& error) {
      EXPECT_EQ(error.code(), ExitCode::BadInput);
      const std::string message = error.what();
      const std::string prefix = sceneFile().string() + ": " + keyPath + ": ";
      EXPECT_EQ(message.compare(0, prefix.size(), prefix), 0) << "message: " << message << "\nexpected prefix: " << prefix;
      EXPECT_NE(message.find(problemFragment, prefix.size()), std::string::npos)
          << "message: " << message << "\nexpected to contain: " << problemFragment;
    }
  }

  std::filesystem::path folder_;
};

void expectNear(const glm::dvec3& actual, const glm::dvec3& expected, double tolerance) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(actual[i], expected[i], tolerance) << "component " << i;
}

void expectDiagonal(const glm::dmat3& actual, const glm::dvec3& diagonal) {
  for (int column = 0; column < 3; ++column) {
    for (int row = 0; row < 3; ++row) {
      const double expected = row == column ? diagonal[row] : 0.0;
      EXPECT_NEAR(actual[column][row], expected, kExactRelative * glm::length(diagonal))
          << "row " << row << ", column " << column;
    }
  }
}

TEST_F(SceneRigidBodies, MeshColliderIsLoadedPlacedAndItsFieldSized) {
  Json scene = baseScene();
  scene["colliders"] = Json::parse(R"([
    { "type": "mesh", "path": "meshes/cube.obj", "scale": 0.21, "translate": [0.5, 0.1, 0.5], "resolution": 2.5,
      "friction": 0.4, "boundary": "sticky" },
    { "type": "mesh", "path": "meshes/cube.obj", "rotate_deg": [0, 45, 0], "scale": 0.1,
      "translate": [0.2, 0.2, 0.2], "pivot": [0, 0, 0], "velocity": [0, 0, 1] } ])");
  const Scene parsed = parse(scene);
  ASSERT_EQ(parsed.colliders.size(), 2u);
  const Collider& cube = parsed.colliders[0];
  EXPECT_EQ(cube.shape, ColliderShape::Mesh);
  EXPECT_EQ(cube.path, "meshes/cube.obj");
  EXPECT_EQ(cube.resolvedPath, folder_ / "meshes/cube.obj");
  EXPECT_DOUBLE_EQ(cube.fieldResolution, 2.5);
  EXPECT_DOUBLE_EQ(cube.friction, 0.4);
  EXPECT_EQ(cube.boundary, Boundary::Sticky);
  ASSERT_NE(cube.mesh, nullptr);
  EXPECT_EQ(cube.mesh->triangles.size(), 12u);
  // Placed: 0.21 m on a side from (0.5, 0.1, 0.5); the pivot defaults to the centre of that box.
  expectNear(cube.pivotM, glm::dvec3(0.605, 0.205, 0.605), 1e-15);

  const Collider& turned = parsed.colliders[1];
  EXPECT_DOUBLE_EQ(turned.fieldResolution, 2);  // the default
  // The unit cube scaled to 0.1 m, turned 45° about y, then moved by (0.2, 0.2, 0.2): its box is 0.1 √2 m wide in x
  // and z, centred 0.05 √2 m along x from the moved origin corner. Rounding of the turn: a few units of 2⁻⁵².
  const voxelizer::Bounds turnedBox = voxelizer::bounds(*turned.mesh);
  expectNear(turnedBox.maxM - turnedBox.minM, glm::dvec3(0.1 * std::sqrt(2.0), 0.1, 0.1 * std::sqrt(2.0)), 1e-15);
  expectNear(0.5 * (turnedBox.minM + turnedBox.maxM), glm::dvec3(0.2 + 0.05 * std::sqrt(2.0), 0.25, 0.2), 1e-15);
  expectNear(turned.pivotM, glm::dvec3(0.0), 0);
  expectNear(turned.velocityMPerS, glm::dvec3(0, 0, 1), 0);

  // Spacing 0.02 / 2.5 = 0.008 m over 0.21 m and a margin of 3 cells (0.06 m) each side: ⌈0.33 / 0.008⌉ + 1 = 43.
  const std::vector<FieldLattice> fields = fieldLattices(parsed);
  ASSERT_EQ(fields.size(), 2u);
  EXPECT_EQ(fields[0].object, "colliders[0]");
  EXPECT_EQ(fields[0].path, "meshes/cube.obj");
  EXPECT_DOUBLE_EQ(fields[0].spacingM, 0.008);
  EXPECT_DOUBLE_EQ(fields[0].marginM, 0.06);
  expectNear(fields[0].samples, glm::dvec3(43), 0);
  // Two floats per sample (φ and its nearest triangle) and 33 per triangle of the 12.
  EXPECT_DOUBLE_EQ(fields[0].bytes(), 4.0 * (2.0 * 43 * 43 * 43 + 33 * 12));
  // What the budget counts is what is baked, to the sample.
  for (std::size_t i = 0; i < 2; ++i) {
    const Collider& collider = parsed.colliders[i];
    const voxelizer::DistanceField baked = bakeField(*collider.mesh, parsed.grid, collider.fieldResolution);
    expectNear(glm::dvec3(baked.samples), fields[i].samples, 0);
  }
}

TEST_F(SceneRigidBodies, RigidBodiesTakeTheirMassAndInertiaFromTheShape) {
  const Scene parsed = parse(withRigidBodies(R"([
    { "shape": "sphere", "center": [0.3, 0.3, 0.3], "radius": 0.1, "density": 500, "velocity": [1, 0, 0] },
    { "shape": "box", "center": [0.8, 0.3, 0.3], "size": [0.1, 0.2, 0.3], "rotate_deg": [0, 0, 30], "mass": 6,
      "angular_velocity": [0, 2, 0], "friction": 0.1, "boundary": "slip" },
    { "shape": "mesh", "path": "meshes/cube.obj", "scale": 0.2, "translate": [0.5, 0.7, 0.5], "density": 1000,
      "resolution": 4 } ])"));
  ASSERT_EQ(parsed.rigidBodies.size(), 3u);

  const RigidBody& ball = parsed.rigidBodies[0];
  EXPECT_EQ(ball.shape, RigidShape::Sphere);
  const double ballVolumeM3 = 4.0 / 3.0 * pi * 0.001;
  EXPECT_NEAR(ball.volumeM3, ballVolumeM3, kExactRelative * ballVolumeM3);
  EXPECT_NEAR(ball.massKg, 500 * ballVolumeM3, kExactRelative * ball.massKg);
  expectNear(ball.centerOfMassM, glm::dvec3(0.3), 0);
  expectDiagonal(ball.inertiaKgM2, glm::dvec3(0.4 * ball.massKg * 0.01));  // 2/5 m r²
  expectNear(ball.velocityMPerS, glm::dvec3(1, 0, 0), 0);
  EXPECT_DOUBLE_EQ(ball.friction, 0.3);
  EXPECT_EQ(ball.boundary, Boundary::Separate);

  // m/12 diag(b² + c², a² + c², a² + b²) along its own edges, whatever its turn.
  const RigidBody& block = parsed.rigidBodies[1];
  EXPECT_EQ(block.shape, RigidShape::Box);
  expectNear(block.halfExtentsM, glm::dvec3(0.05, 0.1, 0.15), 1e-17);
  expectNear(block.rotateDeg, glm::dvec3(0, 0, 30), 0);
  EXPECT_NEAR(block.volumeM3, 0.006, kExactRelative * 0.006);
  EXPECT_DOUBLE_EQ(block.massKg, 6);
  expectDiagonal(block.inertiaKgM2, 0.5 * glm::dvec3(0.04 + 0.09, 0.01 + 0.09, 0.01 + 0.04));
  expectNear(block.angularVelocityRadPerS, glm::dvec3(0, 2, 0), 0);
  EXPECT_DOUBLE_EQ(block.friction, 0.1);
  EXPECT_EQ(block.boundary, Boundary::Slip);

  // A cube of 0.2 m at 1000 kg/m³: 8 kg about its centre, m/6 · 0.04 on each axis.
  const RigidBody& cube = parsed.rigidBodies[2];
  EXPECT_EQ(cube.shape, RigidShape::Mesh);
  EXPECT_EQ(cube.resolvedPath, folder_ / "meshes/cube.obj");
  EXPECT_DOUBLE_EQ(cube.fieldResolution, 4);
  EXPECT_NEAR(cube.volumeM3, 0.008, kExactRelative * 0.008);
  EXPECT_NEAR(cube.massKg, 8, kExactRelative * 8);
  expectNear(cube.centerOfMassM, glm::dvec3(0.6, 0.8, 0.6), kExactRelative);
  expectDiagonal(cube.inertiaKgM2, glm::dvec3(8.0 / 6 * 0.04));

  const std::vector<FieldLattice> fields = fieldLattices(parsed);
  ASSERT_EQ(fields.size(), 1u);
  EXPECT_EQ(fields[0].object, "rigid_bodies[2]");
  EXPECT_DOUBLE_EQ(fields[0].spacingM, 0.005);
}

// A body's contact probes (sim/SceneUpload.h, bodyProbes): a box's mesh, 8 vertices and 12 triangles, has the analytic
// box's 26 — its support points are its corners and its edges' midpoints are the box's edges' midpoints and, the
// faces' diagonals being edges too, its faces' centres — to the rounding of its centre of mass (1e-12 of its size). A
// fine mesh (the boulder: 642 vertices) keeps its support points alone, each a vertex, no more than
// kMeshProbeDirections.
TEST_F(SceneRigidBodies, AMeshBoxHasTheAnalyticBoxsContactProbes) {
  const std::string boulder = std::string(FIRN_SOURCE_DIR) + "/assets/meshes/boulder.obj";
  const Scene parsed = parse(withRigidBodies(R"([
    { "shape": "box", "center": [0.3, 0.3, 0.3], "size": [0.2, 0.2, 0.2], "density": 500 },
    { "shape": "mesh", "path": "meshes/cube.obj", "scale": 0.2, "translate": [0.5, 0.5, 0.5], "density": 500 },
    { "shape": "mesh", "path": ")" + boulder + R"(", "scale": 0.1, "translate": [1.0, 0.3, 1.0], "density": 500 } ])"));
  const auto sorted = [](std::vector<glm::dvec3> points) {
    std::sort(points.begin(), points.end(), [](const glm::dvec3& a, const glm::dvec3& b) {
      const glm::dvec3 r = glm::round(a * 1e6), s = glm::round(b * 1e6);
      return std::tie(r.x, r.y, r.z) < std::tie(s.x, s.y, s.z);
    });
    return points;
  };
  const std::vector<glm::dvec3> box = sorted(bodyProbes(parsed.rigidBodies[0]));
  const std::vector<glm::dvec3> mesh = sorted(bodyProbes(parsed.rigidBodies[1]));
  ASSERT_EQ(box.size(), 26u);
  ASSERT_EQ(mesh.size(), box.size());
  for (std::size_t k = 0; k < box.size(); ++k) expectNear(mesh[k], box[k], 1e-12 * 0.2);

  const RigidBody& rock = parsed.rigidBodies[2];
  const std::vector<glm::dvec3> rockProbes = bodyProbes(rock);
  EXPECT_LE(rockProbes.size(), std::size_t(kMeshProbeDirections));
  for (const glm::dvec3& probe : rockProbes) {
    const glm::dvec3 point = probe + rock.centerOfMassM;
    EXPECT_NE(std::find(rock.mesh->vertices.begin(), rock.mesh->vertices.end(), point), rock.mesh->vertices.end());
  }
}

TEST_F(SceneRigidBodies, EachBadKeyIsNamed) {
  const std::string sphere = R"("shape": "sphere", "center": [0.3, 0.3, 0.3], "radius": 0.1)";
  const auto body = [&](const std::string& more) { return withRigidBodies("[{" + sphere + ", " + more + "}]"); };
  expectError(body(R"("mass": 2, "density": 500)"), "rigid_bodies[0].density", "\"mass\" or \"density\", not both");
  expectError(withRigidBodies("[{" + sphere + "}]"), "rigid_bodies[0].mass", "required key is missing");
  expectError(body(R"("mass": 0)"), "rigid_bodies[0].mass", "must be greater than 0");
  expectError(body(R"("density": 500, "friction": -1)"), "rigid_bodies[0].friction", "must be at least 0");
  expectError(body(R"("density": 500, "boundary": "glue")"), "rigid_bodies[0].boundary", "must be one of");
  expectError(body(R"("density": 500, "colour": "red")"), "rigid_bodies[0].colour", "unknown key");
  expectError(body(R"("density": 1e300)"), "rigid_bodies[0].density", "32-bit floats");
  expectError(withRigidBodies(R"([{ "shape": "cone", "mass": 1 }])"), "rigid_bodies[0].shape", "must be one of");
  expectError(withRigidBodies(R"([{ "shape": "box", "center": [0.3, 0.3, 0.3], "size": [0.1, 0, 0.1], "mass": 1 }])"),
              "rigid_bodies[0].size", "longer than 0");
  expectError(withRigidBodies(R"([{ "shape": "box", "center": [0.3, 0.3, 0.3], "min": [0, 0, 0], "mass": 1 }])"),
              "rigid_bodies[0].min", "unknown key");
  expectError(withRigidBodies(R"([{ "shape": "mesh", "path": "meshes/cube.obj", "scale": 0.1,
                                    "translate": [0.3, 0.3, 0.3], "mass": 1, "resolution": 20 }])"),
              "rigid_bodies[0].resolution", "must be in [0.5, 8]");
  expectError(withRigidBodies(R"([{ "shape": "mesh", "path": "meshes/open.obj", "scale": 0.1,
                                    "translate": [0.3, 0.3, 0.3], "mass": 1 }])"),
              "rigid_bodies[0].path", "open");
  expectError(withRigidBodies(R"([{ "shape": "mesh", "path": "meshes/absent.obj", "mass": 1 }])"),
              "rigid_bodies[0].path", (folder_ / "meshes/absent.obj").string());
  expectError(withRigidBodies(R"([{ "shape": "sphere", "center": [0.05, 0.6, 0.6], "radius": 0.1, "mass": 1 }])"),
              "rigid_bodies[0]", "reaches outside the simulation interior");
  expectError(withRigidBodies(R"({ "shape": "sphere" })"), "rigid_bodies", "expected an array of rigid bodies");

  Json scene = baseScene();
  scene["colliders"] = Json::parse(R"([{ "type": "mesh", "path": "meshes/cube.obj", "resolution": 0.1 }])");
  expectError(scene, "colliders[0].resolution", "must be in [0.5, 8]");
  scene["colliders"] = Json::parse(R"([{ "type": "mesh", "path": "meshes/absent.obj" }])");
  expectError(scene, "colliders[0].path", (folder_ / "meshes/absent.obj").string());
  scene["colliders"] = Json::parse(R"([{ "type": "mesh", "path": "meshes/cube.obj", "radius": 1 }])");
  expectError(scene, "colliders[0].radius", "unknown key");
  scene["colliders"] = Json::parse(R"([{ "type": "mesh" }])");
  expectError(scene, "colliders[0].path", "required key is missing");
}

TEST_F(SceneRigidBodies, BodiesOverlappingAtTheStartAreRefused) {
  // Spheres are tested exactly: these two share space, and the next two only their bounding boxes' corners.
  expectError(withRigidBodies(R"([
    { "shape": "sphere", "center": [0.3, 0.3, 0.3], "radius": 0.1, "mass": 1 },
    { "shape": "sphere", "center": [0.4, 0.4, 0.3], "radius": 0.1, "mass": 1 } ])"),
              "rigid_bodies[1]", "overlaps rigid_bodies[0] at the start (the two spheres intersect): bodies meet "
                                 "each other at their surfaces");
  EXPECT_EQ(parse(withRigidBodies(R"([
    { "shape": "sphere", "center": [0.3, 0.3, 0.3], "radius": 0.1, "mass": 1 },
    { "shape": "sphere", "center": [0.45, 0.45, 0.3], "radius": 0.1, "mass": 1 } ])")).rigidBodies.size(), 2u);
  // Touching is fine: a stack of two boxes (binary fractions, so that the faces meet exactly).
  EXPECT_EQ(parse(withRigidBodies(R"([
    { "shape": "box", "center": [0.25, 0.25, 0.25], "size": [0.125, 0.125, 0.125], "mass": 1 },
    { "shape": "box", "center": [0.25, 0.375, 0.25], "size": [0.125, 0.125, 0.125], "mass": 1 } ])"))
                .rigidBodies.size(),
            2u);
  // Any other pair by its bounding boxes, which the message says.
  expectError(withRigidBodies(R"([
    { "shape": "sphere", "center": [0.3, 0.3, 0.3], "radius": 0.1, "mass": 1 },
    { "shape": "box", "center": [0.45, 0.45, 0.3], "size": [0.2, 0.2, 0.2], "mass": 1 } ])"),
              "rigid_bodies[1]", "their bounding boxes");
  // A turned box reaches further: 45° about z takes its 0.2 m edges to 0.141 m from its centre.
  expectError(withRigidBodies(R"([
    { "shape": "box", "center": [0.3, 0.3, 0.3], "size": [0.2, 0.2, 0.2], "mass": 1 },
    { "shape": "box", "center": [0.54, 0.3, 0.3], "size": [0.2, 0.2, 0.2], "rotate_deg": [0, 0, 45], "mass": 1 } ])"),
              "rigid_bodies[1]", "would be thrown apart");
}

}  // namespace
}  // namespace firn
