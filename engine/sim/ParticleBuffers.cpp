#include "sim/ParticleBuffers.h"

#include "gpu/GpuLayout.h"

namespace firn {

namespace {

gpu::Mat3x4 identityMat3() { return {{glm::vec4(1, 0, 0, 0), glm::vec4(0, 1, 0, 0), glm::vec4(0, 0, 1, 0)}}; }

}  // namespace

ParticleBuffers::ParticleBuffers(std::size_t capacity, bool deformationGradient, bool affine) : capacity_(capacity) {
  const std::size_t n = capacity;
  positionMass_ = gl::Buffer(n * sizeof(glm::vec4)).labelled("particles: position, mass");
  velocityVolume_ = gl::Buffer(n * sizeof(glm::vec4)).labelled("particles: velocity, volume");
  plasticState_ = gl::Buffer(n * sizeof(gpu::ParticlePlasticState)).labelled("particles: plastic state");
  if (deformationGradient) elasticDeformation_ = gl::Buffer(n * sizeof(gpu::Mat3x4)).labelled("particles: F");
  kirchhoffStress_ = gl::Buffer(n * sizeof(gpu::Mat3x4)).labelled("particles: Kirchhoff stress");
  if (affine) affine_ = gl::Buffer(n * sizeof(gpu::Mat3x4)).labelled("particles: APIC C");
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

std::vector<gl::Buffer*> ParticleBuffers::stateBuffers() { return stateBuffersOf(*this); }

}  // namespace firn
