#pragma once
// A simulation's share of a domain that several processes simulate together (docs/distributed.md): which particles
// are its own, the grid sums it adds with the other shares', the particles it hands over, and the decisions every
// share must take alike. A process that simulates the whole domain has none; the MPI ranks of `firn run` under
// mpirun each have one (engine/mpi/MpiShare.h).
//
// What keeps a run on several shares the same, to the bit, as a run on one: P2G's sums are integers, so a node's
// sum does not depend on which process added which particle's part or in what order, and every other part of a step
// is a particle's or a node's own. So a share only has to complete the sums of the nodes it holds before the grid
// update reads them, and keep each particle's record intact as it moves from share to share. The rigid bodies' sums
// are integers too: each share adds its particles' and its nodes' parts (a node that several shares hold counted by
// one), the shares sum them, and every share moves every body alike (StepPipeline::step).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "gpu/GpuLayout.h"
#include "sim/BlockGrid.h"
#include "sim/GpuState.h"
#include "sim/ParticleBuffers.h"
#include "sim/SceneUpload.h"

namespace firn {

// A share's particle buffers hold its particles and a quarter more (and kShareSpareParticles), growing as particles
// come, never beyond one process's `capacity`; the budget counts a GPU for that room (run/Budget.cpp).
constexpr std::size_t kShareSpareFraction = 4;  // a quarter
constexpr std::size_t kShareSpareParticles = 1024;
inline std::size_t shareParticleCapacity(std::size_t particles, std::size_t capacity) {
  return std::min(capacity, particles + particles / kShareSpareFraction + kShareSpareParticles);
}

class DomainShare {
 public:
  virtual ~DomainShare() = default;

  // How many shares the domain is split into.
  virtual int shares() const = 0;

  // A step begins: `step`, counted from the run's start (what a share names when the run is ended from outside).
  virtual void beginStep(std::uint64_t step) = 0;
  // Draws the shares' regions for particles at `positionsM`: all the particles (the scene's seeds at the start, a
  // checkpoint's when resuming), the same in every share.
  virtual void balance(const std::vector<glm::vec3>& positionsM) = 0;
  // Whether a particle at `positionM` starts in this share: the seeds, and the emitters' particles as they join.
  virtual bool owns(const glm::vec3& positionM) const = 0;
  // After P2G: adds to the sums of this share's active nodes what the other shares summed at the same nodes, so
  // that every share holding a node holds its whole sum, and marks the blocks a share of a lower rank holds too
  // (BlockSlot::auditedElsewhere), whose nodes' energy flows, loads and pushes on rigid bodies that share counts. Every
  // share calls it at the same point of the same step.
  virtual void sumSharedNodes(BlockGrid& grid) = 0;
  // After passes that add to the sums of the nodes once sumSharedNodes has completed them (the images of a fluid's
  // stress in the rigid bodies, mirror_stress.comp): adds what the other shares added at the shared nodes since, so
  // that every holder holds the whole sums again. Every share calls it at the same point of the same step.
  virtual void sumSharedChanges(BlockGrid& grid) = 0;
  // After a step: hands the particles that left this share's region to the shares they entered and appends those
  // that entered it, after `makeRoom(n)` has made room for n particles in the state's buffers; `ids` (each
  // particle's place in the order of a single process) moves with them. Returns the new count.
  using MakeRoom = std::function<void(std::size_t particles)>;
  virtual std::size_t migrate(GpuState& state, std::size_t count, std::vector<std::uint32_t>& ids,
                              const MakeRoom& makeRoom) = 0;
  // At the end of each frame: the regions may be redrawn for the particles' counts (and the particles migrated).
  virtual std::size_t endFrame(GpuState& state, std::size_t count, std::vector<std::uint32_t>& ids,
                               const MakeRoom& makeRoom) = 0;

  // Decisions every share takes alike: the largest of all shares' values, whether any share's flag is set.
  virtual double largest(double value) = 0;
  virtual bool any(bool flag) = 0;
  // Each value summed over all shares, in integers: exact, so every share ends with the sums one process would have
  // made (the energy audit's ledger, sim/EnergyAudit.h).
  virtual void sumExactly(std::vector<std::int64_t>& values) = 0;

  // What every share does alike — the rigid bodies' motion, from sums every share holds whole — is counted once, in
  // the energy audit, by the first share: whether this is it.
  virtual bool countsCommonWork() const = 0;
  // The output, which one share writes: whether this is it. Every share calls the rest together.
  virtual bool writesOutput() const = 0;
  // Every share's particle records in the order of a single process: `records` holds, per array, this share's
  // particles' records of `strides` bytes each, in the order of `ids`; the writer gets each array for all particles
  // (the others, nothing).
  virtual std::vector<std::string> gatherRecords(const std::vector<std::string>& records,
                                                 const std::vector<std::size_t>& strides,
                                                 const std::vector<std::uint32_t>& ids) = 0;
  // What the watchdogs of all shares saw, as one process's would have: counts summed, the first event of each kind
  // from the lowest share that saw one, the largest speed.
  virtual gpu::WatchdogStatus combineWatchdogs(const gpu::WatchdogStatus& mine) = 0;
  // The blocks the last step's particles reached in all shares, each counted once.
  virtual std::size_t activeBlocksInAll() = 0;
};

}  // namespace firn
