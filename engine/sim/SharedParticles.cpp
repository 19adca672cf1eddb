#include "sim/SharedParticles.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace firn {

namespace {

// Records `particles` of `bytes` (a buffer's contents: `capacity` records), packed at the start of a buffer of
// `packedCapacity` records, the rest zero: a share's particles of a whole checkpoint.
std::string recordsOf(const std::string& bytes, std::size_t capacity, const std::vector<std::uint32_t>& particles,
                      std::size_t packedCapacity) {
  const std::size_t stride = bytes.size() / capacity;
  std::string packed(packedCapacity * stride, '\0');
  for (std::size_t i = 0; i < particles.size(); ++i) {
    std::memcpy(packed.data() + i * stride, bytes.data() + std::size_t(particles[i]) * stride, stride);
  }
  return packed;
}

template <typename T>
std::string bytesOf(const std::vector<T>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

template <typename T>
std::vector<T> valuesOf(const std::string& bytes) {
  std::vector<T> values(bytes.size() / sizeof(T));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
  return values;
}

}  // namespace

SharedParticles::SharedParticles(DomainShare* share, std::size_t totalCapacity,
                                 const std::vector<ParticleSeed>& seeds)
    : share_(share), totalCapacity_(totalCapacity) {
  if (share_ == nullptr) return;
  std::vector<glm::vec3> positionsM;
  positionsM.reserve(seeds.size());
  for (const ParticleSeed& seed : seeds) positionsM.push_back(seed.positionM);
  share_->balance(positionsM);
}

std::size_t SharedParticles::startCapacity(const std::vector<ParticleSeed>& seeds) const {
  if (share_ == nullptr) return totalCapacity_;
  const auto owned = [this](const ParticleSeed& seed) { return share_->owns(seed.positionM); };
  const auto own = std::size_t(std::count_if(seeds.begin(), seeds.end(), owned));
  return shareParticleCapacity(own, totalCapacity_);
}

std::vector<ParticleSeed> SharedParticles::own(const std::vector<ParticleSeed>& particles, std::size_t firstId) {
  if (!share_) return particles;
  std::vector<ParticleSeed> own;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (!share_->owns(particles[i].positionM)) continue;
    own.push_back(particles[i]);
    ids_.push_back(static_cast<std::uint32_t>(firstId + i));
  }
  return own;
}

void SharedParticles::beginStep(std::uint64_t step) {
  viewGathered_ = false;
  if (share_) share_->beginStep(step);
}

std::size_t SharedParticles::migrate(GpuState& state, std::size_t count, const MakeRoom& makeRoom) {
  return share_ ? share_->migrate(state, count, ids_, makeRoom) : count;
}

std::size_t SharedParticles::endFrame(GpuState& state, std::size_t count, const MakeRoom& makeRoom) {
  return share_ ? share_->endFrame(state, count, ids_, makeRoom) : count;
}

void SharedParticles::restore(std::vector<std::uint32_t> ids) {
  viewGathered_ = false;
  ids_ = std::move(ids);
}

ParticleSnapshot SharedParticles::snapshot(const ParticleBuffers& mine, std::size_t count) const {
  if (!share_) return mine.read(count);
  // Gathered already for the view at this step: read on the writer, not gathered again.
  if (viewGathered_) return gathered_ ? gathered_->read(gatheredCount_) : ParticleSnapshot{};
  const ParticleSnapshot records = mine.read(count);
  const std::vector<std::string> all =
      share_->gatherRecords({bytesOf(records.positionMass), bytesOf(records.velocityVolume), bytesOf(records.plasticJ)},
                            {sizeof(glm::vec4), sizeof(glm::vec4), sizeof(float)}, ids_);
  if (all.empty()) return {};
  return {valuesOf<glm::vec4>(all[0]), valuesOf<glm::vec4>(all[1]), valuesOf<float>(all[2])};
}

