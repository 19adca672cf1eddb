#include "surface/PrefixScan.h"

#include <algorithm>

#include <glm/vec2.hpp>

#include "surface/SurfaceLayout.h"

namespace firn::surface {

namespace {

std::size_t chunksOf(std::size_t count) { return (count + gpu::SCAN_CHUNK - 1) / gpu::SCAN_CHUNK; }

}  // namespace

PrefixScan::PrefixScan(const gl::ShaderLibrary& library, const gl::ShaderOptions& options, int maxWorkGroupsX)
    : reduce_(library, "surface/scan_reduce.comp", options),
      distribute_(library, "surface/scan_distribute.comp", options),
      maxWorkGroupsX_(maxWorkGroupsX) {}

void PrefixScan::run(const gl::Buffer& values, std::size_t count, const gl::BufferBindings& buffers,
                     gl::PassTimer& timer) {
  // Level 0 is `values`; level k + 1 holds one sum per chunk of level k, up to the level of a single chunk.
  std::vector<std::size_t> counts = {count};
  while (counts.back() > gpu::SCAN_CHUNK) counts.push_back(chunksOf(counts.back()));
  const std::size_t levelsAbove = counts.size() - 1;
  if (levels_.size() < levelsAbove) levels_.resize(levelsAbove);
  for (std::size_t k = 0; k < levelsAbove; ++k) {
    const std::size_t bytes = counts[k + 1] * sizeof(glm::uvec2);
    if (levels_[k].bytes() < bytes) levels_[k] = gl::Buffer(bytes);
  }
  const auto level = [&](std::size_t k) -> const gl::Buffer& { return k == 0 ? values : levels_[k - 1]; };

  // A level's values and the sums above them (the top level has none: distribute reads none, and its values stand in).
  const auto levelBuffers = [&](std::size_t k) {
    gl::BufferBindings levelBuffers = buffers;
    levelBuffers.storage(FIRN_BINDING_SCAN_VALUES, level(k));
    levelBuffers.storage(FIRN_BINDING_SCAN_SUMS, level(std::min(k + 1, levelsAbove)));
    return levelBuffers;
  };
  for (std::size_t k = 0; k < levelsAbove; ++k) {
    reduce_.set("elementCount", static_cast<unsigned>(counts[k]));
    reduce_.runOver(chunksOf(counts[k]), maxWorkGroupsX_, levelBuffers(k), timer);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
  for (std::size_t k = levelsAbove + 1; k-- > 0;) {
    const bool hasLevelAbove = k < levelsAbove;
    distribute_.set("elementCount", static_cast<unsigned>(counts[k]));
    distribute_.program().set("hasLevelAbove", hasLevelAbove ? 1 : 0);
    distribute_.runOver(chunksOf(counts[k]), maxWorkGroupsX_, levelBuffers(k), timer);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
}

}  // namespace firn::surface
