#pragma once
// One headless GL context shared by every test in the GL test binary (llvmpipe in CI).
#include <cmath>
#include <cstddef>
#include <cstring>

#include "gl/Context.h"
#include "sim/Simulation.h"

namespace firn::test {

inline gl::HeadlessContext& glContext() {
  static gl::HeadlessContext context;
  return context;
}

// The index of the first particle with a non-finite position, velocity or J_P, or the count if there is none.
inline std::size_t firstNonFiniteParticle(const ParticleSnapshot& s) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    const float sum = s.positionMass[i].x + s.positionMass[i].y + s.positionMass[i].z + s.velocityVolume[i].x +
                      s.velocityVolume[i].y + s.velocityVolume[i].z + s.plasticJ[i];
    if (!std::isfinite(sum)) return i;  // a NaN or infinity in any term makes the sum non-finite
  }
  return s.size();
}

// Whether two snapshots hold the same particles to the last bit (positions, masses, velocities, volumes, J_P).
inline bool sameBytes(const ParticleSnapshot& a, const ParticleSnapshot& b) {
  return a.size() == b.size() &&
         std::memcmp(a.positionMass.data(), b.positionMass.data(), a.size() * sizeof(glm::vec4)) == 0 &&
         std::memcmp(a.velocityVolume.data(), b.velocityVolume.data(), a.size() * sizeof(glm::vec4)) == 0 &&
         std::memcmp(a.plasticJ.data(), b.plasticJ.data(), a.size() * sizeof(float)) == 0;
}

}  // namespace firn::test
