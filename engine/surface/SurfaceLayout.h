#pragma once
// The surface reconstruction's GPU contract (shaders/surface/surface_contract.h) as C++, in namespace firn::gpu
// beside the simulation's (gpu/GpuLayout.h, gpu/GpuFunctions.h). Sizes are pinned here; every member's offset is
// checked against the driver's by tests/gl/SurfaceTest.cpp.
#include <glm/vec3.hpp>

#include "gpu/GpuFunctions.h"
#include "gpu/GpuLayout.h"

namespace firn::gpu {

#include "surface/surface_contract.h"

// The surface's bindings lie in its range of the contract (gpu/GpuLayout.h checks the ranges against each other).
// The prefix scan's values are the counts' binding (it scans them in place).
constexpr int kSurfaceBindingPoints[] = {
    FIRN_BINDING_SURFACE_HEADER,   FIRN_BINDING_SURFACE_DENSITY,   FIRN_BINDING_SURFACE_SUMS,
    FIRN_BINDING_SURFACE_CELLS,    FIRN_BINDING_SURFACE_COUNTS,    FIRN_BINDING_SURFACE_VERTICES,
    FIRN_BINDING_SURFACE_INDICES,  FIRN_BINDING_SURFACE_MATERIALS, FIRN_BINDING_SURFACE_PARTICLE_COLORS,
    FIRN_BINDING_SCAN_SUMS};
static_assert(FIRN_BINDING_SCAN_VALUES == FIRN_BINDING_SURFACE_COUNTS, "the scan's values are the counts");
static_assert(bindingsWithin(kSurfaceBindingPoints, kSurfaceBindings), "a surface binding outside its range");
static_assert(sizeof(SurfaceUniforms) == 64, "std140 SurfaceUniforms");
static_assert(sizeof(SurfaceHeader) == 32, "std430 SurfaceHeader");
static_assert(sizeof(SurfaceNodeSums) == 32, "std430 SurfaceNodeSums");
static_assert(sizeof(SurfaceVertex) == 64, "std430 SurfaceVertex");

}  // namespace firn::gpu
