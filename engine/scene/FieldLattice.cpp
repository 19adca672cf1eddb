#include "scene/FieldLattice.h"

#include <cmath>
#include <string>

#include <glm/common.hpp>

namespace firn {

FieldLattice fieldLattice(const voxelizer::TriangleMesh& mesh, const GridSpec& grid, double resolution) {
  FieldLattice lattice;
  lattice.spacingM = grid.cellSizeM / resolution;
  lattice.marginM = kFieldMarginCells * grid.cellSizeM;
  const voxelizer::Bounds box = voxelizer::bounds(mesh);
  lattice.samples = voxelizer::distanceFieldSamples(box, lattice.spacingM, lattice.marginM);
  lattice.triangles = double(mesh.triangles.size());
  return lattice;
}

voxelizer::DistanceField bakeField(const voxelizer::TriangleMesh& mesh, const GridSpec& grid, double resolution) {
  const FieldLattice lattice = fieldLattice(mesh, grid, resolution);
  return voxelizer::bakeDistanceField(mesh, lattice.spacingM, lattice.marginM);
}

std::vector<FieldLattice> fieldLattices(const Scene& scene) {
  std::vector<FieldLattice> lattices;
  for (std::size_t i = 0; i < scene.colliders.size(); ++i) {
    const Collider& collider = scene.colliders[i];
    if (collider.shape != ColliderShape::Mesh) continue;
    FieldLattice& lattice = lattices.emplace_back(fieldLattice(*collider.mesh, scene.grid, collider.fieldResolution));
    lattice.object = "colliders[" + std::to_string(i) + "]";
    lattice.path = collider.path;
  }
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i) {
    const RigidBody& body = scene.rigidBodies[i];
    if (body.shape != RigidShape::Mesh) continue;
    FieldLattice& lattice = lattices.emplace_back(fieldLattice(*body.mesh, scene.grid, body.fieldResolution));
    lattice.object = "rigid_bodies[" + std::to_string(i) + "]";
    lattice.path = body.path;
  }
  return lattices;
}

}  // namespace firn
