#pragma once
// The block-sparse grid (common/blocks.glsl, docs/numerics.md "The block-sparse grid"): the one structure every
// grid pass shares. Nodes are stored by blocks of BLOCK_WIDTH³, claimed each step where the particles' stencils
// reach from a pool of slots (the block table) through a map over the domain; the particles are sorted by block and
// base node into bins, and for the tile passes the bins' rows into tiles in order of fill. It owns those buffers,
// published at the grid bindings of the GPU contract (FIRN_GRID_BINDINGS_FIRST to _END), and the passes that rebuild
// them each step.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gl/Buffer.h"
#include "gl/BufferBindings.h"
#include "gl/ComputePass.h"
#include "gl/Context.h"
#include "gl/ShaderLibrary.h"
#include "gpu/GpuLayout.h"
#include "sim/GpuStateLayout.h"

namespace firn {

// The blocks of the grid's pool that particles' stencils reached.
struct BlockUsage {
  std::size_t lastStep = 0;    // claimed in the last step
  std::size_t mostInAStep = 0; // the most claimed in any step since the pool was made (may exceed the capacity)
  std::size_t capacity = 0;
  std::size_t poolBytes = 0;   // the grid's pool: nodes, bins and the block table (the solver's vectors apart)
  std::size_t mapBytes = 0;    // the block map's: 4 bytes per block of the domain
};

// A block the last step's particles reached: its index in the domain's block map (x fastest, then y, then z) and its
// slot in the pool.
struct ActiveBlock {
  std::uint32_t block = 0;
  std::uint32_t slot = 0;
  bool claimedForImages = false;  // no particle's stencil reached it, only an image's (claimImageBlocks)
};

// One node of the grid as stored after P2G: its index per axis and its sums (fixed point or float bits).
struct StoredNode {
  glm::ivec3 node{0};
  glm::ivec4 sums{0};
};

// Values at `nodes`, paired as {node, value} and sorted in the order of the dense grid (z, then y, then x).
template <typename Result, typename Value>
std::vector<Result> inGridOrder(const std::vector<glm::ivec3>& nodes, const std::vector<Value>& values) {
  std::vector<Result> result;
  result.reserve(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) result.push_back({nodes[i], values[i]});
  std::sort(result.begin(), result.end(), [](const Result& a, const Result& b) {
    return std::tie(a.node.z, a.node.y, a.node.x) < std::tie(b.node.z, b.node.y, b.node.x);
  });
  return result;
}

class BlockGrid {
 public:
  // The pool holds layout.blockCapacity blocks; the passes are built with the step's shader options.
  BlockGrid(const GpuStateLayout& layout, const gl::ShaderLibrary& library, const gl::ShaderOptions& options,
            const gl::ContextInfo& gl);

  // A new, zero-filled pool of `capacity` blocks (the grid is rebuilt every step, so nothing is copied). The caller
  // checks the sizes against the driver (GpuState).
  void allocatePool(std::size_t capacity);
  // The sort's per-particle buffers for `particleCapacity` particles (rebuilt every step, so nothing is copied).
  void allocateParticles(std::size_t particleCapacity);
  BlockUsage usage() const;
  // The pool's slots (no read of the GPU, unlike usage()).
  std::size_t capacity() const { return capacity_; }

  // What the sort leaves for the transfers: the particles by block and base node for every shape, and for the tile
  // passes (P2G's and the Hessian product's tiles, sim/TransferShape.h) also the tiles in order of fill.
  enum class SortFor { Blocks, Tiles };
  // The blocks the particles' stencils reach claim slots of the pool (last step's are released first), and the
  // particles are sorted by block and base node; `buffers` must hold the grid's, the particles' and the step's. The
  // bins are scanned in the shape of the transfers that read them: a work group per block for blocks, an
  // invocation per block (and the tiles' buckets of fill) for tiles.
  void sortParticles(std::size_t particles, SortFor sortFor, const gl::BufferBindings& buffers,
                     gl::PassTimer& timer) const;
  // Runs `pass`, whose work groups stride over the step's blocks (common/blocks.glsl, workGroupCount), dispatched
  // directly: as many groups as the blocks of the last step the host counted (usage()), an eighth more for their
  // growth, and at most the pool's capacity (the capacity itself before any count).
  void runOverBlocks(const gl::ComputePass& pass, const gl::BufferBindings& buffers, gl::PassTimer& timer) const;
  // A pass over the blocks that every step runs, in the dispatch of each sort (why: common/blocks.glsl,
  // workGroupCount): for tiles a work group per block from the block table's dispatch at `tableDispatch`, for blocks
  // work groups striding over them (built with FIRN_STRIDE_OVER_BLOCKS, run by runOverBlocks).
  struct StepPass {
    gl::ComputePass fromTable;
    gl::ComputePass striding;
    std::size_t tableDispatch = 0;
    StepPass() = default;
    StepPass(const gl::ShaderLibrary& library, const std::string& shader, const gl::ShaderOptions& options,
             std::size_t tableDispatch);
  };
  void run(const StepPass& pass, SortFor sortFor, const gl::BufferBindings& buffers, gl::PassTimer& timer) const;

