#pragma once
// The lattices of the scene's signed distance fields, one per mesh collider and mesh rigid body, sized before any
// is baked: where the fields' memory is counted (run/Budget.cpp) and reported (run/Preflight.cpp), and what the
// baking is asked for (voxelizer/DistanceField.h).
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/Scene.h"
#include "voxelizer/DistanceField.h"
#include "voxelizer/Mesh.h"

namespace firn {

// The field covers the placed mesh's box grown by this many grid cells on every side, so that it is defined
// wherever a particle near the surface, or a node of its stencil (2 cells away with the cubic kernel), asks for it.
constexpr double kFieldMarginCells = 3;
// The floats of a triangle's record in the field buffer (gpu::FIELD_TRIANGLE_FLOATS; sim/SceneUpload.cpp checks).
constexpr int kFieldTriangleFloats = 33;

struct FieldLattice {
  std::string object;  // "colliders[1]", "rigid_bodies[0]": as errors and the pre-flight name them
  std::string path;    // the mesh file, as the scene names it
  double spacingM = 0; // cell_size / resolution
  double marginM = 0;  // kFieldMarginCells cells
  // Per axis; doubles, so that the count of a wild scene cannot overflow before it is refused.
  glm::dvec3 samples{0.0};

  double triangles = 0;  // of the mesh: the field buffer holds a record of each (kFieldTriangleFloats)

  double sampleCount() const { return samples.x * samples.y * samples.z; }
  // Per sample its φ and its nearest triangle's number, and each triangle's record: 32-bit floats.
  double bytes() const { return 4 * (2 * sampleCount() + kFieldTriangleFloats * triangles); }
};

// The size of the lattice the mesh's field is baked on (voxelizer::distanceFieldSamples), counted before baking.
FieldLattice fieldLattice(const voxelizer::TriangleMesh& mesh, const GridSpec& grid, double resolution);

// The field of `mesh` baked on its lattice (voxelizer/DistanceField.h), for the simulation's upload.
voxelizer::DistanceField bakeField(const voxelizer::TriangleMesh& mesh, const GridSpec& grid, double resolution);

// Every mesh collider's field, then every mesh rigid body's, in the scene's order.
std::vector<FieldLattice> fieldLattices(const Scene& scene);

}  // namespace firn
