#include "mpi/MpiShare.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <string>

#include "Error.h"
#include "mpi/MpiWorld.h"
#include "sim/GpuStateLayout.h"

namespace firn::mpi {

namespace {

using Clock = std::chrono::steady_clock;

// A run over several processes is the same, to the bit, as one process's only where a step's sums are integers
// and each node's and particle's update its own; say which keys stand in the way, before any communication.
const Scene& requireDistributable(const Scene& scene, int ranks) {
  if (ranks <= 1) return scene;
  const std::string file = sceneFileName(scene);
  const std::string where = " (mpirun -np " + std::to_string(ranks) + ")";
  if (scene.solver.atomics == Atomics::Float) {
    throw InputError(file + ": solver.atomics: \"float\" sums depend on the order of the additions, so a run over "
                     "several processes could not match one process; use \"fixed\"" + where);
  }
  if (scene.solver.semiImplicit()) {
    throw InputError(file + ": solver.integrator: the semi-implicit solve runs in one process only; use "
                     "\"explicit\" or run without mpirun" + where);
  }
  return scene;
}

// a + b as the GPU's 32-bit atomics add them: modulo 2³².
glm::ivec4 wrappingSum(const glm::ivec4& a, const glm::ivec4& b) {
  return glm::ivec4(glm::uvec4(a) + glm::uvec4(b));
}

int commRank(MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank;
}

int commSize(MPI_Comm comm) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  return size;
}

// The top bit of a block's index as the ranks list their blocks: only images claimed it (BlockSlot::claimedForImages).
constexpr std::uint32_t kImagesOnly = 0x80000000u;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// A record of `bytes` bytes as one MPI element, so that counts and offsets count records: an int of bytes overflows
// at 2 GiB (a gather of about 45M particles' positions, a migration of about 10M particles at once), an int of
// records only at 2³¹ of them, beyond the particles' 32-bit ids.
class RecordType {
 public:
  explicit RecordType(std::size_t bytes) {
    MPI_Type_contiguous(int(bytes), MPI_BYTE, &type_);
    MPI_Type_commit(&type_);
  }
  ~RecordType() { MPI_Type_free(&type_); }
  RecordType(const RecordType&) = delete;
  RecordType& operator=(const RecordType&) = delete;
  MPI_Datatype get() const { return type_; }

 private:
  MPI_Datatype type_ = MPI_DATATYPE_NULL;
};

}  // namespace

MpiShare::MpiShare(MPI_Comm comm, const Scene& scene, int rebalanceEveryFrames)
    : comm_(comm),
      rank_(commRank(comm)),
      size_(commSize(comm)),
      slabs_(requireDistributable(scene, size_), size_),
      rebalanceEveryFrames_(rebalanceEveryFrames),
      sumsPerNode_(GpuStateLayout::forScene(scene, 0, 0, false).impulse ? 2 : 1) {}

void MpiShare::beginStep(std::uint64_t step) { MpiWorld::noteStep(step); }

void MpiShare::balance(const std::vector<glm::vec3>& positionsM) {
  LayerCounts counts = slabs_.emptyCounts();
  for (const glm::vec3& positionM : positionsM) slabs_.count(positionM, counts);
  slabs_.balance(counts);
}

