#pragma once
// A rank's share of the domain in a run over MPI (sim/DomainShare.h, docs/distributed.md): a slab of block layers
// (mpi/Slabs.h), its particles, and the exchanges that keep the run the same, to the bit, as one process's.
//
// The grid's sums: after P2G every rank lists its active blocks and all ranks gather the lists, so each knows which
// of its blocks another rank holds too (where its slab meets another, a rank's particles reach one layer into the
// next slab). For those blocks the ranks swap their integer sums and each adds the other's: every holder then has
// the whole sum, and each runs the grid update on all its blocks, the shared ones alike (the update is a node's own),
// so no velocities need sending back. Nothing depends on a particle being in the "right" slab: a particle anywhere
// is summed right wherever its stencil reaches, and the slabs only balance the work.
#include <cstdint>
#include <string>
#include <vector>

#include <mpi.h>

#include "gl/Buffer.h"
#include "mpi/Slabs.h"
#include "scene/Scene.h"
#include "sim/DomainShare.h"

namespace firn::mpi {

// What a share exchanged, summed over its steps (docs/distributed.md, the benchmarks).
struct ShareTraffic {
  std::uint64_t steps = 0;
  std::uint64_t haloBytes = 0;        // grid sums sent
  std::uint64_t activeBlocks = 0;     // this rank's active blocks, step by step
  std::uint64_t migratedParticles = 0;
  std::uint64_t particleSteps = 0;    // this rank's particles, step by step
  double sumsS = 0;                   // wall time completing the shared nodes' sums
  double migrationS = 0;              // wall time moving particles between ranks
};

// What all ranks exchanged over a run, per step (MpiShare::summary).
struct RunTraffic {
  double haloBytesPerStep = 0;      // grid sums sent by all ranks
  double gridBytesPerStep = 0;      // what the grid passes move: 4 × the node sums of every rank's active blocks
  double exchangeMsPerStep = 0;     // completing sums and migrating: the least of any rank (the others also wait)
  double migratedPerStep = 0;       // particles that changed rank
  double imbalance = 1;             // the busiest rank's particles over the mean (time-averaged)
  // "per step 230 KiB of grid sums exchanged (5.2% of the 4.4 MiB the grid passes move), …"
  std::string describe() const;
};

class MpiShare final : public DomainShare {
 public:
  // Throws InputError, the same on every rank and before any communication, for a scene a run over several
  // processes does not take (the keys named) or one with fewer block layers along z than ranks.
  MpiShare(MPI_Comm comm, const Scene& scene, int rebalanceEveryFrames);

  int rank() const { return rank_; }
  const Slabs& slabs() const { return slabs_; }
  // This run's traffic over all ranks; every rank calls it.
  RunTraffic summary() const;

  int shares() const override { return size_; }
  void beginStep(std::uint64_t step) override;
  void balance(const std::vector<glm::vec3>& positionsM) override;
  bool owns(const glm::vec3& positionM) const override { return slabs_.ownerOf(positionM) == rank_; }
  void sumSharedNodes(BlockGrid& grid) override;
  void sumSharedChanges(BlockGrid& grid) override;
  std::size_t migrate(GpuState& state, std::size_t count, std::vector<std::uint32_t>& ids,
                      const MakeRoom& makeRoom) override;
  std::size_t endFrame(GpuState& state, std::size_t count, std::vector<std::uint32_t>& ids,
                       const MakeRoom& makeRoom) override;
  double largest(double value) override;
  bool any(bool flag) override;
  void sumExactly(std::vector<std::int64_t>& values) override;
  bool countsCommonWork() const override { return rank_ == 0; }
  bool writesOutput() const override { return rank_ == 0; }
  std::vector<std::string> gatherRecords(const std::vector<std::string>& records, const std::vector<std::size_t>& strides,
                                         const std::vector<std::uint32_t>& ids) override;
  gpu::WatchdogStatus combineWatchdogs(const gpu::WatchdogStatus& mine) override;
  std::size_t activeBlocksInAll() override;

 private:
  // Sends each other rank `sent`, this rank's sums of the blocks they share (laid out as heldSlots_, `perBlock`
  // sums a block), and adds what each sends to `sums`.
  void addOtherShares(std::size_t perBlock, const std::vector<glm::ivec4>& sent, std::vector<glm::ivec4>& sums);

  MPI_Comm comm_;
  int rank_ = 0;
  int size_ = 1;
  Slabs slabs_;
  int rebalanceEveryFrames_;
  int framesSinceBalance_ = 0;
  std::size_t firstHeldBlocks_ = 0;  // this rank's blocks its particles reached and no lower rank's did (counted once)
  ShareTraffic traffic_;
  // The blocks this rank shares, as sumSharedNodes found them this step: their slots, their sums as last completed,
  // and per other rank the places among them of the blocks it holds too (in block order, as it lists them).
  std::vector<std::uint32_t> heldSlots_;
  std::vector<glm::ivec4> sharedSums_;
  std::vector<std::vector<std::size_t>> sharedWith_;
  gl::Buffer staging_;               // migration: the leavers' records, read back at once
  int sumsPerNode_;                  // 1, or 2 with PIC/FLIP's impulse sums (as the grid stores them)
};

}  // namespace firn::mpi
