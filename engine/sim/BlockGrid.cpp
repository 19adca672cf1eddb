#include "sim/BlockGrid.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "gpu/GpuLayout.h"

namespace firn {

namespace {

std::size_t nodeStorageBytes(std::size_t blocks) { return blocks * gpu::BLOCK_NODES * sizeof(glm::ivec4); }

}  // namespace

BlockGrid::BlockGrid(const GpuStateLayout& layout, const gl::ShaderLibrary& library, const gl::ShaderOptions& options,
                     const gl::ContextInfo& gl)
    : blocksPerAxis_(layout.blocksPerAxis()),
      withImpulse_(layout.impulse),
      maxWorkGroupsX_(gl.maxComputeWorkGroupCountX),
      prepareBlocks_(library, "sim/prepare_blocks.comp", options),
      releaseBlocks_(library, "sim/release_blocks.comp", options, offsetof(gpu::BlockTableHeader, releaseDispatch)),
      markBlocks_(library, "sim/mark_blocks.comp", options),
      countBlocks_(library, "sim/count_blocks.comp", options),
      binCount_(library, "sim/bin_count.comp", options),
      binScan_(library, "sim/bin_scan.comp", options),
      binScanBlock_(library, "sim/bin_scan_block.comp", options),
      blockOffsets_(library, "sim/block_offsets.comp", options),
      binPlace_(library, "sim/bin_place.comp", options),
      orderTiles_(library, "sim/order_tiles.comp", options),
      shaderOptions_(options) {
  blockMap_ = gl::Buffer(layout.blockMapBytes()).labelled("block grid: block map");
  allocateParticles(layout.particleCapacity);
}

void BlockGrid::allocateParticles(std::size_t particleCapacity) {
  sortedParticles_ = gl::Buffer(particleCapacity * sizeof(std::uint32_t)).labelled("block grid: sorted particles");
  particleRanks_ = gl::Buffer(particleCapacity * sizeof(std::uint32_t)).labelled("block grid: particle ranks");
}

void BlockGrid::allocatePool(std::size_t capacity) {
  capacity_ = capacity;
  // A zero-filled pool: every block free, every slot clean (release_blocks.comp keeps them so).
  momentumMass_ = gl::Buffer(nodeStorageBytes(capacity)).labelled("block grid: momentum, mass");
  impulseSums_ = withImpulse_ ? gl::Buffer(nodeStorageBytes(capacity)).labelled("block grid: impulse") : gl::Buffer();
  bins_ = gl::Buffer(capacity * gpu::BLOCK_NODES * sizeof(glm::uvec2)).labelled("block grid: bins");
  tileOrder_ = gl::Buffer(capacity * gpu::BLOCK_TILES * sizeof(std::uint32_t)).labelled("block grid: tile order");
  blockMap_.zero();
  gpu::BlockTableHeader header{};
  header.blockCounts.y = static_cast<std::uint32_t>(capacity);
  blockTable_ = gl::Buffer(sizeof header + capacity * sizeof(gpu::BlockSlot)).labelled("block grid: block table");
  blockTable_.upload(0, sizeof header, &header);
}

BlockUsage BlockGrid::usage() const {
  const gpu::BlockTableHeader header = blockTable_.read<gpu::BlockTableHeader>(1)[0];
  BlockUsage usage;
  usage.lastStep = std::min<std::size_t>(header.blockCounts.x, capacity_);
  // A step with no blocks (the particles all gone, or none yet) leaves the count as it was: any count is correct.
  if (usage.lastStep > 0) countedBlocks_ = usage.lastStep;
  usage.mostInAStep = std::max(header.blockCounts.x, header.blockCounts.w);
  usage.capacity = capacity_;
  usage.poolBytes = momentumMass_.bytes() + impulseSums_.bytes() + bins_.bytes() + tileOrder_.bytes() + blockTable_.bytes();
  usage.mapBytes = blockMap_.bytes();
  return usage;
}

void BlockGrid::sortParticles(std::size_t particles, SortFor sortFor, const gl::BufferBindings& buffers,
                              gl::PassTimer& timer) const {
  const gl::Buffer& table = blockTable_;
  prepareBlocks_.runOnce(buffers, timer);
  run(releaseBlocks_, sortFor, buffers, timer);
  markBlocks_.runOver(particles, maxWorkGroupsX_, buffers, timer);
  if (claimImageBlocks_) claimImageBlocks_->runOver(particles, maxWorkGroupsX_, buffers, timer);
  countBlocks_.runOnce(buffers, timer);
  binCount_.runOver(particles, maxWorkGroupsX_, buffers, timer);
  if (sortFor == SortFor::Tiles) {
    binScan_.runIndirect(table, offsetof(gpu::BlockTableHeader, blockRunDispatch), buffers, timer);
  } else {
    runOverBlocks(binScanBlock_, buffers, timer);
  }
  blockOffsets_.runOnce(buffers, timer);
  binPlace_.runOver(particles, maxWorkGroupsX_, buffers, timer);
  if (sortFor == SortFor::Tiles) {
    orderTiles_.runIndirect(table, offsetof(gpu::BlockTableHeader, blockDispatch), buffers, timer);
  }
}

void BlockGrid::runOverBlocks(const gl::ComputePass& pass, const gl::BufferBindings& buffers,
                              gl::PassTimer& timer) const {
  const std::size_t blocks = countedBlocks_ == 0 ? capacity_ : std::min(countedBlocks_ + countedBlocks_ / 8, capacity_);
  pass.runGroups(std::max<std::size_t>(blocks, 1), maxWorkGroupsX_, buffers, timer);
}

BlockGrid::StepPass::StepPass(const gl::ShaderLibrary& library, const std::string& shader,
                              const gl::ShaderOptions& options, std::size_t tableDispatch)
    : fromTable(library, shader, options), tableDispatch(tableDispatch) {
  gl::ShaderOptions stridingOptions = options;
  stridingOptions.defines.emplace_back("FIRN_STRIDE_OVER_BLOCKS", "1");
  striding = gl::ComputePass(library, shader, stridingOptions);
}

void BlockGrid::run(const StepPass& pass, SortFor sortFor, const gl::BufferBindings& buffers,
                    gl::PassTimer& timer) const {
  if (sortFor == SortFor::Blocks) {
    runOverBlocks(pass.striding, buffers, timer);
  } else {
    pass.fromTable.runIndirect(blockTable_, pass.tableDispatch, buffers, timer);
  }
}

void BlockGrid::publish(gl::BufferBindings& bindings) const {
  bindings.storage(FIRN_BINDING_GRID_MOMENTUM_MASS, momentumMass_);
  if (impulseSums_) bindings.storage(FIRN_BINDING_GRID_IMPULSE, impulseSums_);
  bindings.storage(FIRN_BINDING_BLOCK_TABLE, blockTable_);
  bindings.storage(FIRN_BINDING_BLOCK_MAP, blockMap_);
  bindings.storage(FIRN_BINDING_BINS, bins_);
  bindings.storage(FIRN_BINDING_SORTED_PARTICLES, sortedParticles_);
  bindings.storage(FIRN_BINDING_PARTICLE_RANKS, particleRanks_);
  bindings.storage(FIRN_BINDING_TILE_ORDER, tileOrder_);
}

std::vector<std::uint32_t> BlockGrid::particlesOutside(std::size_t particles, int axis, int firstLayer, int endLayer,
                                                       const gl::BufferBindings& buffers) {
  const std::uint32_t none = 0;
  const std::size_t counter = offsetof(gpu::BlockTableHeader, migration);
  blockTable_.upload(counter, sizeof none, &none);
  gl::PassTimer untimed;
  if (!listLeavers_) listLeavers_.emplace(gl::ShaderLibrary(), "sim/list_leavers.comp", shaderOptions_);
  listLeavers_->set("particles", unsigned(particles)).set("slabAxis", unsigned(axis));
  listLeavers_->set("slabFirstLayer", unsigned(firstLayer)).set("slabEndLayer", unsigned(endLayer));
  listLeavers_->runOver(particles, maxWorkGroupsX_, buffers, untimed);
  return listedParticles(counter);
}

std::vector<std::uint32_t> BlockGrid::mirroredParticles() const {
  return listedParticles(offsetof(gpu::BlockTableHeader, mirrorDispatch) + 3 * sizeof(std::uint32_t));
}

std::vector<std::uint32_t> BlockGrid::listedParticles(std::size_t counterOffset) const {
  std::uint32_t listed = 0;
  blockTable_.download(counterOffset, sizeof listed, &listed);
  std::vector<std::uint32_t> particles = particleRanks_.read<std::uint32_t>(listed);
  std::sort(particles.begin(), particles.end());  // the atomics' order is the GPU's; the list's is the particles'
  return particles;
}

std::vector<ActiveBlock> BlockGrid::activeBlocks() const {
  std::vector<gpu::BlockSlot> slots(usage().lastStep);
  blockTable_.download(sizeof(gpu::BlockTableHeader), slots.size() * sizeof(gpu::BlockSlot), slots.data());
  std::vector<ActiveBlock> blocks;
  blocks.reserve(slots.size());
  for (std::size_t i = 0; i < slots.size(); ++i) {
    blocks.push_back({slots[i].block, static_cast<std::uint32_t>(i), slots[i].claimedForImages != 0});
  }
  return blocks;
}

void BlockGrid::claimImageBlocks() {
  if (!claimImageBlocks_) claimImageBlocks_.emplace(gl::ShaderLibrary(), "sim/claim_image_blocks.comp", shaderOptions_);
}

template <class Self, class Visit>
void BlockGrid::visitBlockSums(Self& self, const std::vector<std::uint32_t>& slots, Visit visit) {
  const std::size_t blockBytes = gpu::BLOCK_NODES * sizeof(glm::ivec4);
  std::size_t at = 0;  // in node sums
  for (const std::uint32_t slot : slots) {
    for (auto* buffer : {&self.momentumMass_, &self.impulseSums_}) {
      if (!*buffer) continue;
      visit(*buffer, slot * blockBytes, blockBytes, at);
      at += gpu::BLOCK_NODES;
    }
  }
}

std::vector<glm::ivec4> BlockGrid::readBlockSums(const std::vector<std::uint32_t>& slots) const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // P2G's atomics, before they are read back
  std::vector<glm::ivec4> sums(slots.size() * sumsPerBlock());
  visitBlockSums(*this, slots, [&](const gl::Buffer& buffer, std::size_t offset, std::size_t bytes, std::size_t at) {
    buffer.download(offset, bytes, sums.data() + at);
  });
  return sums;
}