void MpiShare::sumSharedNodes(BlockGrid& grid) {
  const auto start = Clock::now();
  // This rank's blocks by their index in the domain, and every rank's.
  std::vector<ActiveBlock> mine = grid.activeBlocks();
  std::sort(mine.begin(), mine.end(), [](const ActiveBlock& a, const ActiveBlock& b) { return a.block < b.block; });
  // A block only images claimed travels with its top bit set (block indices stay below 256³: grid.cells ≤ 1024).
  std::vector<std::uint32_t> myBlocks(mine.size());
  for (std::size_t i = 0; i < mine.size(); ++i) {
    myBlocks[i] = mine[i].block | (mine[i].claimedForImages ? kImagesOnly : 0u);
  }
  const int myCount = int(myBlocks.size());
  std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
  MPI_Allgather(&myCount, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_);
  std::exclusive_scan(counts.begin(), counts.end(), offsets.begin(), 0);
  std::vector<std::uint32_t> everyBlock(std::size_t(offsets.back() + counts.back()));
  MPI_Allgatherv(myBlocks.data(), myCount, MPI_UINT32_T, everyBlock.data(), counts.data(), offsets.data(),
                 MPI_UINT32_T, comm_);

  // The blocks this rank holds with each other rank, as places in `mine` (in block order, as the other rank lists
  // them too), and whether a lower rank holds each (then that rank counts it). The blocks the particles reached are
  // counted as one process counts them: each where a particle's stencil claimed it, on the lowest such rank.
  std::vector<std::vector<std::size_t>> shared(static_cast<std::size_t>(size_));
  std::vector<bool> heldBelow(mine.size(), false), heldElsewhere(mine.size(), false);
  std::vector<bool> reachedBelow(mine.size(), false);
  const auto blockOf = [](std::uint32_t listed) { return listed & ~kImagesOnly; };
  for (int q = 0; q < size_; ++q) {
    if (q == rank_) continue;
    const std::uint32_t* other = everyBlock.data() + offsets[std::size_t(q)];
    const std::uint32_t* otherEnd = other + counts[std::size_t(q)];
    for (std::size_t i = 0; i < myBlocks.size() && other != otherEnd; ++i) {
      other = std::lower_bound(other, otherEnd, mine[i].block,
                               [&](std::uint32_t listed, std::uint32_t block) { return blockOf(listed) < block; });
      if (other == otherEnd || blockOf(*other) != mine[i].block) continue;
      shared[std::size_t(q)].push_back(i);
      heldElsewhere[i] = true;
      if (q < rank_) heldBelow[i] = true;
      if (q < rank_ && (*other & kImagesOnly) == 0) reachedBelow[i] = true;
    }
  }
  firstHeldBlocks_ = 0;
  for (std::size_t i = 0; i < mine.size(); ++i) firstHeldBlocks_ += !mine[i].claimedForImages && !reachedBelow[i];

  // The sums of every block held elsewhere, read once; each other rank's shared blocks as places among them.
  heldSlots_.clear();
  std::vector<std::size_t> sumsAt(mine.size(), 0);  // a held block's place in the sums read, in blocks
  for (std::size_t i = 0; i < mine.size(); ++i) {
    if (!heldElsewhere[i]) continue;
    sumsAt[i] = heldSlots_.size();
    heldSlots_.push_back(mine[i].slot);
  }
  for (std::vector<std::size_t>& places : shared) {
    for (std::size_t& place : places) place = sumsAt[place];
  }
  sharedWith_ = std::move(shared);
  sharedSums_ = grid.readBlockSums(heldSlots_);
  addOtherShares(grid.sumsPerBlock(), sharedSums_, sharedSums_);
  grid.writeBlockSums(heldSlots_, sharedSums_);
  // What the collisions at a shared block's nodes move — energy, loads, the bodies' sums — is counted by the lowest
  // rank holding it.
  std::vector<std::uint32_t> auditedBelow;
  for (std::size_t i = 0; i < mine.size(); ++i) {
    if (heldBelow[i]) auditedBelow.push_back(mine[i].slot);
  }
  grid.markAuditedElsewhere(auditedBelow);

  ++traffic_.steps;
  traffic_.activeBlocks += mine.size();
  traffic_.sumsS += secondsSince(start);
}

void MpiShare::sumSharedChanges(BlockGrid& grid) {
  const auto start = Clock::now();
  // What this rank added to the shared blocks since their sums were completed, sent as they were.
  std::vector<glm::ivec4> sums = grid.readBlockSums(heldSlots_);
  std::vector<glm::ivec4> changes(sums.size());
  for (std::size_t k = 0; k < sums.size(); ++k) {
    changes[k] = glm::ivec4(glm::uvec4(sums[k]) - glm::uvec4(sharedSums_[k]));  // modulo 2³², as the GPU adds
  }
  addOtherShares(grid.sumsPerBlock(), changes, sums);
  grid.writeBlockSums(heldSlots_, sums);
  sharedSums_ = std::move(sums);
  traffic_.sumsS += secondsSince(start);
}

