#pragma once
// The domain split among the ranks of a run over several processes (docs/distributed.md): into slabs of whole
// layers of the block grid across one axis, each rank's slab holding about the same number of particles. The axis is
// the one along which the particles span the most layers (the finest split), chosen whenever the slabs are drawn.
// No MPI here: every rank computes the same slabs from the same counts.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/Scene.h"

namespace firn::mpi {

// Particles per block layer, along x, y and z.
using LayerCounts = std::array<std::vector<std::uint64_t>, 3>;

class Slabs {
 public:
  // `ranks` slabs of equal thickness across z until balanced. Throws InputError when the grid has fewer layers of
  // blocks than ranks along every axis (each slab holds at least one).
  Slabs(const Scene& scene, int ranks);

  int axis() const { return axis_; }
  int layers() const { return layers_[std::size_t(axis_)]; }
  int ranks() const { return int(firstLayers_.size()) - 1; }
  // The block layer along `axis` of a particle at `positionM`: its stencil's base node's (kernel.glsl), clamped to
  // the domain.
  int layerOf(const glm::vec3& positionM, int axis) const;
  int ownerOf(const glm::vec3& positionM) const { return ownerOfLayer(layerOf(positionM, axis_)); }
  int ownerOfLayer(int layer) const;
  // Rank r's slab is layers [firstLayer(r), firstLayer(r + 1)) along axis().
  int firstLayer(int rank) const { return firstLayers_[std::size_t(rank)]; }

  // Empty counts, sized for the grid's layers along each axis, and the counts of particles at `positionsM`.
  LayerCounts emptyCounts() const;
  void count(const glm::vec3& positionM, LayerCounts& counts) const;
  // Redraws the slabs: across the axis whose particles span the most layers (of those with a layer per rank at
  // least), each slab holding about 1/ranks of the particles and at least one layer.
  void balance(const LayerCounts& counts);
  // "z: 0–11 | 12–19 | 20–31": the slabs' layers.
  std::string describe() const;

 private:
  glm::dvec3 originM_;
  double cellSizeM_;
  bool cubic_;
  std::array<int, 3> layers_;
  int axis_ = 2;
  std::vector<int> firstLayers_;  // ranks + 1 entries, the last = layers()
};

}  // namespace firn::mpi
