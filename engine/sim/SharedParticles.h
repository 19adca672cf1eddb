#pragma once
// A simulation's particles when several processes share its domain (sim/DomainShare.h, docs/distributed.md): the
// bookkeeping that keeps what a run writes one process's — each particle's id (its place in one process's order),
// every share's particles gathered for the output and the checkpoints, a checkpoint's particles handed back to the
// shares, the particles that cross into another share's region — and the decisions every share takes alike. Without
// a share (one process) each call is the identity, so that Simulation runs the same code either way and knows
// nothing of the decomposition.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gpu/GpuLayout.h"
#include "gpu/ParticleView.h"
#include "io/Checkpoint.h"
#include "sim/DomainShare.h"
#include "sim/GpuState.h"
#include "sim/ParticleBuffers.h"
#include "sim/SceneUpload.h"

namespace firn {

class SharedParticles {
 public:
  using MakeRoom = DomainShare::MakeRoom;

  // `share` null: one process. `totalCapacity`: one process's particle capacity. With a share, draws the shares'
  // regions for all the scene's `seeds`: first, since a share's buffers are sized for its own.
  SharedParticles(DomainShare* share, std::size_t totalCapacity, const std::vector<ParticleSeed>& seeds);
  // The particle buffers' first capacity: one process's, or room for the share's own seeds and some more.
  std::size_t startCapacity(const std::vector<ParticleSeed>& seeds) const;

  DomainShare* share() const { return share_; }
  // With a share, each of its particles' place in one process's order (the snapshot's); empty without one.
  const std::vector<std::uint32_t>& ids() const { return ids_; }

  // The share's own of `particles`, whose places in one process's order start at `firstId` (all of them without a
  // share); their ids are appended.
  std::vector<ParticleSeed> own(const std::vector<ParticleSeed>& particles, std::size_t firstId);

  // What every share decides alike: the largest of all shares' values, whether any share's flag is set, each value
  // summed over the shares (exactly: integers).
  double largest(double value) const { return share_ ? share_->largest(value) : value; }
  bool any(bool flag) const { return share_ ? share_->any(flag) : flag; }
  void sumExactly(std::vector<std::int64_t>& values) const {
    if (share_ && !values.empty()) share_->sumExactly(values);
  }

  // After P2G: the nodes' whole sums, where other shares' particles reach too (DomainShare::sumSharedNodes).
  void sumSharedNodes(BlockGrid& grid) {
    if (share_) share_->sumSharedNodes(grid);
  }
  // A step begins (the particles change: a gathered copy is stale), and after it the particles that left the share's
  // region go to the shares they entered (DomainShare::migrate); `makeRoom(n)` grows the state's buffers for n
  // particles. Returns the share's particles now.
  void beginStep(std::uint64_t step);
  std::size_t migrate(GpuState& state, std::size_t count, const MakeRoom& makeRoom);
  // At a frame's end: the regions may be redrawn for the particles' counts, and the particles migrate.
  std::size_t endFrame(GpuState& state, std::size_t count, const MakeRoom& makeRoom);
  // The state was put back to a saved frame with these ids: a gathered copy is stale.
  void restore(std::vector<std::uint32_t> ids);

  // Every share's particles in one process's order, from `mine` (its first `count`), on the share that writes the
  // output (empty on the others); without a share, `mine` read. Every share calls it.
  ParticleSnapshot snapshot(const ParticleBuffers& mine, std::size_t count) const;
  // With a share: gathers every share's particles into a copy on the GPU of the share that writes the output, which
  // view() shows and snapshot() reads until the next step. Every share calls it.
  void gatherView(const ParticleBuffers& mine, std::size_t count);
  // The gathered copy's view at `timeS`, if there is one.
  std::optional<ParticleView> view(double timeS) const;

  // With a share: the checkpoint of `state` (its buffers' bytes, the share's first `count` particles in its particle
  // buffers, then the watchdog's) made every share's, in one process's order, on the writer: the bytes of one
  // process's checkpoint (past the particles, zero, as its never-written records are). Every share calls it.
  void gatherCheckpoint(Checkpoint& checkpoint, const GpuState& state, std::size_t count) const;
  // Loads `checkpoint` (every share's, or one process's) into `state`: with a share, its own particles (the regions
  // drawn anew for the checkpoint's particles, the ids their places in it) packed at the start of its buffers, after
  // `makeRoom(n)` has made room for them. Returns the particles it holds.
  std::size_t scatterCheckpoint(const Checkpoint& checkpoint, GpuState& state, const MakeRoom& makeRoom);

 private:
  DomainShare* share_ = nullptr;
  std::size_t totalCapacity_ = 0;
  std::vector<std::uint32_t> ids_;
  std::optional<ParticleBuffers> gathered_;  // on the writer: every share's particles (gatherView)
  std::size_t gatheredCount_ = 0;
  bool viewGathered_ = false;  // since the step began: snapshot() reads the gathered copy (every share alike)
};

}  // namespace firn
