#include "render/Camera.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include "render/Geometry.h"

namespace firn::render {

namespace {

constexpr double kDefaultElevationDeg = 20;  // "a little above": the ground reads as a floor, not a line
constexpr double kFramingMargin = 0.1;       // of the framed region's size, on each side
constexpr float kNearFarRatio = 1e-3f;

}  // namespace

glm::mat4 Camera::view() const {
  const glm::vec3 forward = glm::normalize(targetM - positionM);
  const glm::vec3 pictureUp = glm::length(glm::cross(forward, up)) > 1e-6f * glm::length(up) ? up : glm::vec3(0, 0, -1);
  return glm::lookAt(positionM, targetM, pictureUp);
}

glm::mat4 Camera::projection(float aspect) const {
  return glm::perspective(glm::radians(fovDeg), aspect, nearM, farM);
}

void fitDepthRange(Camera& camera, const Scene& scene) {
  const glm::dvec3 domainCentreM = 0.5 * (scene.domainMinM() + scene.domainMaxM());
  const double farM = glm::length(glm::dvec3(camera.positionM) - domainCentreM) + drawnRadiusM(scene);
  camera.farM = static_cast<float>(farM);
  camera.nearM = static_cast<float>(farM) * kNearFarRatio;
}

Camera defaultCamera(const Scene& scene, float aspect) {
  Camera camera;
  if (scene.camera) {
    camera.positionM = glm::vec3(scene.camera->positionM);
    camera.targetM = glm::vec3(scene.camera->targetM);
    camera.fovDeg = static_cast<float>(scene.camera->fovDeg);
    fitDepthRange(camera, scene);
    return camera;
  }
  const Bounds region = usedRegion(scene);
  const glm::dvec3 targetM = region.centerM();
  const glm::dvec3 paddedHalfM = (0.5 + kFramingMargin) * (region.maxM - region.minM);
  const double elevation = glm::radians(kDefaultElevationDeg);
  const glm::dvec3 toEye(0, std::sin(elevation), std::cos(elevation));
  const glm::dvec3 right(1, 0, 0);
  const glm::dvec3 pictureUp = glm::cross(toEye, right);
  const double tanHalfFovY = std::tan(glm::radians(double(camera.fovDeg)) / 2);
  const double tanHalfFovX = tanHalfFovY * aspect;
  // A corner q (relative to the target) at depth D − q·toEye is in view when |q·up| ≤ tan(fov_y/2)·depth and
  // |q·right| ≤ tan(fov_x/2)·depth: each corner bounds the distance D from below.
  double distanceM = 0;
  for (int index = 0; index < 8; ++index) {
    const glm::dvec3 q((index & 1) ? paddedHalfM.x : -paddedHalfM.x, (index & 2) ? paddedHalfM.y : -paddedHalfM.y,
                       (index & 4) ? paddedHalfM.z : -paddedHalfM.z);
    const double towardsEyeM = glm::dot(q, toEye);
    distanceM = std::max({distanceM, towardsEyeM + std::abs(glm::dot(q, pictureUp)) / tanHalfFovY,
                          towardsEyeM + std::abs(glm::dot(q, right)) / tanHalfFovX});
  }
  camera.targetM = glm::vec3(targetM);
  camera.positionM = glm::vec3(targetM + distanceM * toEye);
  fitDepthRange(camera, scene);
  return camera;
}

}  // namespace firn::render
