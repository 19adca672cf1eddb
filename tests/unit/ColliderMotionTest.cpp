// A collider's keyframed motion (docs/algorithm.md, Colliders; docs/scene-format.md, colliders): the pose is each
// keyframe's at its time, interpolated linearly and by slerp between, held before the first and after the last;
// v and ω are constant over a segment; every new key is validated with its key path.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <glm/gtc/constants.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "Error.h"
#include "scene/ColliderMotion.h"
#include "gpu/GpuFunctions.h"
#include "scene/Scene.h"
#include "scene/SceneObjects.h"
#include "sim/SceneUpload.h"
#include "voxelizer/Mesh.h"

namespace firn {
namespace {

using Json = nlohmann::ordered_json;

const char* const sceneFile = "scenes/motion.json";

// Double rounding of a few products and sums of numbers near 1: a few units of 2⁻⁵².
constexpr double kRoundingTolerance = 1e-14;

// The point x_rest of the shape at rest where the pose puts it: pivot + R (x_rest − pivot_rest) (eq. 31).
glm::dvec3 placed(const Collider& collider, const RigidPose& pose, const glm::dvec3& restM) {
  return pose.pivotM + pose.rotation * (restM - collider.pivotM);
}

void expectNear(const glm::dvec3& actual, const glm::dvec3& expected, double tolerance) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
  EXPECT_NEAR(actual.z, expected.z, tolerance);
}

// A box paddle turning about y through quarter turns and rising: keyframes at 0, 0.25 and 0.5 s.
Collider paddle() {
  Collider box;
  box.shape = ColliderShape::Box;
  box.minM = {0.4, 0.1, 0.48};
  box.maxM = {0.6, 0.3, 0.52};
  box.pivotM = {0.5, 0.2, 0.5};
  box.keyframes = {{0.25, {0, 0, 0}, {0, 0, 0}}, {0.5, {0, 0.1, 0}, {0, 90, 0}}, {0.75, {0.2, 0.1, 0}, {0, 180, 0}}};
  return box;
}

TEST(ColliderMotion, PoseIsExactlyEachKeyframesAtItsTime) {
  const Collider box = paddle();
  const glm::dvec3 corner = box.maxM;
  for (const ColliderKeyframe& key : box.keyframes) {
    const RigidPose pose = colliderPose(box, key.timeS);
    expectNear(pose.pivotM, box.pivotM + key.translateM, kRoundingTolerance);
    const glm::dvec3 rotated = voxelizer::rotationMatrix(key.rotateDeg) * (corner - box.pivotM);
    expectNear(placed(box, pose, corner), box.pivotM + key.translateM + rotated, kRoundingTolerance);
  }
}

TEST(ColliderMotion, HoldsTheFirstPoseBeforeAndTheLastAfter) {
  const Collider box = paddle();
  const RigidPose before = colliderPose(box, 0.1);
  EXPECT_EQ(before.segmentStartS, 0.0);
  EXPECT_EQ(before.velocityMPerS, glm::dvec3(0.0));
  EXPECT_EQ(before.angularVelocityRadPerS, glm::dvec3(0.0));
  expectNear(before.pivotM, box.pivotM, 0.0);
  const RigidPose after = colliderPose(box, 9.0);
  EXPECT_EQ(after.segmentStartS, 0.75);
  EXPECT_EQ(after.velocityMPerS, glm::dvec3(0.0));
  EXPECT_EQ(after.angularVelocityRadPerS, glm::dvec3(0.0));
  expectNear(after.pivotM, box.pivotM + glm::dvec3(0.2, 0.1, 0), kRoundingTolerance);
  // Half a turn about y: the corner's offset from the pivot has x and z reversed.
  expectNear(placed(box, after, box.maxM), box.pivotM + glm::dvec3(0.2, 0.1, 0) + glm::dvec3(-0.1, 0.1, -0.02),
             kRoundingTolerance);
}

TEST(ColliderMotion, MidpointsAreLinearInTranslationAndSlerpInRotation) {
  const Collider box = paddle();
  const RigidPose middle = colliderPose(box, 0.375);
  EXPECT_EQ(middle.segmentStartS, 0.25);
  expectNear(middle.pivotM, box.pivotM + glm::dvec3(0, 0.05, 0), kRoundingTolerance);
  // Halfway through a quarter turn about +y: 45°, and v = 0.1 m / 0.25 s, ω = (π/2) / 0.25 s about +y.
  const double angle = glm::quarter_pi<double>();
  const glm::dvec3 offset = box.maxM - box.pivotM;
  const glm::dvec3 turned(std::cos(angle) * offset.x + std::sin(angle) * offset.z, offset.y,
                          -std::sin(angle) * offset.x + std::cos(angle) * offset.z);
  expectNear(placed(box, middle, box.maxM), middle.pivotM + turned, kRoundingTolerance);
  expectNear(middle.velocityMPerS, {0, 0.4, 0}, kRoundingTolerance);
  expectNear(middle.angularVelocityRadPerS, {0, 2 * glm::pi<double>(), 0}, kRoundingTolerance);
  const RigidPose last = colliderPose(box, 0.6);
  expectNear(last.velocityMPerS, {0.8, 0, 0}, kRoundingTolerance);
  expectNear(last.angularVelocityRadPerS, {0, 2 * glm::pi<double>(), 0}, kRoundingTolerance);
}

TEST(ColliderMotion, ConstantVelocityIsTheOneSegmentFromZero) {
  Collider ball;
  ball.shape = ColliderShape::Sphere;
  ball.centerM = ball.pivotM = {1, 2, 3};
  ball.velocityMPerS = {0.5, 0, -1};
  const RigidPose pose = colliderPose(ball, 2.0);
  EXPECT_EQ(pose.segmentStartS, 0.0);
  expectNear(pose.pivotM, {2, 2, 1}, 0.0);
  EXPECT_EQ(pose.angularVelocityRadPerS, glm::dvec3(0.0));
}

// The GPU's table holds the pose at the start of a step's segment and colliderDistance (shared with the shaders)
// advances it by v and ω: from a step inside the segment [0.25, 0.5), the box's corners lie on its surface at the
// keyframe that ends it, and at the keyframe's own table too. Float rounding of positions below 1 m and of the
// turn's sine and cosine, a few units of 2⁻²⁴ m: tolerance 1e-6 m.
TEST(ColliderMotion, TheGpuTableAdvancedToAKeyframeIsAtIt) {
  Scene scene;
  scene.colliders = {paddle()};
  const Collider& box = scene.colliders[0];
  const ColliderKeyframe& key = box.keyframes[1];
  const ColliderFields noFields = bakeColliderFields(scene);
  const glm::dmat3 rotation = voxelizer::rotationMatrix(key.rotateDeg);
  for (const double tableTimeS : {0.3, key.timeS}) {
    const gpu::ColliderParams table = buildColliderTable(scene, noFields, tableTimeS).at(0);
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec3 restM((corner & 1) ? box.maxM.x : box.minM.x, (corner & 2) ? box.maxM.y : box.minM.y,
                             (corner & 4) ? box.maxM.z : box.minM.z);
      const glm::dvec3 posedM = box.pivotM + key.translateM + rotation * (restM - box.pivotM);
      glm::vec3 normal;
      EXPECT_NEAR(gpu::colliderDistance(table, noFields.samples, glm::vec3(posedM), float(key.timeS), normal), 0.0, 1e-6)
          << "corner " << corner << ", table at " << tableTimeS << " s";
    }
  }
  // The boundary velocity v + ω × r (eq. 33) at 0.6 s, in the last segment: v = 0.8 m/s along x, ω = 2π rad/s
  // about +y, and the pivot at (0.5, 0.2, 0.5) + (0, 0.1, 0) + 0.1 s · v = (0.58, 0.3, 0.5); 0.1 m from it along −x,
  // ω × r = (0, 0, 0.1 ω). Float rounding as above.
  const gpu::ColliderParams table = buildColliderTable(scene, noFields, 0.6).at(0);
  const glm::vec3 velocity = gpu::colliderVelocity(table, glm::vec3(0.48f, 0.3f, 0.5f), 0.6f);
  EXPECT_NEAR(velocity.x, 0.8, 1e-6);
  EXPECT_NEAR(velocity.y, 0.0, 1e-6);
  EXPECT_NEAR(velocity.z, 0.1 * 2 * glm::pi<double>(), 1e-5);
}

