#pragma once
// What the readers of the particles beside the simulation (the renderer, the surface reconstruction) see of them: the
// buffers they read, how many particles are live, and the simulated time they are at. A view binds its buffers at the
// particle bindings of the GPU contract (common/particles.glsl), so that a reader's programs find them where the
// simulation's passes do; it owns nothing and is valid until the simulation next steps or grows.
#include <cstddef>

#include "gl/Buffer.h"
#include "gl/BufferBindings.h"
#include "gpu/GpuLayout.h"

namespace firn {

struct ParticleView {
  const gl::Buffer* positionMass = nullptr;     // vec4 per particle: x (m), mass (kg)
  const gl::Buffer* velocityVolume = nullptr;   // vec4 per particle: v (m/s), V0 (m³)
  const gl::Buffer* kirchhoffStress = nullptr;  // mat3 per particle: τ (Pa)
  const gl::Buffer* plasticState = nullptr;     // ParticlePlasticState per particle
  std::size_t count = 0;
  double timeS = 0;

  // Publishes the buffers at their particle bindings (nothing for a view of no buffers: a scene drawn without
  // particles).
  void publish(gl::BufferBindings& bindings) const {
    if (positionMass == nullptr) return;
    bindings.storage(FIRN_BINDING_POSITION_MASS, *positionMass);
    bindings.storage(FIRN_BINDING_VELOCITY_VOLUME, *velocityVolume);
    bindings.storage(FIRN_BINDING_KIRCHHOFF_STRESS, *kirchhoffStress);
    bindings.storage(FIRN_BINDING_PLASTIC_STATE, *plasticState);
  }
};

}  // namespace firn
