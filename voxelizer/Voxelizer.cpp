#include "voxelizer/Voxelizer.h"

#include <glm/vector_relational.hpp>

namespace firn::voxelizer {

std::vector<glm::dvec3> voxelize(const TriangleMesh& mesh, const SamplingOptions& options) {
  const WindingNumber windingNumber(mesh);
  const Bounds box = bounds(mesh);
  // The box test first: it is free, and it keeps the lattice's jittered candidates beyond the box out even
  // where an open mesh's winding number reaches 0.5 there.
  return samplePoints(
      box,
      [&](const glm::dvec3& pointM) {
        return glm::all(glm::greaterThanEqual(pointM, box.minM)) && glm::all(glm::lessThanEqual(pointM, box.maxM)) &&
               windingNumber.inside(pointM);
      },
      options);
}

}  // namespace firn::voxelizer
