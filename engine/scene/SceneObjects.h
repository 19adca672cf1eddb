#pragma once
// The solid objects of a scene as an artist sees them and a DCC replays them: each collider (analytic or mesh) and
// each rigid body as a triangle mesh in its own frame, and where that frame is at a time (docs/command-line.md,
// Outputs: bodies.csv and Object meshes).
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "scene/Scene.h"
#include "voxelizer/MassProperties.h"
#include "voxelizer/Mesh.h"

namespace firn {

// A point p of an object's frame is at positionM + orientation · p. For a collider the frame's origin is its pivot
// and its axes the world's at rest; for a rigid body, its centre of mass and its own axes (Scene.h, RigidBody).
struct ObjectPose {
  glm::dvec3 positionM{0.0};
  glm::dquat orientation{1, 0, 0, 0};
  glm::dvec3 velocityMPerS{0.0};           // of the frame's origin
  glm::dvec3 angularVelocityRadPerS{0.0};  // world axes
};

enum class ObjectKind { Collider, RigidBody };

struct SceneObject {
  ObjectKind kind = ObjectKind::Collider;
  int index = 0;     // into Scene::colliders or Scene::rigidBodies
  std::string name;  // "colliders[2]", "rigid_bodies[0]": as errors and pre-flight name them
  bool moves = false;  // a rigid body, or a collider with keyframes or a velocity
  // The object's surface in its own frame: a mesh's triangles as placed, a sphere's and a box's tessellated, a
  // plane's a square across the domain (planes are the ground and walls, drawn but never exported as moving).
  voxelizer::TriangleMesh meshM;
};

// Whether a collider moves as an object bodies.csv follows: one with keyframes or a velocity, but not a plane (planes
// are the ground and walls: a moving one still does work on the snow, which the energy audit counts).
bool colliderMoves(const Collider& collider);

// Every collider, then every rigid body, in the scene's order.
std::vector<SceneObject> sceneObjects(const Scene& scene);

// A collider's frame at timeS (from colliderPose): position the pivot's, orientation its turn from rest.
ObjectPose colliderObjectPose(const Collider& collider, double timeS);

// A rigid body's frame at t = 0, as the scene places it.
ObjectPose initialBodyPose(const RigidBody& body);

// A rigid body's volume (m³), centre of mass (world, t = 0) and inertia of unit density about it along its own axes:
// a sphere's and a box's in closed form, a mesh's from its volume integrals (voxelizer::massProperties, which throws
// MeshError for a mesh that encloses no definite volume).
voxelizer::MassProperties shapeMassProperties(const RigidBody& body);

// The farthest point of a rigid body's surface from its centre of mass (m): how far ω reaches (|v| + |ω| r is the
// fastest any point of it moves).
double rigidBodyReachM(const RigidBody& body);

// The fastest any point of a rigid body's surface moves, |v| + |ω| r with r its reach (m/s).
double rigidBodySurfaceSpeedMPerS(const RigidBody& body);

// Fills the body's volume, centre of mass, mass and inertia for a uniform density, from its shape's `shape`.
void setUniformDensity(RigidBody& body, const voxelizer::MassProperties& shape, double densityKgPerM3);

// Whether every number of the pose is finite (no NaN, no infinity): a pose that is not stops a run (exit 3).
bool isFinite(const ObjectPose& pose);

// Where the pose puts a point of its object's frame: positionM + orientation · pointM.
glm::dvec3 worldPoint(const ObjectPose& pose, const glm::dvec3& pointM);

// An object's mesh (SceneObject::meshM) where the pose puts it: each vertex through worldPoint, the triangles as
// they are, so vertex i of every frame's mesh is the same point of the object.
voxelizer::TriangleMesh posedMesh(const voxelizer::TriangleMesh& meshM, const ObjectPose& pose);

}  // namespace firn
