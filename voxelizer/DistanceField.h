#pragma once
// A triangle mesh's signed distance field, sampled on a regular lattice in the mesh's own coordinates, for mesh
// colliders and rigid bodies (docs/algorithm.md, Mesh colliders). |φ| is the exact distance to the nearest
// triangle at every sample; the sign comes from the generalized winding number (WindingNumber.h), as the voxelizer
// fills meshes, so open, flipped and overlapping artist meshes have an inside: negative where |w| ≥ 0.5.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "voxelizer/Mesh.h"

namespace firn::voxelizer {

// What the GPU needs of a triangle to measure exact distances near the surface (common/shared_functions.h,
// meshRestDistance). The outward unit normals of its features, for telling inside from outside by the feature
// nearest a point (Bærentzen & Aanæs 2005, angle-weighted pseudonormals): its face's; each edge's, the sum of the
// faces that share it; each corner's, the faces around it weighted by their angles there. "Outward" is as the
// field's sign says: a face whose samples the winding number puts on its back is turned (a flipped or inside-out
// mesh). And the triangle across each edge (vertices welded by position; −1 at a hole's border), where a point
// whose nearest feature is that edge may find a nearer face.
struct TriangleFeatures {
  glm::dvec3 face{0.0};
  glm::dvec3 edges[3];    // ab, bc, ca
  glm::dvec3 corners[3];  // a, b, c
  std::int32_t across[3] = {-1, -1, -1};  // the triangle beyond ab, bc, ca
};

struct DistanceField {
  glm::dvec3 originM{0.0};        // where sample (0, 0, 0) lies, in the mesh's coordinates
  double spacingM = 0;            // between neighbouring samples, on every axis
  glm::ivec3 samples{0};          // per axis
  std::vector<float> distancesM;  // φ (m) per sample, x fastest, then y, then z; negative inside
  std::vector<std::int32_t> nearestTriangles;  // per sample: the triangle whose distance |φ| is
  std::vector<TriangleFeatures> features;      // per triangle of the mesh

  std::size_t sampleCount() const { return std::size_t(samples.x) * std::size_t(samples.y) * std::size_t(samples.z); }
  float at(int x, int y, int z) const {
    return distancesM[(std::size_t(z) * std::size_t(samples.y) + std::size_t(y)) * std::size_t(samples.x) + std::size_t(x)];
  }
};

// Samples per axis of the lattice below, ⌈(extent + 2 marginM) / spacingM⌉ + 1 (less a rounding's slack off a whole
// number of steps), as doubles: a wild scene's count can be reported before anything is refused.
glm::dvec3 distanceFieldSamples(const Bounds& meshBox, double spacingM, double marginM);

// The lattice bakeDistanceField samples: the mesh's box grown by marginM on every side, in whole steps of spacingM
// from its low corner (so the scene can count a field's memory before baking it).
DistanceField distanceFieldLattice(const Bounds& meshBox, double spacingM, double marginM);

// Bakes the field of `mesh` on distanceFieldLattice(bounds(mesh), spacingM, marginM), on `threadCount` threads (0:
// as many as the machine has; the field's bytes are the same for any count). Throws MeshError if the mesh has no
// triangles or more than 2^24 (the GPU names a sample's nearest triangle by a float), a triangle indexes past the
// vertices, a vertex is not finite, or the spacing or the margin is not positive and finite.
// How (DistanceField.cpp, after Bridson's makelevelset3): exact distances in a band two spacings wide around each
// triangle; the closest triangles carried outward by sweeps and relaxed until no sample has a nearer triangle among
// its six neighbours' or among those sharing a corner with its own. Distances to the triangle found are always
// exact, and the triangle is the nearest wherever that lies within the band; beyond it, propagation can miss a
// nearest triangle whose region holds no sample near the band (a near tie, in practice): against every triangle's
// distance at every sample the tests' meshes show no difference beyond float rounding. The sign is the winding
// number's at every sample within half a spacing of the surface, and elsewhere that of a few probes per region
// the surface does not cross (every sample's of a region whose probes disagree, as around a hole). The features'
// normals are the faces' as wound, turned by patches of faces wound alike where most samples over them (nearest to
// one within a spacing, and more above or below it than beside it) have the other sign.
DistanceField bakeDistanceField(const TriangleMesh& mesh, double spacingM, double marginM);
DistanceField bakeDistanceField(const TriangleMesh& mesh, double spacingM, double marginM, unsigned threadCount);

// The steepest |∇φ| of the field's trilinear interpolation anywhere in its lattice: within a cell ∂φ/∂x is a blend
// of the differences along the cell's four x edges over the spacing, so at most the largest of them, and likewise
// for y and z; the most, over the cells, of the root of their squares. About 1 for a distance field; steeper where
// the sign flips away from the surface (around a hole). 0 for a lattice of fewer than two samples on an axis.
double steepestSlope(const DistanceField& field);

}  // namespace firn::voxelizer