  // The block table: its header holds the tile, solve and rigid-body passes' indirect dispatches
  // (gpu::BlockTableHeader).
  const gl::Buffer& blockTable() const { return blockTable_; }
  void publish(gl::BufferBindings& bindings) const;

  // The node index per axis of each storage address of the last step's active blocks (slot after slot).
  std::vector<glm::ivec3> activeNodes() const;
  // Every node of the active blocks after P2G, as stored, in the order of the dense grid (z, then y, then x).
  std::vector<StoredNode> readNodes() const;

  // The particles whose stencil's base node lies in a block layer along `axis` outside [firstLayer, endLayer), in
  // index order (list_leavers.comp): a share's particles that left its slab. `buffers` must hold the particles'.
  std::vector<std::uint32_t> particlesOutside(std::size_t particles, int axis, int firstLayer, int endLayer,
                                              const gl::BufferBindings& buffers);
  // The particles the last step's list_mirrored.comp listed, those whose stress it mirrored into a rigid body (scenes
  // with rigid bodies; docs/algorithm.md eq. 38), in index order.
  std::vector<std::uint32_t> mirroredParticles() const;
  // The last step's active blocks, in the order of their slots.
  std::vector<ActiveBlock> activeBlocks() const;
  // The sums P2G left at the nodes of the blocks in `slots`: per block its BLOCK_NODES momentum-mass sums, then (PIC/
  // FLIP) its impulse sums, as stored (fixed point), and back.
  std::size_t sumsPerBlock() const { return (withImpulse_ ? 2 : 1) * std::size_t(gpu::BLOCK_NODES); }
  std::vector<glm::ivec4> readBlockSums(const std::vector<std::uint32_t>& slots) const;
  void writeBlockSums(const std::vector<std::uint32_t>& slots, const std::vector<glm::ivec4>& sums);
  // Marks the blocks in `slots` as audited by another share of the domain (BlockSlot::auditedElsewhere): what their
  // nodes' collisions move — energy, the objects' loads, the rigid bodies' sums — is that share's to count
  // (common/energy.glsl).
  void markAuditedElsewhere(const std::vector<std::uint32_t>& slots);
  // From the next sort on, the particles near a rigid body claim the blocks their images reach too
  // (claim_image_blocks.comp): a share of the domain with rigid bodies needs them, one process never does.
  void claimImageBlocks();

 private:
  // The particles a pass listed in particleRanks, as many as the block table's counter at `counterOffset` says, in
  // index order.
  std::vector<std::uint32_t> listedParticles(std::size_t counterOffset) const;
  // visit(buffer, byte offset, bytes, place in the sums) for each node-sum array of each slot, in readBlockSums' order.
  template <class Self, class Visit>
  static void visitBlockSums(Self& self, const std::vector<std::uint32_t>& slots, Visit visit);

  glm::ivec3 blocksPerAxis_;
  std::size_t capacity_ = 0;
  // The blocks of the last step usage() read, which runOverBlocks dispatches for (0 before the first read).
  mutable std::size_t countedBlocks_ = 0;
  bool withImpulse_;
  int maxWorkGroupsX_;

  gl::Buffer momentumMass_;     // per node of the pool
  gl::Buffer impulseSums_;      // per node of the pool, PIC/FLIP or semi-implicit only
  gl::Buffer blockTable_;       // BlockTableHeader, then a BlockSlot per slot of the pool
  gl::Buffer blockMap_;         // per block of the domain
  gl::Buffer bins_;             // per base node of the pool
  gl::Buffer tileOrder_;        // per row of the pool
  gl::Buffer sortedParticles_;  // particle indices in block, then bin, order
  gl::Buffer particleRanks_;    // each particle's place in its bin

  gl::ComputePass prepareBlocks_;
  StepPass releaseBlocks_;
  gl::ComputePass markBlocks_;
  gl::ComputePass countBlocks_;
  gl::ComputePass binCount_;
  gl::ComputePass binScan_;
  gl::ComputePass binScanBlock_;
  gl::ComputePass blockOffsets_;
  gl::ComputePass binPlace_;
  gl::ComputePass orderTiles_;
  // Compiled where a share of the domain needs them (particlesOutside, claimImageBlocks): one process never does.
  gl::ShaderOptions shaderOptions_;
  std::optional<gl::ComputePass> listLeavers_;
  std::optional<gl::ComputePass> claimImageBlocks_;
};

}  // namespace firn
