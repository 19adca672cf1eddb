#pragma once
// A collider's rigid motion (docs/algorithm.md, Colliders): its pose at a time, from its keyframes or its constant
// velocity, and the velocities that carry it through the segment of motion holding that time.
#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "scene/Scene.h"

namespace firn {

// Where a collider is at a time: a point x_rest of its shape at rest is at pivotM + rotation (x_rest − pivot).
// Between two keyframes the pivot moves at a constant velocity and the collider turns at a constant angular
// velocity (eq. 32), so the pose at any later time of the segment is this one advanced rigidly.
struct RigidPose {
  glm::dvec3 pivotM{0.0};                   // where the pivot is
  glm::dquat rotation{1, 0, 0, 0};          // the turn from rest, about the pivot
  glm::dvec3 velocityMPerS{0.0};            // the pivot's velocity, over the segment
  glm::dvec3 angularVelocityRadPerS{0.0};   // ω, over the segment (world axes)
  double segmentStartS = 0;                 // when the segment holding the time began (0 before the first keyframe)
};

// The pose at `timeS` (eqs. 31–32): before the first keyframe the first's, after the last the last's (at rest);
// without keyframes, translated by velocityMPerS · t.
RigidPose colliderPose(const Collider& collider, double timeS);

// A keyframe's turn as a unit quaternion (R = R_z R_y R_x, voxelizer::rotationMatrix).
glm::dquat keyframeRotation(const ColliderKeyframe& keyframe);

// The angle (rad) of the shorter turn from `from` to `to`: slerp's way between two keyframes.
double turnBetweenRad(const glm::dquat& from, const glm::dquat& to);

// How far the collider's solid reaches from its pivot, within the scene's domain (a plane's extends past it).
double colliderReachM(const Scene& scene, const Collider& collider);

// The fastest a point of the collider's solid in the domain moves: over the segments, |v| + |ω| reach.
double fastestColliderSpeedMPerS(const Scene& scene, const Collider& collider);

}  // namespace firn