void MpiShare::addOtherShares(std::size_t perBlock, const std::vector<glm::ivec4>& sent,
                              std::vector<glm::ivec4>& sums) {
  // Each rank sends each other rank its sums of the blocks they share, in block order, and adds what it gets. A
  // block travels as a mask of its nodes whose sums are not all zero, then those nodes' sums (per array): where the
  // sender summed nothing there is nothing to add, and the rank below a slab reaches only the first node layers of
  // the slab's first block layer.
  const std::size_t arrays = perBlock / gpu::BLOCK_NODES;
  std::vector<int> sendCounts(static_cast<std::size_t>(size_)), sendOffsets(static_cast<std::size_t>(size_));
  std::vector<glm::ivec4> packed;
  for (int q = 0; q < size_; ++q) {
    sendOffsets[std::size_t(q)] = int(packed.size());
    for (const std::size_t at : sharedWith_[std::size_t(q)]) {
      const glm::ivec4* block = sent.data() + at * perBlock;
      std::uint64_t mask = 0;
      for (std::size_t node = 0; node < gpu::BLOCK_NODES; ++node) {
        for (std::size_t a = 0; a < arrays; ++a) {
          if (block[a * gpu::BLOCK_NODES + node] != glm::ivec4(0)) mask |= std::uint64_t(1) << node;
        }
      }
      packed.emplace_back(int(std::uint32_t(mask)), int(std::uint32_t(mask >> 32)), 0, 0);
      for (std::size_t node = 0; node < gpu::BLOCK_NODES; ++node) {
        if ((mask >> node & 1u) == 0) continue;
        for (std::size_t a = 0; a < arrays; ++a) packed.push_back(block[a * gpu::BLOCK_NODES + node]);
      }
    }
    sendCounts[std::size_t(q)] = int(packed.size()) - sendOffsets[std::size_t(q)];
  }
  std::vector<int> receiveCounts(static_cast<std::size_t>(size_)), receiveOffsets(static_cast<std::size_t>(size_));
  MPI_Alltoall(sendCounts.data(), 1, MPI_INT, receiveCounts.data(), 1, MPI_INT, comm_);
  std::exclusive_scan(receiveCounts.begin(), receiveCounts.end(), receiveOffsets.begin(), 0);
  std::vector<glm::ivec4> received(std::size_t(receiveOffsets.back()) + std::size_t(receiveCounts.back()));
  const RecordType sumType(sizeof(glm::ivec4));
  MPI_Alltoallv(packed.data(), sendCounts.data(), sendOffsets.data(), sumType.get(), received.data(),
                receiveCounts.data(), receiveOffsets.data(), sumType.get(), comm_);
  // Integer sums: the order of the ranks' additions cannot matter, so every holder ends with the same bits.
  for (int q = 0; q < size_; ++q) {
    const glm::ivec4* in = received.data() + receiveOffsets[std::size_t(q)];
    for (const std::size_t at : sharedWith_[std::size_t(q)]) {
      glm::ivec4* block = sums.data() + at * perBlock;
      const std::uint64_t mask = std::uint64_t(std::uint32_t(in->x)) | std::uint64_t(std::uint32_t(in->y)) << 32;
      ++in;
      for (std::size_t node = 0; node < gpu::BLOCK_NODES; ++node) {
        if ((mask >> node & 1u) == 0) continue;
        for (std::size_t a = 0; a < arrays; ++a, ++in) {
          glm::ivec4& sum = block[a * gpu::BLOCK_NODES + node];
          sum = wrappingSum(sum, *in);
        }
      }
    }
  }
  traffic_.haloBytes += packed.size() * sizeof(glm::ivec4);
}

