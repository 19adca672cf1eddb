#pragma once
// The functions the host shares with the shaders (shaders/common/shared_functions.h), in namespace firn::gpu:
// GLSL's built-ins are glm's (and std's, for the double-precision templates).
#include <cmath>
#include <vector>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <glm/vector_relational.hpp>

#include "gpu/GpuLayout.h"

namespace firn::gpu {

using vec3 = glm::vec3;
using vec4 = glm::vec4;
using ivec3 = glm::ivec3;
using glm::abs;
using glm::any;
using glm::clamp;
using glm::floor;
using glm::min;
using glm::cross;
using glm::dot;
using glm::greaterThan;
using glm::length;
using glm::max;
using glm::normalize;
using glm::sign;
using std::cos;
using std::sin;
using glm::ivec4;
using std::sqrt;

#include "common/shared_functions.h"

// A collider's signed distance φ at x (m, negative inside its solid) and its outward unit normal there at timeS,
// as common/colliders.glsl's colliderDistance measures it: `fieldSamples` is the field buffer the table's mesh
// entries index (SceneUpload.h, ColliderFields).
inline float colliderDistance(const ColliderParams& c, const std::vector<float>& fieldSamples, vec3 x, float timeS,
                              vec3& normal) {
  const vec3 fromPivot = colliderRestPoint(c, x, timeS);
  vec3 restNormal;
  float distanceM;
  if (c.shapeBoundary.x == SHAPE_MESH) {
    distanceM = meshRestDistance(fieldSamples, c, fromPivot, restNormal);
  } else {
    distanceM = shapeDistance(c, fromPivot, restNormal);
  }
  normal = colliderWorldDirection(c, restNormal, timeS);
  return distanceM;
}

}  // namespace firn::gpu
