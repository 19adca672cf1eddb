#pragma once
// The domain split among the ranks of a run over several processes (docs/distributed.md): into slabs of whole
// layers of the block grid along z (the block map's slowest axis), each rank's slab holding about the same number
// of particles. No MPI here: every rank computes the same slabs from the same counts.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/Scene.h"

namespace firn::mpi {

class Slabs {
 public:
  // `ranks` slabs of equal thickness over the scene's block layers. Throws InputError when the grid has fewer
  // layers of blocks along z than there are ranks (each slab holds at least one).
  Slabs(const Scene& scene, int ranks);

  int layers() const { return layers_; }
  int ranks() const { return int(firstLayers_.size()) - 1; }
  // The block layer of a particle at `positionM`: its stencil's base node's (kernel.glsl), clamped to the domain.
  int layerOf(const glm::vec3& positionM) const;
  int ownerOfLayer(int layer) const;
  int ownerOf(const glm::vec3& positionM) const { return ownerOfLayer(layerOf(positionM)); }
  // Rank r's slab is layers [firstLayer(r), firstLayer(r + 1)).
  int firstLayer(int rank) const { return firstLayers_[std::size_t(rank)]; }

  // Redraws the slabs so that each holds about 1/ranks of the particles counted per layer, each at least one layer
  // thick.
  void balance(const std::vector<std::uint64_t>& particlesPerLayer);
  // "0–11 | 12–19 | 20–31": the slabs' layers.
  std::string describe() const;

 private:
  double originZM_;
  double cellSizeM_;
  bool cubic_;
  int layers_;
  std::vector<int> firstLayers_;  // ranks + 1 entries, the last = layers_
};

}  // namespace firn::mpi
