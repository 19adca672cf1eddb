#pragma once
// The functions the host shares with the shaders (shaders/common/shared_functions.h), in namespace firn::gpu:
// GLSL's built-ins are glm's (and std's, for the double-precision templates).
#include <cmath>

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
using glm::abs;
using glm::any;
using glm::cross;
using glm::dot;
using glm::greaterThan;
using glm::length;
using glm::max;
using glm::normalize;
using glm::sign;
using std::cos;
using std::sin;
using std::sqrt;

#include "common/shared_functions.h"

}  // namespace firn::gpu