// The reach (ColliderParams.contact.y) lets the shaders skip a collider at a point beyond it, so it must hold
// every point of the solid, at every time of the motion: the keyframed box (turning), a sphere turned about a pivot
// outside it, a mesh turned about a pivot off its centre (its field's lattice holds it), and a box and a mesh body. Probed on a
// 2 cm lattice through the colliders at four times. A plane has no reach (−1). The reach of the sphere is its exact
// one, |c − pivot| + r, plus the 1e-4 the host adds: tolerance 1e-6 m of float rounding.
TEST(ColliderMotion, EveryPointInsideAColliderLiesWithinItsReach) {
  Scene scene;
  scene.grid.cells = glm::ivec3(40);
  scene.grid.cellSizeM = 0.05;
  scene.colliders = {paddle()};
  Collider ball;
  ball.shape = ColliderShape::Sphere;
  ball.centerM = {1.0, 0.5, 1.0};
  ball.radiusM = 0.2;
  ball.pivotM = {0.6, 0.5, 1.0};
  ball.keyframes = {{0.0, {0, 0, 0}, {0, 0, 0}}, {0.5, {0.1, 0, 0}, {0, 120, 0}}};
  scene.colliders.push_back(ball);
  Collider floor;
  floor.shape = ColliderShape::Plane;
  scene.colliders.push_back(floor);
  Collider mesh;
  mesh.shape = ColliderShape::Mesh;
  mesh.mesh = std::make_shared<voxelizer::TriangleMesh>(voxelizer::boxMesh({1.2, 0.2, 0.3}, {1.6, 0.5, 0.9}));
  mesh.pivotM = {1.3, 0.35, 0.6};
  mesh.keyframes = {{0.0, {0, 0, 0}, {0, 0, 0}}, {0.5, {0.1, 0, 0}, {0, 30, 10}}};
  scene.colliders.push_back(mesh);
  RigidBody box;
  box.shape = RigidShape::Box;
  box.halfExtentsM = {0.2, 0.1, 0.3};
  box.centerOfMassM = {0.5, 1.2, 0.5};
  box.angularVelocityRadPerS = {1, 2, 0};
  RigidBody meshBody;
  meshBody.shape = RigidShape::Mesh;
  meshBody.mesh = std::make_shared<voxelizer::TriangleMesh>(voxelizer::boxMesh({1.0, 1.0, 1.0}, {1.3, 1.5, 1.2}));
  meshBody.centerOfMassM = {1.15, 1.25, 1.1};
  for (RigidBody* body : {&box, &meshBody}) {
    setUniformDensity(*body, shapeMassProperties(*body), 500);
    scene.rigidBodies.push_back(*body);
  }
  const ColliderFields fields = bakeColliderFields(scene);
  const std::vector<gpu::ColliderParams> table = buildColliderTable(scene, fields, 0.0);
  EXPECT_EQ(table[2].contact.y, -1.0f);
  EXPECT_NEAR(table[1].contact.y, 0.6 * (1 + 1e-4), 1e-6);
  std::vector<int> inside(table.size(), 0);
  for (const double timeS : {0.0, 0.1, 0.3, 0.45}) {
    const std::vector<gpu::ColliderParams> atTime = buildColliderTable(scene, fields, timeS);
    for (std::size_t entry = 0; entry < atTime.size(); ++entry) {
      if (entry == 2) continue;
      const gpu::ColliderParams& c = atTime[entry];
      const glm::vec3 pivot = gpu::colliderPivot(c, float(timeS));
      for (int i = 0; i < 100; ++i) {
        for (int j = 0; j < 100; ++j) {
          for (int k = 0; k < 100; ++k) {
            const glm::vec3 x = glm::vec3(i, j, k) * 0.02f;
            glm::vec3 normal;
            if (gpu::colliderDistance(c, fields.samples, x, float(timeS), normal) > 0.0f) continue;
            ++inside[entry];
            const glm::vec3 fromPivot = x - pivot;
            ASSERT_LE(glm::dot(fromPivot, fromPivot), c.contact.y * c.contact.y)
                << "entry " << entry << " at " << timeS << " s, x = (" << x.x << ", " << x.y << ", " << x.z << ")";
          }
        }
      }
    }
  }
  for (std::size_t entry = 0; entry < table.size(); ++entry) {
    if (entry != 2) {
      EXPECT_GT(inside[entry], 100) << "entry " << entry << ": too few points probed inside";
    }
  }
}

