#include "scene/SceneObjects.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

#include "scene/ColliderMotion.h"

namespace firn {

namespace {

// A sphere fine enough that its facets stay within 0.2 % of the radius (48 segments round, 24 rings).
voxelizer::TriangleMesh sphereMesh(double radiusM) { return voxelizer::uvSphere(radiusM, 24, 48); }

// A box of these half extents about the origin.
voxelizer::TriangleMesh boxMesh(const glm::dvec3& halfExtentsM) {
  return voxelizer::boxMesh(-halfExtentsM, halfExtentsM);
}

// A square across the domain in the plane through the origin with this normal, facing it.
voxelizer::TriangleMesh planeMesh(const glm::dvec3& normal, double halfSizeM) {
  const glm::dvec3 helper = std::abs(normal.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(helper, normal));
  const glm::dvec3 v = glm::cross(normal, u);
  voxelizer::TriangleMesh mesh;
  mesh.vertices = {halfSizeM * (-u - v), halfSizeM * (u - v), halfSizeM * (u + v), halfSizeM * (-u + v)};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

voxelizer::TriangleMesh shifted(voxelizer::TriangleMesh mesh, const glm::dvec3& originM) {
  for (glm::dvec3& vertex : mesh.vertices) vertex -= originM;
  return mesh;
}

voxelizer::TriangleMesh colliderMesh(const Scene& scene, const Collider& collider) {
  switch (collider.shape) {
    case ColliderShape::Plane: {
      const double halfSizeM = glm::length(scene.domainMaxM() - scene.domainMinM());
      return shifted(planeMesh(collider.normal, halfSizeM), collider.pivotM - collider.pointM);
    }
    case ColliderShape::Sphere: return shifted(sphereMesh(collider.radiusM), collider.pivotM - collider.centerM);
    case ColliderShape::Box:
      return shifted(boxMesh(0.5 * (collider.maxM - collider.minM)),
                     collider.pivotM - 0.5 * (collider.minM + collider.maxM));
    case ColliderShape::Mesh: return shifted(*collider.mesh, collider.pivotM);
  }
  return {};
}

voxelizer::TriangleMesh bodyMesh(const RigidBody& body) {
  switch (body.shape) {
    case RigidShape::Sphere: return sphereMesh(body.radiusM);
    case RigidShape::Box: return boxMesh(body.halfExtentsM);
    case RigidShape::Mesh: return shifted(*body.mesh, body.centerOfMassM);
  }
  return {};
}

}  // namespace

bool colliderMoves(const Collider& collider) {
  return collider.shape != ColliderShape::Plane &&
         (!collider.keyframes.empty() || collider.velocityMPerS != glm::dvec3(0.0));
}

std::vector<SceneObject> sceneObjects(const Scene& scene) {
  std::vector<SceneObject> objects;
  for (std::size_t i = 0; i < scene.colliders.size(); ++i) {
    const Collider& collider = scene.colliders[i];
    SceneObject& object = objects.emplace_back();
    object.kind = ObjectKind::Collider;
    object.index = int(i);
    object.name = "colliders[" + std::to_string(i) + "]";
    object.moves = colliderMoves(collider);
    object.meshM = colliderMesh(scene, collider);
  }
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i) {
    SceneObject& object = objects.emplace_back();
    object.kind = ObjectKind::RigidBody;
    object.index = int(i);
    object.name = "rigid_bodies[" + std::to_string(i) + "]";
    object.moves = true;
    object.meshM = bodyMesh(scene.rigidBodies[i]);
  }
  return objects;
}

ObjectPose colliderObjectPose(const Collider& collider, double timeS) {
  const RigidPose pose = colliderPose(collider, timeS);
  return {pose.pivotM, pose.rotation, pose.velocityMPerS, pose.angularVelocityRadPerS};
}

voxelizer::MassProperties shapeMassProperties(const RigidBody& body) {
  voxelizer::MassProperties shape;
  switch (body.shape) {
    case RigidShape::Sphere: {
      const double r = body.radiusM;
      shape.volumeM3 = 4.0 / 3.0 * glm::pi<double>() * r * r * r;
      shape.centroidM = body.centerM;
      shape.inertiaPerDensityM5 = glm::dmat3(2.0 / 5.0 * shape.volumeM3 * r * r);  // 2/5 m r²
      break;
    }
    case RigidShape::Box: {
      const glm::dvec3 edgesM = 2.0 * body.halfExtentsM;
      const glm::dvec3 squared = edgesM * edgesM;
      shape.volumeM3 = edgesM.x * edgesM.y * edgesM.z;
      shape.centroidM = body.centerM;
      // m/12 diag(b² + c², a² + c², a² + b²), in the box's own axes.
      shape.inertiaPerDensityM5[0][0] = shape.volumeM3 / 12 * (squared.y + squared.z);
      shape.inertiaPerDensityM5[1][1] = shape.volumeM3 / 12 * (squared.x + squared.z);
      shape.inertiaPerDensityM5[2][2] = shape.volumeM3 / 12 * (squared.x + squared.y);
      break;
    }
    case RigidShape::Mesh:
      // Measured as placed: the body's own axes are the world's at t = 0 (Scene.h, RigidBody).
      shape = voxelizer::massProperties(*body.mesh);
      break;
  }
  return shape;
}

double rigidBodyReachM(const RigidBody& body) {
  switch (body.shape) {
    case RigidShape::Sphere: return body.radiusM;
    case RigidShape::Box: return glm::length(body.halfExtentsM);
    case RigidShape::Mesh: {
      double reachM = 0;
      for (const glm::dvec3& vertex : body.mesh->vertices) reachM = std::max(reachM, glm::length(vertex - body.centerOfMassM));
      return reachM;
    }
  }
  return 0;
}

double rigidBodySurfaceSpeedMPerS(const RigidBody& body) {
  return glm::length(body.velocityMPerS) + glm::length(body.angularVelocityRadPerS) * rigidBodyReachM(body);
}

void setUniformDensity(RigidBody& body, const voxelizer::MassProperties& shape, double densityKgPerM3) {
  body.volumeM3 = shape.volumeM3;
  body.centerOfMassM = shape.centroidM;
  body.massKg = densityKgPerM3 * shape.volumeM3;
  body.inertiaKgM2 = densityKgPerM3 * shape.inertiaPerDensityM5;
}

ObjectPose initialBodyPose(const RigidBody& body) {
  ObjectPose pose;
  pose.positionM = body.centerOfMassM;
  if (body.shape == RigidShape::Box) {
    pose.orientation = glm::normalize(glm::quat_cast(voxelizer::rotationMatrix(body.rotateDeg)));
  }
  pose.velocityMPerS = body.velocityMPerS;
  pose.angularVelocityRadPerS = body.angularVelocityRadPerS;
  return pose;
}

bool isFinite(const ObjectPose& pose) {
  const auto finite = [](const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  const glm::dquat& q = pose.orientation;
  return finite(pose.positionM) && std::isfinite(q.w) && finite(glm::dvec3(q.x, q.y, q.z)) &&
         finite(pose.velocityMPerS) && finite(pose.angularVelocityRadPerS);
}

glm::dvec3 worldPoint(const ObjectPose& pose, const glm::dvec3& pointM) {
  return pose.positionM + pose.orientation * pointM;
}

voxelizer::TriangleMesh posedMesh(const voxelizer::TriangleMesh& meshM, const ObjectPose& pose) {
  voxelizer::TriangleMesh mesh;
  mesh.vertices.reserve(meshM.vertices.size());
  for (const glm::dvec3& vertexM : meshM.vertices) mesh.vertices.push_back(worldPoint(pose, vertexM));
  mesh.triangles = meshM.triangles;
  return mesh;
}

}  // namespace firn