void BlockGrid::writeBlockSums(const std::vector<std::uint32_t>& slots, const std::vector<glm::ivec4>& sums) {
  visitBlockSums(*this, slots, [&](gl::Buffer& buffer, std::size_t offset, std::size_t bytes, std::size_t at) {
    buffer.upload(offset, bytes, sums.data() + at);
  });
}

void BlockGrid::markAuditedElsewhere(const std::vector<std::uint32_t>& slots) {
  const std::uint32_t elsewhere = 1;
  for (const std::uint32_t slot : slots) {
    blockTable_.upload(sizeof(gpu::BlockTableHeader) + slot * sizeof(gpu::BlockSlot) +
                           offsetof(gpu::BlockSlot, auditedElsewhere),
                       sizeof elsewhere, &elsewhere);
  }
}

std::vector<glm::ivec3> BlockGrid::activeNodes() const {
  const glm::ivec3 blocks = blocksPerAxis_;
  std::vector<glm::ivec3> nodes;
  const std::vector<ActiveBlock> active = activeBlocks();
  nodes.reserve(active.size() * gpu::BLOCK_NODES);
  for (const ActiveBlock& slot : active) {
    const int index = static_cast<int>(slot.block);
    const glm::ivec3 block(index % blocks.x, (index / blocks.x) % blocks.y, index / (blocks.x * blocks.y));
    for (int local = 0; local < gpu::BLOCK_NODES; ++local) {
      const glm::ivec3 offset(local % gpu::BLOCK_WIDTH, (local / gpu::BLOCK_WIDTH) % gpu::BLOCK_WIDTH,
                              local / (gpu::BLOCK_WIDTH * gpu::BLOCK_WIDTH));
      nodes.push_back(block * gpu::BLOCK_WIDTH + offset);
    }
  }
  return nodes;
}

std::vector<StoredNode> BlockGrid::readNodes() const {
  const std::vector<glm::ivec3> addresses = activeNodes();
  const std::vector<glm::ivec4> sums = momentumMass_.read<glm::ivec4>(addresses.size());
  return inGridOrder<StoredNode>(addresses, sums);
}

}  // namespace firn