// A box's 12-triangle mesh measures as the analytic box inside it and within a cell's diagonal of its surface (0.04 m
// at s = 0.025 m), its edges and corners included (docs/algorithm.md, Mesh colliders): φ to float rounding of the
// positions (2⁻²⁴ of 1 m, 6e-8 m; bound 1e-6 m), and the normal to 1e-3 rad wherever the point lies 1e-4 m or more from the surface (the rounding
// over that distance, 6e-4 rad), except on the ridges inside, where two faces are equally near and either normal is
// right. Before exact distances near the surface the field's trilinear interpolation was 1 cm (0.4 samples) off at
// the edges and its normals up to 89° (1.55 rad). Two faces pass through samples (the lattice starts 3 cells below
// the box's low corner), which names either of two faces at some of them; the other edges cross cells. A copy wound
// inside out measures the same: the bake turns each face to the side its samples' winding number gives.
TEST(ColliderMotion, AMeshBoxMeasuresAsTheAnalyticBoxAtItsEdgesAndCorners) {
  Scene scene;
  scene.grid.cells = glm::ivec3(24);
  scene.grid.cellSizeM = 0.05;
  const glm::dvec3 minM(0.33, 0.27, 0.41), maxM(0.77, 0.58, 0.86);
  Collider box;
  box.shape = ColliderShape::Box;
  box.minM = minM;
  box.maxM = maxM;
  box.pivotM = 0.5 * (minM + maxM);
  Collider mesh;
  mesh.shape = ColliderShape::Mesh;
  mesh.mesh = std::make_shared<voxelizer::TriangleMesh>(voxelizer::boxMesh(minM, maxM));
  mesh.pivotM = box.pivotM;
  // The same box wound inside out: the bake turns its faces by the winding number's side of their samples.
  Collider inverted = mesh;
  voxelizer::TriangleMesh turned = voxelizer::boxMesh(minM, maxM);
  for (glm::uvec3& triangle : turned.triangles) std::swap(triangle.y, triangle.z);
  inverted.mesh = std::make_shared<voxelizer::TriangleMesh>(turned);
  scene.colliders = {box, mesh, inverted};
  const ColliderFields fields = bakeColliderFields(scene);
  const std::vector<gpu::ColliderParams> table = buildColliderTable(scene, fields, 0.0);
  const double bandM = 2 * scene.grid.cellSizeM;
  // The mesh is measured exactly within a cell's diagonal (√3 s) outside, and inside; beyond, interpolated.
  const double exactBandM = 0.04;
  double worstDistanceM = 0, worstTurnRad = 0, worstFarM = 0, worstInvertedM = 0, worstInvertedRad = 0;
  int probed = 0;
  for (double x = minM.x - bandM; x <= maxM.x + bandM; x += 0.0037) {
    for (double y = minM.y - bandM; y <= maxM.y + bandM; y += 0.0041) {
      for (double z = minM.z - bandM; z <= maxM.z + bandM; z += 0.0043) {
        const glm::vec3 point(x, y, z);
        glm::vec3 boxNormal, meshNormal;
        const float boxM = gpu::colliderDistance(table[0], fields.samples, point, 0.0f, boxNormal);
        const float meshM = gpu::colliderDistance(table[1], fields.samples, point, 0.0f, meshNormal);
        glm::vec3 invertedNormal;
        const float invertedM = gpu::colliderDistance(table[2], fields.samples, point, 0.0f, invertedNormal);
        worstInvertedM = std::max(worstInvertedM, double(std::abs(invertedM - meshM)));
        if (std::abs(meshM) >= 1e-4) {
          worstInvertedRad = std::max(
              worstInvertedRad, std::acos(std::clamp(double(glm::dot(invertedNormal, meshNormal)), -1.0, 1.0)));
        }
        if (std::abs(boxM) > bandM) continue;
        if (meshM > exactBandM) {
          worstFarM = std::max(worstFarM, double(std::abs(meshM - boxM)));
          continue;
        }
        ++probed;
        worstDistanceM = std::max(worstDistanceM, double(std::abs(meshM - boxM)));
        // Inside, a point as near two faces (to 1e-4 m) lies on a ridge where the normal turns.
        const glm::dvec3 excess = glm::abs(glm::dvec3(point) - box.pivotM) - 0.5 * (maxM - minM);
        const double nearest = std::max({excess.x, excess.y, excess.z});
        const int nearFaces = (excess.x > nearest - 1e-4) + (excess.y > nearest - 1e-4) + (excess.z > nearest - 1e-4);
        if (std::abs(boxM) < 1e-4 || (boxM < 0 && nearFaces > 1)) continue;
        worstTurnRad = std::max(worstTurnRad, std::acos(std::clamp(double(glm::dot(boxNormal, meshNormal)), -1.0, 1.0)));
      }
    }
  }
  std::printf("%d points: φ within %.3g m, normals within %.3g rad; farther out φ within %.3g m; inside out %.3g m, "
              "%.3g rad\n", probed, worstDistanceM, worstTurnRad, worstFarM, worstInvertedM, worstInvertedRad);
  EXPECT_GT(probed, 100000);
  EXPECT_LT(worstDistanceM, 1e-6);
  EXPECT_LT(worstTurnRad, 1e-3);
  // Farther out the trilinear interpolant, rounding edges off by up to 0.16 s (measured: 3.8 mm at s = 2.5 mm).
  EXPECT_LT(worstFarM, 0.2 * 0.025);
  // Wound inside out it measures the same, to the rounding of the corners' other order (the same bounds).
  EXPECT_LT(worstInvertedM, 1e-6);
  EXPECT_LT(worstInvertedRad, 1e-3);
}

