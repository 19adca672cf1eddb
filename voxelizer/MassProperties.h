#pragma once
// A closed mesh's volume, centroid and inertia, from its volume integrals by the divergence theorem (Mirtich 1996,
// "Fast and Accurate Computation of Polyhedral Mass Properties"; Eberly 2002's form over signed tetrahedra), for
// rigid bodies of uniform density.
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "voxelizer/Mesh.h"

namespace firn::voxelizer {

struct MassProperties {
  double volumeM3 = 0;
  glm::dvec3 centroidM{0.0};
  // ∫ (|r|² I − r rᵀ) dV about the centroid (m⁵): the inertia tensor of unit density; times ρ, kg·m².
  glm::dmat3 inertiaPerDensityM5{0.0};
};

// Throws MeshError naming the problem if the mesh is open (it encloses no definite volume) or encloses none; a
// mesh whose faces all point inward is measured as its outward twin.
MassProperties massProperties(const TriangleMesh& mesh);

}  // namespace firn::voxelizer
