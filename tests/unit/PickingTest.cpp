// The scene editor's picking (render/Picking.h): the part a ray from the camera meets first, with where and how.
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include "render/Camera.h"
#include "render/Picking.h"
#include "scene/Scene.h"

namespace firn {
namespace {

// A snow ball, a snow box, a rigid box beside the ball and behind the snow box, and the floor.
const char* const kScene = R"({
  "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
  "time": { "dt": 1e-3, "frame_rate": 50, "frames": 2 },
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.2, "material": "snow" },
              { "shape": "box", "min": [0.15, 0.15, 0.3], "max": [0.35, 0.35, 0.5], "material": "snow" } ],
  "colliders": [ { "type": "plane", "point": [0, 0.05, 0], "normal": [0, 1, 0] } ],
  "rigid_bodies": [ { "shape": "box", "center": [0.25, 0.3, 0.2], "size": [0.2, 0.2, 0.1], "density": 500 } ] })";

// Doubles along a metre-sized scene: far below anything a click resolves.
constexpr double kExact = 1e-9;

TEST(Picking, TheNearestPartAlongTheRayWithItsPointAndNormal) {
  const Scene scene = parseScene(kScene, "pick.json");
  // Down −z through the ball's centre: the ball's near pole.
  const std::optional<render::PickedPart> ball = render::pickPart(scene, {{0.6, 0.6, 2.0}, {0, 0, -1}});
  ASSERT_TRUE(ball);
  EXPECT_EQ(ball->pointer(), "/bodies/0");
  EXPECT_NEAR(ball->distanceM, 2.0 - 0.8, kExact);
  EXPECT_NEAR(glm::distance(ball->normal, glm::dvec3(0, 0, 1)), 0.0, kExact);
  // Down −z through the snow box (z in [0.3, 0.5]) and the rigid box behind it (z in [0.15, 0.25]): the snow box.
  const std::optional<render::PickedPart> front = render::pickPart(scene, {{0.25, 0.25, 2.0}, {0, 0, -1}});
  ASSERT_TRUE(front);
  EXPECT_EQ(front->pointer(), "/bodies/1");
  EXPECT_NEAR(front->pointM.z, 0.5, kExact);
  // Above the snow box (y up to 0.35), the rigid box's front face alone (y in [0.2, 0.4]).
  const std::optional<render::PickedPart> box = render::pickPart(scene, {{0.25, 0.38, 2.0}, {0, 0, -1}});
  ASSERT_TRUE(box);
  EXPECT_EQ(box->pointer(), "/rigid_bodies/0");
  EXPECT_NEAR(box->pointM.z, 0.25, kExact);
  // The snow box's top face, from above.
  const std::optional<render::PickedPart> snowBox = render::pickPart(scene, {{0.25, 1.0, 0.4}, {0, -1, 0}});
  ASSERT_TRUE(snowBox);
  EXPECT_EQ(snowBox->pointer(), "/bodies/1");
  EXPECT_NEAR(snowBox->pointM.y, 0.35, kExact);
  EXPECT_NEAR(glm::distance(snowBox->normal, glm::dvec3(0, 1, 0)), 0.0, kExact);
  // Down where nothing else stands: the floor, its normal up whichever way the plane's square is wound.
  const std::optional<render::PickedPart> floor = render::pickPart(scene, {{1.0, 1.0, 1.0}, {0, -1, 0}});
  ASSERT_TRUE(floor);
  EXPECT_EQ(floor->pointer(), "/colliders/0");
  EXPECT_NEAR(floor->pointM.y, 0.05, kExact);
  EXPECT_NEAR(floor->normal.y, 1.0, kExact);
  // Up, away from everything.
  EXPECT_FALSE(render::pickPart(scene, {{1.0, 1.0, 1.0}, {0, 1, 0}}));
}

// The ray through the middle of the view goes from the camera through its target; through a corner, along the edge
// of the field of view (its vertical half-angle, at the top).
TEST(Picking, CameraRaysLeaveTheCameraThroughTheView) {
  render::Camera camera;
  camera.positionM = {0.6f, 0.9f, 2.0f};
  camera.targetM = {0.6f, 0.5f, 0.6f};
  camera.fovDeg = 40;
  const render::Ray middle = render::cameraRay(camera, 1.5f, {0, 0});
  const glm::dvec3 toTarget = glm::normalize(glm::dvec3(camera.targetM) - glm::dvec3(camera.positionM));
  // The matrices are float: their inverse leaves about 1e-6 of a unit direction.
  EXPECT_NEAR(glm::distance(middle.direction, toTarget), 0.0, 1e-5);
  EXPECT_NEAR(glm::distance(middle.originM, glm::dvec3(camera.positionM)), 0.0, 1e-6);
  const render::Ray top = render::cameraRay(camera, 1.5f, {0, 1});
  EXPECT_NEAR(std::acos(glm::dot(top.direction, toTarget)), glm::radians(20.0), 1e-5);
}

}  // namespace
}  // namespace firn
