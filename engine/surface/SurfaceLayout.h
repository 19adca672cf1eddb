#pragma once
// The surface reconstruction's GPU contract (shaders/surface/surface_contract.h) as C++, in namespace firn::gpu
// beside the simulation's (sim/GpuLayout.h, sim/GpuFunctions.h). Sizes are pinned here; every member's offset is
// checked against the driver's by tests/gl/SurfaceTest.cpp.
#include <glm/vec3.hpp>

#include "sim/GpuFunctions.h"
#include "sim/GpuLayout.h"

namespace firn::gpu {

using ivec3 = glm::ivec3;

#include "surface/surface_contract.h"

// The reconstruction runs with the simulation's particle buffers still bound, so its bindings must start past
// the simulation's last (the semi-implicit solver's status, 19).
static_assert(FIRN_BINDING_SURFACE_HEADER > FIRN_BINDING_SOLVER_STATUS, "surface bindings overlap the simulation's");
static_assert(sizeof(SurfaceUniforms) == 80, "std140 SurfaceUniforms");
static_assert(sizeof(SurfaceHeader) == 32, "std430 SurfaceHeader");
static_assert(sizeof(SurfaceNodeSums) == 32, "std430 SurfaceNodeSums");
static_assert(sizeof(SurfaceVertex) == 64, "std430 SurfaceVertex");

}  // namespace firn::gpu
