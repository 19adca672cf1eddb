#pragma once
// Mesh → particles: load a mesh, place it, and fill its inside (by the generalized winding number) with
// particles on a jittered lattice or by Poisson-disk sampling.
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "voxelizer/Mesh.h"
#include "voxelizer/Samplers.h"
#include "voxelizer/WindingNumber.h"

namespace firn::voxelizer {

// The particles inside `mesh` (WindingNumber::inside, default accuracy) within its bounding box.
std::vector<glm::dvec3> voxelize(const TriangleMesh& mesh, const SamplingOptions& options);

// What voxelize(mesh, options) will yield, known before it runs: the volume inside, measured by voxelizing on a
// lattice coarse enough to have at most kEstimateLatticePoints points over the mesh's box, and the surface's
// area. Good for parts thicker than that lattice's spacing; options.maxPoints guards against the rest.
constexpr double kEstimateLatticePoints = 32768;
SampleEstimate estimateVoxelize(const TriangleMesh& mesh, const SamplingOptions& options);

// Why `mesh` yielded no particle at `spacingM`, with its bounds and a spacing that would fill it, or what is
// wrong with it if no spacing would. Callers prefix the file.
std::string whyNoParticles(const TriangleMesh& mesh, const MeshSurface& surface, double spacingM);

// A warning, or "": `particles` at `spacingM` fill an open mesh only as a sheet, on average thinner over its
// surface than one spacing (one layer of particles). An open mesh that encloses next to nothing is filled only where the winding
// number's rounding passes ½ right at its surface, more so the finer the spacing.
std::string sheetWarning(const MeshSurface& surface, std::size_t particles, double spacingM);

}  // namespace firn::voxelizer
