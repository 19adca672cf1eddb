#pragma once
// Which part of a scene a ray from the camera meets first: the scene editor's picking (apps/firn/SceneEditor.h) and
// where it puts what it adds. The snow's bodies are met as their shapes (a sphere, a box, the placed mesh; a points
// body as its bounds); the colliders and the rigid bodies as the renderer draws them at the start
// (scene/SceneObjects.h: the analytic shapes tessellated, meshes as placed, planes as their squares across the
// domain). No GL here.
#include <optional>
#include <string>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/Camera.h"
#include "scene/Scene.h"

namespace firn::render {

struct Ray {
  glm::dvec3 originM;
  glm::dvec3 direction;  // unit
};

// The ray from the camera through a point of its viewport, `ndc` in [−1, 1]² (x right, y up), at `aspect` = width /
// height.
Ray cameraRay(const Camera& camera, float aspect, const glm::dvec2& ndc);

enum class PartKind { Body, Collider, RigidBody };

struct PickedPart {
  PartKind kind = PartKind::Body;
  int index = 0;           // into Scene::bodies, colliders or rigidBodies
  double distanceM = 0;    // along the ray
  glm::dvec3 pointM{0.0};  // where the ray meets it
  glm::dvec3 normal{0.0};  // the surface's there, facing the ray
  // The part's JSON pointer in the scene file ("/bodies/0", "/colliders/2", "/rigid_bodies/1").
  std::string pointer() const;
};

// The nearest part the ray meets in front of its origin, or nothing.
std::optional<PickedPart> pickPart(const Scene& scene, const Ray& ray);

}  // namespace firn::render