// A scene with one collider, for the validation tests.
Json sceneWith(const Json& collider) {
  Json scene = Json::parse(R"({
    "grid": { "origin": [0, 0, 0], "cells": [32, 32, 32], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 24, "frames": 10 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "sphere", "center": [0.8, 0.8, 0.8], "radius": 0.2, "material": "snow" } ]
  })");
  scene["colliders"] = Json::array({collider});
  return scene;
}

Json keyframedBox() {
  return Json::parse(R"({ "type": "box", "min": [0.2, 0.2, 0.2], "max": [0.4, 0.3, 0.4],
    "keyframes": [ { "time_s": 0, "translate": [0, 0, 0] }, { "time_s": 1, "rotate_deg": [0, 90, 0] } ] })");
}

void expectError(const Json& scene, const std::string& keyPath, const std::string& problemFragment) {
  try {
    parseScene(scene.dump(), sceneFile);
  } catch (const InputError& error) {
    EXPECT_EQ(error.code(), ExitCode::BadInput);
    const std::string message = error.what();
    const std::string prefix = std::string(sceneFile) + ": " + keyPath + ": ";
    EXPECT_EQ(message.compare(0, prefix.size(), prefix), 0) << "message: " << message << "\nexpected: " << prefix;
    EXPECT_NE(message.find(problemFragment), std::string::npos) << "message: " << message;
    return;
  }
  ADD_FAILURE() << "expected an InputError for " << scene.dump();
}