std::size_t MpiShare::migrate(GpuState& state, std::size_t count, std::vector<std::uint32_t>& ids,
                              const MakeRoom& makeRoom) {
  const auto start = Clock::now();
  // The particles the GPU finds outside this rank's slab: only theirs are read back.
  const std::vector<std::uint32_t> outside = state.grid().particlesOutside(
      count, slabs_.axis(), slabs_.firstLayer(rank_), slabs_.firstLayer(rank_ + 1), state.bindings());
  // A particle travels as its id and its record in every state buffer, in the buffers' order (x and m first).
  std::vector<std::size_t> strides;
  std::size_t recordBytes = sizeof(std::uint32_t);
  for (const gl::Buffer* buffer : state.particles().stateBuffers()) {
    strides.push_back(buffer->bytes() / state.particles().capacity());
    recordBytes += strides.back();
  }
  // Their records (less the id), gathered on the GPU into a staging buffer record after record and read back at once:
  // a readback per particle, or per state buffer, waited for the GPU once each.
  const std::size_t stateBytes = recordBytes - sizeof(std::uint32_t);
  std::vector<unsigned char> listed(outside.size() * stateBytes);
  if (!outside.empty()) {
    const std::vector<gl::Buffer*> buffers = state.particles().stateBuffers();
    if (staging_.bytes() < listed.size()) staging_ = gl::Buffer(2 * listed.size()).labelled("migration staging");
    for (std::size_t k = 0; k < outside.size(); ++k) {
      std::size_t field = k * stateBytes;
      for (std::size_t b = 0; b < buffers.size(); ++b) {
        staging_.copyFrom(*buffers[b], strides[b], outside[k] * strides[b], field);
        field += strides[b];
      }
    }
    staging_.download(0, listed.size(), listed.data());
  }
  std::vector<unsigned char> records(outside.size() * recordBytes);  // the leaving particles', packed
  std::vector<std::uint32_t> leaving;  // in index order
  std::vector<int> destinations, sendCounts(static_cast<std::size_t>(size_), 0);
  {
    for (std::size_t k = 0; k < outside.size(); ++k) {
      unsigned char* record = records.data() + leaving.size() * recordBytes;
      std::memcpy(record, &ids[outside[k]], sizeof(std::uint32_t));
      std::memcpy(record + sizeof(std::uint32_t), listed.data() + k * stateBytes, stateBytes);
      glm::vec3 positionM;
      std::memcpy(&positionM, record + sizeof(std::uint32_t), sizeof positionM);
      // Where the host's reading of the layer disagrees with the GPU's at a cell's edge, the particle stays.
      const int destination = slabs_.ownerOf(positionM);
      if (destination == rank_) continue;
      leaving.push_back(outside[k]);
      destinations.push_back(destination);
      ++sendCounts[std::size_t(destination)];
    }
  }
  std::vector<int> receiveCounts(static_cast<std::size_t>(size_));
  MPI_Alltoall(sendCounts.data(), 1, MPI_INT, receiveCounts.data(), 1, MPI_INT, comm_);
  const std::size_t arriving = std::accumulate(receiveCounts.begin(), receiveCounts.end(), std::size_t(0));
  std::vector<int> sendOffsets(static_cast<std::size_t>(size_)), receiveOffsets(static_cast<std::size_t>(size_));
  std::exclusive_scan(sendCounts.begin(), sendCounts.end(), sendOffsets.begin(), 0);
  std::exclusive_scan(receiveCounts.begin(), receiveCounts.end(), receiveOffsets.begin(), 0);
  // The records by destination, each destination's in index order.
  std::vector<unsigned char> outgoing(leaving.size() * recordBytes), incoming(arriving * recordBytes);
  std::vector<std::size_t> cursor(sendOffsets.begin(), sendOffsets.end());  // in records
  for (std::size_t k = 0; k < leaving.size(); ++k) {  // records[k] is leaving[k]'s
    std::size_t& at = cursor[std::size_t(destinations[k])];
    std::memcpy(outgoing.data() + at * recordBytes, records.data() + k * recordBytes, recordBytes);
    ++at;
  }
  const RecordType record(recordBytes);
  MPI_Alltoallv(outgoing.data(), sendCounts.data(), sendOffsets.data(), record.get(), incoming.data(),
                receiveCounts.data(), receiveOffsets.data(), record.get(), comm_);
  const std::size_t kept = count - leaving.size();
  traffic_.particleSteps += kept + arriving;
  if (leaving.empty() && arriving == 0) {
    traffic_.migrationS += secondsSince(start);
    return count;
  }

  makeRoom(kept + arriving);  // growing replaces the buffers: take them after
  const std::vector<gl::Buffer*> buffers = state.particles().stateBuffers();
  // The particles that stay close up: each hole a leaver left below `kept` takes a staying particle from above it.
  std::size_t filler = count;
  std::size_t nextLeaving = leaving.size();  // leavers above the filler, from the top
  for (const std::uint32_t hole : leaving) {
    if (hole >= kept) break;
    // The next staying particle from the top: leavers up there are skipped.
    for (--filler; nextLeaving > 0 && leaving[nextLeaving - 1] == filler; --filler) --nextLeaving;
    for (std::size_t b = 0; b < buffers.size(); ++b) {
      buffers[b]->copyFrom(*buffers[b], strides[b], filler * strides[b], hole * strides[b]);
    }
    ids[hole] = ids[filler];
  }
  ids.resize(kept);
  // Arrivals join after them, in the order of the ranks they came from.
  for (std::size_t b = 0, fieldOffset = sizeof(std::uint32_t); b < buffers.size(); fieldOffset += strides[b], ++b) {
    std::vector<unsigned char> bytes(arriving * strides[b]);
    for (std::size_t a = 0; a < arriving; ++a) {
      std::memcpy(bytes.data() + a * strides[b], incoming.data() + a * recordBytes + fieldOffset, strides[b]);
    }
    if (!bytes.empty()) buffers[b]->upload(kept * strides[b], bytes.size(), bytes.data());
  }
  for (std::size_t a = 0; a < arriving; ++a) {
    std::uint32_t id;
    std::memcpy(&id, incoming.data() + a * recordBytes, sizeof id);
    ids.push_back(id);
  }
  traffic_.migratedParticles += leaving.size();
  traffic_.migrationS += secondsSince(start);
  return kept + arriving;
}

