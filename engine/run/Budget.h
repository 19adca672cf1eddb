#pragma once
// Before sampling a scene: the particles its bodies will make, estimated, against what the GPU's buffers hold
// and what the host can allocate; then sampling held to that (docs/scene-format.md, Sizes and limits).
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "gl/Context.h"
#include "scene/Sampling.h"
#include "scene/Scene.h"

namespace firn {

// Host memory per particle from sampling to the first step, beside the GPU's buffers: measured as the peak
// resident memory of `firn run --frames 0` over 0.46 and 1.8 million particles of a box on llvmpipe, 405 bytes
// per particle, less the 152 of that scene's particle buffers that llvmpipe keeps in host memory, rounded up.
constexpr double kHostBytesPerParticle = 256;

struct ParticleBudget {
  std::vector<BodyEstimate> bodies;  // estimateBodies
  double reservedParticles = 0;      // room kept for particles added while running (the viewer's snowballs)
  std::size_t maxParticles = 0;      // what the limits leave for the bodies' particles, all together
  std::string limit;                 // the limit that binds, in words
};

// Estimates the bodies' particles and checks them, with `reservedParticles` more, against each particle buffer's
// largest size, the GPU's free memory where the driver says, the host's allocatable memory and the GPU's 32-bit
// indices. Throws InputError naming the scene file, the bodies, the estimate, the limit and what to change. Over
// `shares` processes (docs/distributed.md) each GPU holds about its share of the particles and a quarter more.
ParticleBudget checkParticleBudget(const Scene& scene, const gl::ContextInfo& gl, double reservedParticles,
                                   int shares = 1);

// checkParticleBudget, then sampleBodies held to its maxParticles, reporting each body's progress to `progress`
// when set.
std::vector<ParticleSeed> sampleWithinBudget(const Scene& scene, const gl::ContextInfo& gl, double reservedParticles,
                                             const std::function<void(std::size_t body, double fraction)>& progress,
                                             int shares = 1);
// The same with the budget checked already.
std::vector<ParticleSeed> sampleWithinBudget(const Scene& scene, const ParticleBudget& budget,
                                             const std::function<void(std::size_t body, double fraction)>& progress);

}  // namespace firn
