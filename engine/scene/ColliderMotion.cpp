#include "scene/ColliderMotion.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "voxelizer/Mesh.h"

namespace firn {

glm::dquat keyframeRotation(const ColliderKeyframe& keyframe) {
  return glm::normalize(glm::quat_cast(voxelizer::rotationMatrix(keyframe.rotateDeg)));
}

namespace {

// The turn from `from` to `to` the shorter way, q_Δ = q₁ q₀⁻¹ with a non-negative scalar part (q and −q are the
// same rotation; slerp takes the one nearer).
glm::dquat shorterTurn(const glm::dquat& from, const glm::dquat& to) {
  glm::dquat turn = to * glm::conjugate(from);
  if (turn.w < 0) turn = -turn;
  return turn;
}

// ω of the turn q_Δ done in `durationS`: its axis times its angle over the duration (eq. 32).
glm::dvec3 angularVelocityOf(const glm::dquat& turn, double durationS) {
  const glm::dvec3 vectorPart(turn.x, turn.y, turn.z);
  const double sinHalf = glm::length(vectorPart);
  if (sinHalf == 0) return glm::dvec3(0.0);
  const double angleRad = 2 * std::atan2(sinHalf, turn.w);
  return vectorPart * (angleRad / (sinHalf * durationS));
}

// The turn of angle |ω| t about ω's axis.
glm::dquat turnOver(const glm::dvec3& angularVelocityRadPerS, double durationS) {
  const double speedRadPerS = glm::length(angularVelocityRadPerS);
  if (speedRadPerS == 0) return {1, 0, 0, 0};
  const double halfAngleRad = 0.5 * speedRadPerS * durationS;
  const glm::dvec3 vectorPart = angularVelocityRadPerS * (std::sin(halfAngleRad) / speedRadPerS);
  return {std::cos(halfAngleRad), vectorPart.x, vectorPart.y, vectorPart.z};
}

}  // namespace

double turnBetweenRad(const glm::dquat& from, const glm::dquat& to) {
  const glm::dquat turn = shorterTurn(from, to);
  return 2 * std::atan2(glm::length(glm::dvec3(turn.x, turn.y, turn.z)), turn.w);
}

RigidPose colliderPose(const Collider& collider, double timeS) {
  RigidPose pose;
  const std::vector<ColliderKeyframe>& keys = collider.keyframes;
  if (keys.empty()) {
    pose.pivotM = collider.pivotM + collider.velocityMPerS * timeS;
    pose.velocityMPerS = collider.velocityMPerS;
    return pose;
  }
  // The last keyframe at or before the time; before the first, the first's pose, held since t = 0.
  const auto next = std::upper_bound(keys.begin(), keys.end(), timeS,
                                     [](double t, const ColliderKeyframe& key) { return t < key.timeS; });
  if (next == keys.begin()) {
    pose.pivotM = collider.pivotM + keys.front().translateM;
    pose.rotation = keyframeRotation(keys.front());
    return pose;
  }
  const ColliderKeyframe& from = *(next - 1);
  pose.segmentStartS = from.timeS;
  const glm::dquat fromRotation = keyframeRotation(from);
  if (next == keys.end()) {
    pose.pivotM = collider.pivotM + from.translateM;
    pose.rotation = fromRotation;
    return pose;
  }
  // Eqs. 31–32: T linear and R by slerp, so v and ω are constant over the segment and the pose is R_ω(t − t_i) R_i.
  const double durationS = next->timeS - from.timeS;
  const double sinceS = timeS - from.timeS;
  pose.velocityMPerS = (next->translateM - from.translateM) / durationS;
  pose.angularVelocityRadPerS = angularVelocityOf(shorterTurn(fromRotation, keyframeRotation(*next)), durationS);
  pose.pivotM = collider.pivotM + from.translateM + pose.velocityMPerS * sinceS;
  pose.rotation = glm::normalize(turnOver(pose.angularVelocityRadPerS, sinceS) * fromRotation);
  return pose;
}

double colliderReachM(const Scene& scene, const Collider& collider) {
  glm::dvec3 lowM = scene.domainMinM(), highM = scene.domainMaxM();
  if (collider.shape == ColliderShape::Sphere) {
    return glm::length(collider.centerM - collider.pivotM) + collider.radiusM;
  }
  if (collider.shape == ColliderShape::Box) {
    lowM = collider.minM;
    highM = collider.maxM;
  }
  if (collider.shape == ColliderShape::Mesh) {
    const voxelizer::Bounds box = voxelizer::bounds(*collider.mesh);
    lowM = box.minM;
    highM = box.maxM;
  }
  // The farthest corner of the box (or, for a plane, of the domain) from the pivot.
  const glm::dvec3 farthestM = glm::max(glm::abs(lowM - collider.pivotM), glm::abs(highM - collider.pivotM));
  return glm::length(farthestM);
}

double fastestColliderSpeedMPerS(const Scene& scene, const Collider& collider) {
  if (collider.keyframes.empty()) return glm::length(collider.velocityMPerS);
  const double reachM = colliderReachM(scene, collider);
  double fastest = 0;
  for (std::size_t i = 1; i < collider.keyframes.size(); ++i) {
    const RigidPose pose = colliderPose(collider, collider.keyframes[i - 1].timeS);
    fastest = std::max(fastest, glm::length(pose.velocityMPerS) + glm::length(pose.angularVelocityRadPerS) * reachM);
  }
  return fastest;
}

}  // namespace firn