void SharedParticles::gatherView(const ParticleBuffers& mine, std::size_t count) {
  if (!share_) return;
  const ParticleView view = mine.view(count, 0.0);
  std::vector<std::string> records;
  std::vector<std::size_t> strides;
  for (const gl::Buffer* array : {view.positionMass, view.velocityVolume, view.kirchhoffStress, view.plasticState}) {
    strides.push_back(array->bytes() / mine.capacity());
    std::string& bytes = records.emplace_back(count * strides.back(), '\0');
    array->download(0, bytes.size(), bytes.data());
  }
  const std::vector<std::string> all = share_->gatherRecords(records, strides, ids_);
  viewGathered_ = true;
  if (all.empty()) return;
  // Without F and C, a particle buffers' state is the view's four arrays, in the view's order.
  if (!gathered_) gathered_.emplace(totalCapacity_, false, false);
  const std::vector<gl::Buffer*> buffers = gathered_->stateBuffers();
  for (std::size_t a = 0; a < all.size(); ++a) buffers[a]->upload(0, all[a].size(), all[a].data());
  gatheredCount_ = all[0].size() / strides[0];
}

std::optional<ParticleView> SharedParticles::view(double timeS) const {
  if (!gathered_) return std::nullopt;
  return gathered_->view(gatheredCount_, timeS);
}

void SharedParticles::gatherCheckpoint(Checkpoint& checkpoint, const GpuState& state, std::size_t count) const {
  if (!share_) return;
  const ParticleBuffers& mine = state.particles();
  // (A share's buffers hold its own particles; one process's, all the scene's capacity.)
  const std::size_t arrays = mine.stateBuffers().size();
  std::vector<std::string> records;
  std::vector<std::size_t> strides;
  for (std::size_t a = 0; a < arrays; ++a) {
    strides.push_back(checkpoint.buffers[a].size() / mine.capacity());
    records.push_back(checkpoint.buffers[a].substr(0, count * strides[a]));
  }
  std::vector<std::string> all = share_->gatherRecords(records, strides, ids_);
  const gpu::WatchdogStatus combined = share_->combineWatchdogs(state.watchdog());
  if (all.empty()) return;
  checkpoint.particleCount = all[0].size() / strides[0];
  for (std::size_t a = 0; a < arrays; ++a) {
    all[a].resize(totalCapacity_ * strides[a], '\0');
    checkpoint.buffers[a] = std::move(all[a]);
  }
  std::memcpy(checkpoint.buffers[arrays].data(), &combined, sizeof combined);
}

std::size_t SharedParticles::scatterCheckpoint(const Checkpoint& checkpoint, GpuState& state,
                                               const MakeRoom& makeRoom) {
  viewGathered_ = false;
  if (!share_) {
    state.loadStateBytes(checkpoint.buffers);
    return checkpoint.particleCount;
  }
  // The checkpoint's particles (of any number of shares, or one process) drawn anew into regions, and each share's
  // packed at the start of its buffers; their places in the checkpoint are their ids.
  std::vector<glm::vec3> positionsM;
  for (const glm::vec4& positionMass : valuesOf<glm::vec4>(checkpoint.buffers[0])) {  // x and mass come first
    if (positionsM.size() == checkpoint.particleCount) break;
    positionsM.emplace_back(positionMass);
  }
  share_->balance(positionsM);
  ids_.clear();
  for (std::size_t i = 0; i < positionsM.size(); ++i) {
    if (share_->owns(positionsM[i])) ids_.push_back(static_cast<std::uint32_t>(i));
  }
  makeRoom(ids_.size());
  std::vector<std::string> mine = checkpoint.buffers;
  for (std::size_t a = 0; a < state.particles().stateBuffers().size(); ++a) {
    mine[a] = recordsOf(mine[a], totalCapacity_, ids_, state.particleCapacity());
  }
  state.loadStateBytes(mine);
  return ids_.size();
}

}  // namespace firn
