#include "mpi/Slabs.h"

#include <algorithm>
#include <cmath>

#include "Error.h"
#include "gpu/GpuLayout.h"

namespace firn::mpi {

Slabs::Slabs(const Scene& scene, int ranks)
    : originZM_(scene.grid.originM.z),
      cellSizeM_(scene.grid.cellSizeM),
      cubic_(scene.solver.kernel == Kernel::Cubic),
      layers_((scene.grid.cells.z + 1 + gpu::BLOCK_WIDTH - 1) / gpu::BLOCK_WIDTH) {
  if (ranks > layers_) {
    throw InputError(sceneFileName(scene) + ": grid.cells: " + std::to_string(ranks) + " processes need at least as "
                     "many layers of " + std::to_string(gpu::BLOCK_WIDTH) + " nodes along z, and the grid has " +
                     std::to_string(layers_) + "; run on fewer processes or make the grid taller in z");
  }
  for (int r = 0; r <= ranks; ++r) firstLayers_.push_back(int(std::int64_t(r) * layers_ / ranks));
}

int Slabs::layerOf(const glm::vec3& positionM) const {
  // The base node as blocksReached (sim/SceneUpload.cpp) and kernel.glsl find it. Off by one at a cell's edge
  // costs nothing but balance: a particle's sums are completed wherever its stencil reaches (MpiShare).
  const double cells = (double(positionM.z) - originZM_) / cellSizeM_;
  const int base = int(std::floor(cubic_ ? cells - 1.0 : cells - 0.5));
  return std::clamp(std::max(base, 0) / gpu::BLOCK_WIDTH, 0, layers_ - 1);
}

int Slabs::ownerOfLayer(int layer) const {
  // The last slab starting at or below the layer.
  const auto after = std::upper_bound(firstLayers_.begin() + 1, firstLayers_.end() - 1, layer);
  return int(after - firstLayers_.begin()) - 1;
}

void Slabs::balance(const std::vector<std::uint64_t>& particlesPerLayer) {
  const int ranks = this->ranks();
  std::uint64_t total = 0;
  for (const std::uint64_t count : particlesPerLayer) total += count;
  std::uint64_t below = 0;  // particles in the layers before `layer`
  int layer = 0;
  for (int r = 1; r < ranks; ++r) {
    // The first layer with at least r/ranks of the particles below it, leaving each slab a layer at least.
    const double target = double(total) * r / ranks;
    while (layer < layers_ && double(below) < target) below += particlesPerLayer[std::size_t(layer++)];
    const int first = std::clamp(layer, firstLayers_[std::size_t(r - 1)] + 1, layers_ - (ranks - r));
    while (layer < first) below += particlesPerLayer[std::size_t(layer++)];
    while (layer > first) below -= particlesPerLayer[std::size_t(--layer)];
    firstLayers_[std::size_t(r)] = first;
  }
}

std::string Slabs::describe() const {
  std::string text;
  for (int r = 0; r < ranks(); ++r) {
    if (r > 0) text += " | ";
    text += std::to_string(firstLayers_[std::size_t(r)]) + "–" + std::to_string(firstLayers_[std::size_t(r + 1)] - 1);
  }
  return text;
}

}  // namespace firn::mpi
