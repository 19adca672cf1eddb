#pragma once
// The particles on the GPU (common/particles.glsl): a buffer per quantity, sized for a capacity and live up to a
// count, published at the particle bindings of the GPU contract (FIRN_PARTICLE_BINDINGS_FIRST to _END). Which
// quantities exist depends on the scene: F for every model but water, APIC's C for APIC only.
#include <cstddef>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gl/Buffer.h"
#include "gl/BufferBindings.h"
#include "gpu/ParticleView.h"
#include "sim/SceneUpload.h"

namespace firn {

// Particle state read back from the GPU.
struct ParticleSnapshot {
  std::vector<glm::vec4> positionMass;    // x (m), mass (kg)
  std::vector<glm::vec4> velocityVolume;  // v (m/s), V0 (m³)
  std::vector<float> plasticJ;            // J_P
  std::size_t size() const { return positionMass.size(); }
};

class ParticleBuffers {
 public:
  ParticleBuffers(std::size_t capacity, bool deformationGradient, bool affine);

  std::size_t capacity() const { return capacity_; }

  // Writes particles [first, first + records.size()) as new: undeformed, unstressed, no affine velocity.
  void write(std::size_t first, const ParticleRecords& records);
  void writeVelocity(std::size_t particle, const glm::vec3& velocityMPerS);
  ParticleSnapshot read(std::size_t count) const;
  glm::vec3 position(std::size_t particle) const;
  // x (m) and mass (kg) of particles [0, count).
  std::vector<glm::vec4> positionsMasses(std::size_t count) const;

  void publish(gl::BufferBindings& bindings) const;
  ParticleView view(std::size_t count, double timeS) const;

  // The buffers a checkpoint holds, in its order (those the scene has).
  std::vector<const gl::Buffer*> stateBuffers() const;
  std::vector<gl::Buffer*> stateBuffers();
  // Throws InputError naming `source`, the buffer and the particle when a float of particles [0, count) in `bytes`
  // is not finite. `bytes` holds the stateBuffers()' contents in their order (a checkpoint's first buffers), each
  // checked to be of its buffer's size, and count is at most the capacity.
  void checkFinite(const std::vector<std::string>& bytes, std::size_t count, const std::string& source) const;

 private:
  template <class Self>
  static auto stateBuffersOf(Self& self);
  const char* labelOf(const gl::Buffer& buffer) const;

  std::size_t capacity_;
  gl::Buffer positionMass_;
  gl::Buffer velocityVolume_;
  gl::Buffer elasticDeformation_;  // F (F_E for snow and sand); water-only scenes carry J alone
  gl::Buffer kirchhoffStress_;
  gl::Buffer affine_;  // APIC only
  gl::Buffer plasticState_;
};

}  // namespace firn