std::size_t MpiShare::endFrame(GpuState& state, std::size_t count, std::vector<std::uint32_t>& ids,
                               const MakeRoom& makeRoom) {
  if (rebalanceEveryFrames_ <= 0 || ++framesSinceBalance_ < rebalanceEveryFrames_) return count;
  framesSinceBalance_ = 0;
  LayerCounts counts = slabs_.emptyCounts();
  for (const glm::vec4& position : state.particles().positionsMasses(count)) slabs_.count(glm::vec3(position), counts);
  for (std::vector<std::uint64_t>& perLayer : counts) {
    MPI_Allreduce(MPI_IN_PLACE, perLayer.data(), int(perLayer.size()), MPI_UINT64_T, MPI_SUM, comm_);
  }
  slabs_.balance(counts);
  return migrate(state, count, ids, makeRoom);
}

double MpiShare::largest(double value) {
  double result = value;
  MPI_Allreduce(&value, &result, 1, MPI_DOUBLE, MPI_MAX, comm_);
  return result;
}

bool MpiShare::any(bool flag) {
  int mine = flag ? 1 : 0, result = 0;
  MPI_Allreduce(&mine, &result, 1, MPI_INT, MPI_LOR, comm_);
  return result != 0;
}

void MpiShare::sumExactly(std::vector<std::int64_t>& values) {
  MPI_Allreduce(MPI_IN_PLACE, values.data(), int(values.size()), MPI_INT64_T, MPI_SUM, comm_);
}

std::vector<std::string> MpiShare::gatherRecords(const std::vector<std::string>& records,
                                                const std::vector<std::size_t>& strides,
                                                const std::vector<std::uint32_t>& ids) {
  const int count = int(ids.size());
  std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm_);
  std::exclusive_scan(counts.begin(), counts.end(), offsets.begin(), 0);
  const std::size_t total = rank_ == 0 ? std::size_t(offsets.back()) + std::size_t(counts.back()) : 0;
  std::vector<std::uint32_t> allIds(total);
  MPI_Gatherv(ids.data(), count, MPI_UINT32_T, allIds.data(), counts.data(), offsets.data(), MPI_UINT32_T, 0, comm_);
  // Every particle present has exactly one id below the total: the order of a single process.
  for (const std::uint32_t id : allIds) {
    if (id >= total) throw std::logic_error("gatherRecords: particle id " + std::to_string(id) + " of " + std::to_string(total));
  }
  std::vector<std::string> ordered;
  for (std::size_t a = 0; a < records.size(); ++a) {
    const std::size_t stride = strides[a];
    const RecordType record(stride);
    std::string arrived(total * stride, '\0');
    MPI_Gatherv(records[a].data(), count, record.get(), arrived.data(), counts.data(), offsets.data(), record.get(), 0,
                comm_);
    std::string& array = ordered.emplace_back(total * stride, '\0');
    for (std::size_t i = 0; i < total; ++i) {
      std::memcpy(array.data() + allIds[i] * stride, arrived.data() + i * stride, stride);
    }
  }
  return rank_ == 0 ? ordered : std::vector<std::string>();
}

