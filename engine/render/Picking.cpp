#include "render/Picking.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "scene/SceneObjects.h"

namespace firn::render {
namespace {

// A hit along a ray: its distance and the surface's normal there (not yet turned to face the ray).
struct Hit {
  double distanceM;
  glm::dvec3 normal;
};

std::optional<Hit> meetSphere(const Ray& ray, const glm::dvec3& centerM, double radiusM) {
  const glm::dvec3 offset = ray.originM - centerM;
  const double b = glm::dot(offset, ray.direction);
  const double c = glm::dot(offset, offset) - radiusM * radiusM;
  const double discriminant = b * b - c;
  if (discriminant < 0) return std::nullopt;
  const double root = std::sqrt(discriminant);
  // The near side, or the far one from inside.
  const double t = -b - root >= 0 ? -b - root : -b + root;
  if (t < 0) return std::nullopt;
  return Hit{t, glm::normalize(ray.originM + t * ray.direction - centerM)};
}

// The slab method; from inside, the exit.
std::optional<Hit> meetBox(const Ray& ray, const glm::dvec3& minM, const glm::dvec3& maxM) {
  double enter = -std::numeric_limits<double>::infinity(), leave = std::numeric_limits<double>::infinity();
  int enterAxis = 0, leaveAxis = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(ray.direction[axis]) < 1e-15) {
      if (ray.originM[axis] < minM[axis] || ray.originM[axis] > maxM[axis]) return std::nullopt;
      continue;
    }
    double near = (minM[axis] - ray.originM[axis]) / ray.direction[axis];
    double far = (maxM[axis] - ray.originM[axis]) / ray.direction[axis];
    if (near > far) std::swap(near, far);
    if (near > enter) {
      enter = near;
      enterAxis = axis;
    }
    if (far < leave) {
      leave = far;
      leaveAxis = axis;
    }
  }
  if (enter > leave || leave < 0) return std::nullopt;
  const bool inside = enter < 0;
  glm::dvec3 normal(0.0);
  normal[inside ? leaveAxis : enterAxis] = 1;
  return Hit{inside ? leave : enter, normal};
}

// Möller–Trumbore over every triangle: the nearest in front.
std::optional<Hit> meetTriangles(const Ray& ray, const voxelizer::TriangleMesh& mesh) {
  std::optional<Hit> nearest;
  for (const glm::uvec3& triangle : mesh.triangles) {
    const glm::dvec3 a = mesh.vertices[triangle.x], b = mesh.vertices[triangle.y], c = mesh.vertices[triangle.z];
    const glm::dvec3 edge1 = b - a, edge2 = c - a;
    const glm::dvec3 p = glm::cross(ray.direction, edge2);
    const double determinant = glm::dot(edge1, p);
    if (std::abs(determinant) < 1e-18) continue;
    const glm::dvec3 s = ray.originM - a;
    const double u = glm::dot(s, p) / determinant;
    if (u < 0 || u > 1) continue;
    const glm::dvec3 q = glm::cross(s, edge1);
    const double v = glm::dot(ray.direction, q) / determinant;
    if (v < 0 || u + v > 1) continue;
    const double t = glm::dot(edge2, q) / determinant;
    if (t < 0 || (nearest && t >= nearest->distanceM)) continue;
    const glm::dvec3 normal = glm::cross(edge1, edge2);
    if (glm::dot(normal, normal) > 0) nearest = Hit{t, glm::normalize(normal)};
  }
  return nearest;
}

std::optional<Hit> meetBody(const Ray& ray, const Body& body) {
  switch (body.shape) {
    case BodyShape::Sphere: return meetSphere(ray, body.centerM, body.radiusM);
    case BodyShape::Box: return meetBox(ray, body.minM, body.maxM);
    default:
      if (body.mesh) return meetTriangles(ray, *body.mesh);
      return meetBox(ray, body.loadedMinM, body.loadedMaxM);  // a points body: its bounds
  }
}

}  // namespace

Ray cameraRay(const Camera& camera, float aspect, const glm::dvec2& ndc) {
  const glm::dmat4 inverse = glm::inverse(glm::dmat4(camera.projection(aspect)) * glm::dmat4(camera.view()));
  const glm::dvec4 near = inverse * glm::dvec4(ndc, -1.0, 1.0);
  const glm::dvec4 far = inverse * glm::dvec4(ndc, 1.0, 1.0);
  const glm::dvec3 nearM = glm::dvec3(near) / near.w, farM = glm::dvec3(far) / far.w;
  return Ray{glm::dvec3(camera.positionM), glm::normalize(farM - nearM)};
}

std::string PickedPart::pointer() const {
  const char* section = kind == PartKind::Body       ? "/bodies/"
                        : kind == PartKind::Collider ? "/colliders/"
                                                     : "/rigid_bodies/";
  return section + std::to_string(index);
}

std::optional<PickedPart> pickPart(const Scene& scene, const Ray& ray) {
  std::optional<PickedPart> nearest;
  const auto consider = [&](PartKind kind, int index, const std::optional<Hit>& hit) {
    if (!hit || (nearest && hit->distanceM >= nearest->distanceM)) return;
    const glm::dvec3 normal = glm::dot(hit->normal, ray.direction) > 0 ? -hit->normal : hit->normal;
    nearest = PickedPart{kind, index, hit->distanceM, ray.originM + hit->distanceM * ray.direction, normal};
  };
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    consider(PartKind::Body, int(i), meetBody(ray, scene.bodies[i]));
  }
  for (const SceneObject& object : sceneObjects(scene)) {
    const ObjectPose pose = object.kind == ObjectKind::Collider
                                ? colliderObjectPose(scene.colliders[std::size_t(object.index)], 0.0)
                                : initialBodyPose(scene.rigidBodies[std::size_t(object.index)]);
    const PartKind kind = object.kind == ObjectKind::Collider ? PartKind::Collider : PartKind::RigidBody;
    consider(kind, object.index, meetTriangles(ray, posedMesh(object.meshM, pose)));
  }
  return nearest;
}

}  // namespace firn::render
