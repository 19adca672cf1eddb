#pragma once
// A perspective camera in world space (metres, y up), and the view Firn takes of a scene by default.
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "scene/Scene.h"

namespace firn::render {

struct Camera {
  glm::vec3 positionM{0.0f, 0.0f, 1.0f};
  glm::vec3 targetM{0.0f};
  float fovDeg = 40;  // vertical field of view
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  // Clip planes; fitDepthRange() sets them from the scene's size.
  float nearM = 0.01f;
  float farM = 100.0f;

  // World → view. Looking along `up` itself, the picture's up becomes −z (the scene's back).
  glm::mat4 view() const;
  // View → clip, for a viewport `aspect` = width / height.
  glm::mat4 projection(float aspect) const;
};

// Sets near and far so that everything drawn for `scene` lies between them, seen from camera.positionM:
// far reaches past the farthest drawn point, near is far / 1000 (32-bit float depth resolves that ratio
// to well under a particle's size).
void fitDepthRange(Camera& camera, const Scene& scene);

// The scene's "camera" if it has one; else one that frames the snow and what it touches (usedRegion: the bodies
// along their free flight, the colliders and ground it reaches), not the empty domain: aimed at the centre of that region from the front (+z) and 20° above,
// just far enough that the region with a 10 % margin fits the vertical field of view and, at `aspect`,
// the horizontal one. Depth range from fitDepthRange().
Camera defaultCamera(const Scene& scene, float aspect);

}  // namespace firn::render