gpu::WatchdogStatus MpiShare::combineWatchdogs(const gpu::WatchdogStatus& mine) {
  std::vector<gpu::WatchdogStatus> all(static_cast<std::size_t>(size_));
  MPI_Allgather(&mine, sizeof mine, MPI_BYTE, all.data(), sizeof mine, MPI_BYTE, comm_);
  gpu::WatchdogStatus combined = all[0];
  for (std::size_t q = 1; q < all.size(); ++q) {
    const gpu::WatchdogStatus& other = all[q];
    if (combined.overflowCount == 0 && other.overflowCount > 0) {
      combined.overflowNode = other.overflowNode;
      combined.overflowStep = other.overflowStep;
      combined.overflowChannel = other.overflowChannel;
    }
    if (combined.nonFiniteCount == 0 && other.nonFiniteCount > 0) {
      combined.nonFiniteParticle = other.nonFiniteParticle;
      combined.nonFiniteStep = other.nonFiniteStep;
    }
    if (combined.cflCount == 0 && other.cflCount > 0) {
      combined.cflParticle = other.cflParticle;
      combined.cflStep = other.cflStep;
      combined.cflCellsPerStep = other.cflCellsPerStep;
    }
    combined.overflowCount += other.overflowCount;
    combined.nonFiniteCount += other.nonFiniteCount;
    combined.cflCount += other.cflCount;
    // Non-negative floats order as their bits do.
    combined.maxSpeedBits = std::max(combined.maxSpeedBits, other.maxSpeedBits);
  }
  return combined;
}

RunTraffic MpiShare::summary() const {
  // Sums over the ranks, and the largest of each rank's value.
  const double mine[] = {double(traffic_.haloBytes), double(traffic_.activeBlocks), double(traffic_.migratedParticles),
                         double(traffic_.particleSteps)};
  double sums[4] = {}, busiest = 0, leastExchangeS = 0;
  const double exchangeS = traffic_.sumsS + traffic_.migrationS, particleSteps = double(traffic_.particleSteps);
  MPI_Allreduce(mine, sums, 4, MPI_DOUBLE, MPI_SUM, comm_);
  MPI_Allreduce(&particleSteps, &busiest, 1, MPI_DOUBLE, MPI_MAX, comm_);
  // A rank's time in the exchanges includes its wait for slower ranks; the rank that waited least shows their cost.
  MPI_Allreduce(&exchangeS, &leastExchangeS, 1, MPI_DOUBLE, MPI_MIN, comm_);
  RunTraffic run;
  const double steps = double(std::max<std::uint64_t>(traffic_.steps, 1));
  // A node's sums are BLOCK_NODES ivec4s per block (two with PIC/FLIP's impulses); P2G writes them, the grid update
  // reads them and writes the velocities over them, G2P reads those: four passes over them a step.
  const double blockBytes = double(gpu::BLOCK_NODES * sizeof(glm::ivec4)) * sumsPerNode_;
  run.haloBytesPerStep = sums[0] / steps;
  run.gridBytesPerStep = 4.0 * sums[1] * blockBytes / steps;
  run.exchangeMsPerStep = 1e3 * leastExchangeS / steps;
  run.migratedPerStep = sums[2] / steps;
  run.imbalance = sums[3] > 0 ? busiest / (sums[3] / size_) : 1.0;
  return run;
}

std::string RunTraffic::describe() const {
  char text[256];
  std::snprintf(text, sizeof text,
                "per step %.1f KiB of grid sums exchanged (%.1f%% of the %.2f MiB the grid passes move), %.2f ms "
                "exchanging and migrating (the rank that waited least), %.0f particles migrated; load imbalance %.3f (the "
                "busiest rank's particles over the mean)",
                haloBytesPerStep / 1024.0, gridBytesPerStep > 0 ? 100.0 * haloBytesPerStep / gridBytesPerStep : 0.0,
                gridBytesPerStep / (1024.0 * 1024.0), exchangeMsPerStep, migratedPerStep, imbalance);
  return text;
}

std::size_t MpiShare::activeBlocksInAll() {
  std::uint64_t mine = firstHeldBlocks_, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_UINT64_T, MPI_SUM, comm_);
  return std::size_t(all);
}

}  // namespace firn::mpi
