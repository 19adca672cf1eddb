#include "sim/ParticleBuffers.h"

#include <cmath>
#include <cstddef>
#include <cstring>

#include "Error.h"
#include "gpu/GpuLayout.h"

namespace firn {

namespace {

gpu::Mat3x4 identityMat3() { return {{glm::vec4(1, 0, 0, 0), glm::vec4(0, 1, 0, 0), glm::vec4(0, 0, 1, 0)}}; }

// The buffers' labels, for debuggers (glObjectLabel) and for messages about a checkpoint's buffers.
constexpr const char* kPositionMassLabel = "particles: position, mass";
constexpr const char* kVelocityVolumeLabel = "particles: velocity, volume";
constexpr const char* kPlasticStateLabel = "particles: plastic state";
constexpr const char* kElasticDeformationLabel = "particles: F";
constexpr const char* kKirchhoffStressLabel = "particles: Kirchhoff stress";
constexpr const char* kAffineLabel = "particles: APIC C";

}  // namespace

ParticleBuffers::ParticleBuffers(std::size_t capacity, bool deformationGradient, bool affine) : capacity_(capacity) {
  const std::size_t n = capacity;
  positionMass_ = gl::Buffer(n * sizeof(glm::vec4)).labelled(kPositionMassLabel);
  velocityVolume_ = gl::Buffer(n * sizeof(glm::vec4)).labelled(kVelocityVolumeLabel);
  plasticState_ = gl::Buffer(n * sizeof(gpu::ParticlePlasticState)).labelled(kPlasticStateLabel);
  if (deformationGradient) elasticDeformation_ = gl::Buffer(n * sizeof(gpu::Mat3x4)).labelled(kElasticDeformationLabel);
  kirchhoffStress_ = gl::Buffer(n * sizeof(gpu::Mat3x4)).labelled(kKirchhoffStressLabel);
  if (affine) affine_ = gl::Buffer(n * sizeof(gpu::Mat3x4)).labelled(kAffineLabel);
}

void ParticleBuffers::write(std::size_t first, const ParticleRecords& records) {
  const std::size_t n = records.size();
  positionMass_.upload(first * sizeof(glm::vec4), n * sizeof(glm::vec4), records.positionMass.data());
  velocityVolume_.upload(first * sizeof(glm::vec4), n * sizeof(glm::vec4), records.velocityVolume.data());
  plasticState_.upload(first * sizeof(gpu::ParticlePlasticState), n * sizeof(gpu::ParticlePlasticState),
                       records.plastic.data());
  // Particles start undeformed: F = I, so their stress is zero.
  const std::vector<gpu::Mat3x4> identity(n, identityMat3());
  if (elasticDeformation_) {
    elasticDeformation_.upload(first * sizeof(gpu::Mat3x4), n * sizeof(gpu::Mat3x4), identity.data());
  }
  const std::vector<gpu::Mat3x4> zero(n, gpu::Mat3x4{});
  kirchhoffStress_.upload(first * sizeof(gpu::Mat3x4), n * sizeof(gpu::Mat3x4), zero.data());
  if (affine_) affine_.upload(first * sizeof(gpu::Mat3x4), n * sizeof(gpu::Mat3x4), zero.data());
}

void ParticleBuffers::writeVelocity(std::size_t particle, const glm::vec3& velocityMPerS) {
  velocityVolume_.upload(particle * sizeof(glm::vec4), sizeof(glm::vec3), &velocityMPerS);
}

ParticleSnapshot ParticleBuffers::read(std::size_t count) const {
  ParticleSnapshot snapshot;
  snapshot.positionMass = positionMass_.read<glm::vec4>(count);
  snapshot.velocityVolume = velocityVolume_.read<glm::vec4>(count);
  const auto plastic = plasticState_.read<gpu::ParticlePlasticState>(count);
  snapshot.plasticJ.reserve(plastic.size());
  for (const auto& state : plastic) snapshot.plasticJ.push_back(state.plasticJ);
  return snapshot;
}

glm::vec3 ParticleBuffers::position(std::size_t particle) const {
  return glm::vec3(positionMass_.read<glm::vec4>(1, particle)[0]);
}

void ParticleBuffers::publish(gl::BufferBindings& bindings) const {
  bindings.storage(FIRN_BINDING_POSITION_MASS, positionMass_);
  bindings.storage(FIRN_BINDING_VELOCITY_VOLUME, velocityVolume_);
  if (elasticDeformation_) bindings.storage(FIRN_BINDING_ELASTIC_DEFORMATION, elasticDeformation_);
  bindings.storage(FIRN_BINDING_KIRCHHOFF_STRESS, kirchhoffStress_);
  if (affine_) bindings.storage(FIRN_BINDING_AFFINE, affine_);
  bindings.storage(FIRN_BINDING_PLASTIC_STATE, plasticState_);
}

ParticleView ParticleBuffers::view(std::size_t count, double timeS) const {
  return ParticleView{&positionMass_, &velocityVolume_, &kirchhoffStress_, &plasticState_, count, timeS};
}

std::vector<glm::vec4> ParticleBuffers::positionsMasses(std::size_t count) const {
  return positionMass_.read<glm::vec4>(count);
}

template <class Self>
auto ParticleBuffers::stateBuffersOf(Self& self) {
  std::vector<decltype(&self.positionMass_)> buffers;
  for (auto* buffer : {&self.positionMass_, &self.velocityVolume_, &self.elasticDeformation_, &self.kirchhoffStress_,
                       &self.affine_, &self.plasticState_}) {
    if (*buffer) buffers.push_back(buffer);
  }
  return buffers;
}

std::vector<const gl::Buffer*> ParticleBuffers::stateBuffers() const { return stateBuffersOf(*this); }

const char* ParticleBuffers::labelOf(const gl::Buffer& buffer) const {
  if (&buffer == &positionMass_) return kPositionMassLabel;
  if (&buffer == &velocityVolume_) return kVelocityVolumeLabel;
  if (&buffer == &elasticDeformation_) return kElasticDeformationLabel;
  if (&buffer == &kirchhoffStress_) return kKirchhoffStressLabel;
  if (&buffer == &affine_) return kAffineLabel;
  return kPlasticStateLabel;
}

void ParticleBuffers::checkFinite(const std::vector<std::string>& bytes, std::size_t count,
                                  const std::string& source) const {
  const std::vector<const gl::Buffer*> buffers = stateBuffers();
  for (std::size_t b = 0; b < buffers.size(); ++b) {
    // Every 4-byte word of a particle's record is a float (mat3's padding included, written as 0), but for the
    // plastic state's material index.
    const std::size_t words = buffers[b]->bytes() / capacity_ / sizeof(float);
    const std::size_t indexWord =
        buffers[b] == &plasticState_ ? offsetof(gpu::ParticlePlasticState, materialIndex) / sizeof(float) : words;
    for (std::size_t particle = 0; particle < count; ++particle) {
      for (std::size_t word = 0; word < words; ++word) {
        if (word == indexWord) continue;
        float value;
        std::memcpy(&value, bytes[b].data() + (particle * words + word) * sizeof(float), sizeof value);
        if (std::isfinite(value)) continue;
        throw InputError(source + ": buffer " + std::to_string(b + 1) + " of the checkpoint (" + labelOf(*buffers[b]) +
                         ") holds a value that is not finite (" + (std::isnan(value) ? "NaN" : "infinity") +
                         ") for particle " + std::to_string(particle) +
                         "; a run never checkpoints such a state, so this file cannot be resumed");
      }
    }
  }
}

std::vector<gl::Buffer*> ParticleBuffers::stateBuffers() { return stateBuffersOf(*this); }

}  // namespace firn
