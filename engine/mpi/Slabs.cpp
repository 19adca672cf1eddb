#include "mpi/Slabs.h"

#include <algorithm>
#include <cmath>

#include "Error.h"
#include "gpu/GpuLayout.h"

namespace firn::mpi {

namespace {

// Rank r's first layer of `layers` split evenly.
std::vector<int> evenSplit(int layers, int ranks) {
  std::vector<int> first;
  for (int r = 0; r <= ranks; ++r) first.push_back(int(std::int64_t(r) * layers / ranks));
  return first;
}

}  // namespace

Slabs::Slabs(const Scene& scene, int ranks)
    : originM_(scene.grid.originM), cellSizeM_(scene.grid.cellSizeM), cubic_(scene.solver.kernel == Kernel::Cubic) {
  for (int a = 0; a < 3; ++a) layers_[std::size_t(a)] = (scene.grid.cells[a] + 1 + gpu::BLOCK_WIDTH - 1) / gpu::BLOCK_WIDTH;
  // Across z, or the axis with the most layers when z has too few.
  axis_ = layers_[2] >= ranks ? 2 : int(std::max_element(layers_.begin(), layers_.end()) - layers_.begin());
  if (ranks > layers()) {
    throw InputError(sceneFileName(scene) + ": grid.cells: " + std::to_string(ranks) + " processes need at least as "
                     "many layers of " + std::to_string(gpu::BLOCK_WIDTH) + " nodes along some axis, and the grid has " +
                     std::to_string(layers()) + " at most; run on fewer processes or make the grid larger");
  }
  firstLayers_ = evenSplit(layers(), ranks);
}

int Slabs::layerOf(const glm::vec3& positionM, int axis) const {
  // The base node as blocksReached (sim/SceneUpload.cpp) and kernel.glsl find it. Off by one at a cell's edge
  // costs nothing but balance: a particle's sums are completed wherever its stencil reaches (MpiShare).
  const double cells = (double(positionM[axis]) - originM_[axis]) / cellSizeM_;
  const int base = int(std::floor(std::clamp(cubic_ ? cells - 1.0 : cells - 0.5, -1.0, 1e9)));
  return std::clamp(std::max(base, 0) / gpu::BLOCK_WIDTH, 0, layers_[std::size_t(axis)] - 1);
}

int Slabs::ownerOfLayer(int layer) const {
  // The last slab starting at or below the layer.
  const auto after = std::upper_bound(firstLayers_.begin() + 1, firstLayers_.end() - 1, layer);
  return int(after - firstLayers_.begin()) - 1;
}

LayerCounts Slabs::emptyCounts() const {
  LayerCounts counts;
  for (int a = 0; a < 3; ++a) counts[std::size_t(a)].assign(std::size_t(layers_[std::size_t(a)]), 0);
  return counts;
}

void Slabs::count(const glm::vec3& positionM, LayerCounts& counts) const {
  for (int a = 0; a < 3; ++a) ++counts[std::size_t(a)][std::size_t(layerOf(positionM, a))];
}

void Slabs::balance(const LayerCounts& counts) {
  const int ranks = this->ranks();
  // The axis whose particles span the most layers, first to last: the finest split of them.
  int widest = 0;
  for (int a = 0; a < 3; ++a) {
    const std::vector<std::uint64_t>& perLayer = counts[std::size_t(a)];
    if (int(perLayer.size()) < ranks) continue;
    const auto first = std::find_if(perLayer.begin(), perLayer.end(), [](std::uint64_t c) { return c > 0; });
    const auto last = std::find_if(perLayer.rbegin(), perLayer.rend(), [](std::uint64_t c) { return c > 0; });
    const int span = first == perLayer.end() ? 0 : int((perLayer.rend() - last) - (first - perLayer.begin()));
    if (span > widest || (span == widest && a == 2)) {  // z on a tie: the slabs are then the map's contiguous layers
      widest = span;
      axis_ = a;
    }
  }
  const std::vector<std::uint64_t>& perLayer = counts[std::size_t(axis_)];
  const int layers = this->layers();
  firstLayers_ = evenSplit(layers, ranks);
  std::uint64_t total = 0;
  for (const std::uint64_t count : perLayer) total += count;
  std::uint64_t below = 0;  // particles in the layers before `layer`
  int layer = 0;
  for (int r = 1; r < ranks; ++r) {
    // The layer boundary with the count below it nearest r/ranks of the particles, leaving each slab a layer at
    // least.
    const double target = double(total) * r / ranks;
    while (layer < layers && double(below) < target) below += perLayer[std::size_t(layer++)];
    const double belowBefore = layer > 0 ? double(below - perLayer[std::size_t(layer - 1)]) : 0.0;
    const int nearest = layer > 0 && target - belowBefore < double(below) - target ? layer - 1 : layer;
    const int first = std::clamp(nearest, firstLayers_[std::size_t(r - 1)] + 1, layers - (ranks - r));
    while (layer < first) below += perLayer[std::size_t(layer++)];
    while (layer > first) below -= perLayer[std::size_t(--layer)];
    firstLayers_[std::size_t(r)] = first;
  }
}

std::string Slabs::describe() const {
  std::string text = std::string(1, "xyz"[axis_]) + ": ";
  for (int r = 0; r < ranks(); ++r) {
    if (r > 0) text += " | ";
    text += std::to_string(firstLayers_[std::size_t(r)]) + "–" + std::to_string(firstLayers_[std::size_t(r + 1)] - 1);
  }
  return text;
}

}  // namespace firn::mpi
