#pragma once
// Mesh → particles: load a mesh, place it, and fill its inside (by the generalized winding number) with
// particles on a jittered lattice or by Poisson-disk sampling.
#include <vector>

#include <glm/vec3.hpp>

#include "voxelizer/Mesh.h"
#include "voxelizer/Samplers.h"
#include "voxelizer/WindingNumber.h"

namespace firn::voxelizer {

// The particles inside `mesh` (WindingNumber::inside, default accuracy) within its bounding box.
std::vector<glm::dvec3> voxelize(const TriangleMesh& mesh, const SamplingOptions& options);

}  // namespace firn::voxelizer