TEST(ColliderMotion, SceneKeysLandInTheCollider) {
  Json collider = keyframedBox();
  collider["pivot"] = {0.3, 0.2, 0.3};
  const Scene scene = parseScene(sceneWith(collider).dump(), sceneFile);
  const Collider& box = scene.colliders.at(0);
  ASSERT_EQ(box.keyframes.size(), 2u);
  EXPECT_EQ(box.keyframes[1].timeS, 1.0);
  EXPECT_EQ(box.keyframes[1].rotateDeg, glm::dvec3(0, 90, 0));
  EXPECT_EQ(box.pivotM, glm::dvec3(0.3, 0.2, 0.3));
  // Without "pivot", the box's centre.
  const Scene centred = parseScene(sceneWith(keyframedBox()).dump(), sceneFile);
  expectNear(centred.colliders.at(0).pivotM, {0.3, 0.25, 0.3}, kRoundingTolerance);
}

TEST(ColliderMotion, EveryNewKeyIsValidatedByName) {
  Json both = keyframedBox();
  both["velocity"] = {1, 0, 0};
  expectError(sceneWith(both), "colliders[0].keyframes", "velocity");

  Json empty = keyframedBox();
  empty["keyframes"] = Json::array();
  expectError(sceneWith(empty), "colliders[0].keyframes", "non-empty array");

  Json notArray = keyframedBox();
  notArray["keyframes"] = 3;
  expectError(sceneWith(notArray), "colliders[0].keyframes", "non-empty array");

  Json missingTime = keyframedBox();
  missingTime["keyframes"][1].erase("time_s");
  expectError(sceneWith(missingTime), "colliders[0].keyframes[1].time_s", "missing");

  Json negative = keyframedBox();
  negative["keyframes"][0]["time_s"] = -1;
  expectError(sceneWith(negative), "colliders[0].keyframes[0].time_s", "");

  Json backwards = keyframedBox();
  backwards["keyframes"][1]["time_s"] = 0;
  expectError(sceneWith(backwards), "colliders[0].keyframes[1].time_s", "later than");

  Json unknown = keyframedBox();
  unknown["keyframes"][0]["scale"] = 2;
  expectError(sceneWith(unknown), "colliders[0].keyframes[0].scale", "");

  Json badTranslate = keyframedBox();
  badTranslate["keyframes"][0]["translate"] = {1, 2};
  expectError(sceneWith(badTranslate), "colliders[0].keyframes[0].translate", "3 numbers");

  Json badRotate = keyframedBox();
  badRotate["keyframes"][1]["rotate_deg"] = "ninety";
  expectError(sceneWith(badRotate), "colliders[0].keyframes[1].rotate_deg", "3 numbers");

  Json halfTurn = keyframedBox();
  halfTurn["keyframes"][1]["rotate_deg"] = {0, 180, 0};
  expectError(sceneWith(halfTurn), "colliders[0].keyframes[1].rotate_deg", "shorter way");

  Json badPivot = keyframedBox();
  badPivot["pivot"] = {0, "a", 0};
  expectError(sceneWith(badPivot), "colliders[0].pivot[1]", "");
}

}  // namespace
}  // namespace firn
