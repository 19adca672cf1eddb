// Fills each body with particles: sphere, box and mesh bodies through the voxelizer's samplers (a jittered
// lattice aligned with the grid, or Poisson-disk samples), points bodies with the cloud as it is.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "Error.h"
#include "scene/Scene.h"
#include "voxelizer/Voxelizer.h"

namespace firn {
namespace {

// Body i is sampled with seed jitterSeedBase + i, so a scene always gives the same particles, and adding a
// body leaves the others' particles unchanged.
constexpr std::uint32_t jitterSeedBase = 0x4669726e;  // "Firn" in ASCII; any fixed value would do
// Particle and body indices are 32-bit on the GPU.
constexpr std::int64_t maxParticles = std::numeric_limits<std::int32_t>::max();

std::string sceneFileName(const Scene& scene) {
  return scene.sourcePath.empty() ? kBuiltInSceneName : scene.sourcePath.string();
}

std::vector<glm::dvec3> sampleShape(const Body& body, const voxelizer::SamplingOptions& options) {
  const voxelizer::Bounds box{body.boundsMinM(), body.boundsMaxM()};
  switch (body.shape) {
    case BodyShape::Sphere:
      return voxelizer::samplePoints(box, [&](const glm::dvec3& pointM) {
        const glm::dvec3 offsetM = pointM - body.centerM;
        return glm::dot(offsetM, offsetM) <= body.radiusM * body.radiusM;
      }, options);
    case BodyShape::Box:
      return voxelizer::samplePoints(box, [&](const glm::dvec3& pointM) {
        return glm::all(glm::greaterThanEqual(pointM, body.minM)) && glm::all(glm::lessThanEqual(pointM, body.maxM));
      }, options);
    case BodyShape::Mesh: return voxelizer::voxelize(*body.mesh, options);
    case BodyShape::Points: return *body.pointsM;
  }
  return {};
}

using SeedIterator = std::vector<ParticleSeed>::iterator;

// v = v0 + ω × (x − c) about the body's centre of mass c: the body translates at v0 and spins at ω.
void setInitialMotion(const Body& body, SeedIterator begin, SeedIterator end) {
  if (body.angularVelocityRadPerS == glm::dvec3(0.0)) return;
  glm::dvec3 weightedSumM(0.0);
  double massKg = 0;
  for (auto seed = begin; seed != end; ++seed) {
    weightedSumM += double(seed->massKg) * glm::dvec3(seed->positionM);
    massKg += seed->massKg;
  }
  const glm::dvec3 centerM = weightedSumM / massKg;
  for (auto seed = begin; seed != end; ++seed) {
    seed->velocityMPerS = glm::vec3(body.velocityMPerS +
                                    glm::cross(body.angularVelocityRadPerS, glm::dvec3(seed->positionM) - centerM));
  }
}

// An emitter's particles leave in order of how far they lie along its velocity (the leading edge first, as if
// the body were pushed out of a nozzle at its back), evenly over its release window; at rest, top first.
void setReleaseTimes(const Body& body, double frameRateHz, SeedIterator begin, SeedIterator end) {
  const glm::dvec3 direction = body.velocityMPerS == glm::dvec3(0.0) ? glm::dvec3(0, 1, 0)
                                                                      : glm::normalize(body.velocityMPerS);
  std::stable_sort(begin, end, [&](const ParticleSeed& a, const ParticleSeed& b) {
    return glm::dot(glm::dvec3(a.positionM), direction) > glm::dot(glm::dvec3(b.positionM), direction);
  });
  const double startS = body.startFrame / frameRateHz;
  const double windowS = body.durationFrames / frameRateHz;
  const double count = double(end - begin);
  for (auto seed = begin; seed != end; ++seed) seed->releaseTimeS = startS + windowS * double(seed - begin) / count;
}

}  // namespace

std::vector<ParticleSeed> sampleBodies(const Scene& scene) {
  std::vector<ParticleSeed> particles;
  for (std::size_t bodyIndex = 0; bodyIndex < scene.bodies.size(); ++bodyIndex) {
    const Body& body = scene.bodies[bodyIndex];
    const std::string bodyName = sceneFileName(scene) + ": bodies[" + std::to_string(bodyIndex) + "]";
    const Material& material = scene.materials.at(body.materialIndex);
    const double spacingM = scene.grid.cellSizeM / std::cbrt(body.particlesPerCell);

    // The lattice has about one candidate per spacing³ of the bounding box (plus a jitter margin).
    const glm::dvec3 candidatesPerAxis = (body.boundsMaxM() - body.boundsMinM()) / spacingM + 2.0;
    const double candidates = body.shape == BodyShape::Points
                                  ? double(body.pointsM->size())
                                  : candidatesPerAxis.x * candidatesPerAxis.y * candidatesPerAxis.z;
    if (double(particles.size()) + candidates > double(maxParticles)) {
      throw InputError(bodyName + ": too many particles: the scene would exceed " + std::to_string(maxParticles) +
                       "; lower particles_per_cell or the body's size");
    }

    voxelizer::SamplingOptions options;
    options.spacingM = spacingM;
    options.sampler = body.sampler == BodySampler::PoissonDisk ? voxelizer::Sampler::PoissonDisk
                                                               : voxelizer::Sampler::Lattice;
    options.seed = jitterSeedBase + static_cast<std::uint32_t>(bodyIndex);
    options.latticeOriginM = scene.grid.originM;
    const std::vector<glm::dvec3> positionsM = sampleShape(body, options);
    if (positionsM.empty()) {
      std::ostringstream message;
      message << bodyName << ": no particles: the body is smaller than the particle spacing s = " << spacingM
              << " m (cell_size / cbrt(particles_per_cell))";
      throw InputError(message.str());
    }

    // Each sampled particle carries its share of the shape's volume (voxelizer/Samplers.h); a points body brings
    // its own masses.
    const double sampledMassKg =
        body.shape == BodyShape::Points
            ? 0
            : material.densityKgPerM3 * voxelizer::volumePerSampleM3(positionsM.size(), options, [&](const auto& o) {
                return sampleShape(body, o);
              });
    const std::size_t first = particles.size();
    for (std::size_t i = 0; i < positionsM.size(); ++i) {
      double massKg = sampledMassKg;
      if (body.shape == BodyShape::Points) {
        massKg = body.pointMassesKg.size() == 1 ? body.pointMassesKg.front() : body.pointMassesKg[i];
      }
      particles.push_back({glm::vec3(positionsM[i]), glm::vec3(body.velocityMPerS),
                           static_cast<float>(massKg * body.massScale), body.materialIndex, static_cast<int>(bodyIndex)});
    }
    setInitialMotion(body, particles.begin() + std::ptrdiff_t(first), particles.end());
    if (body.isEmitter()) setReleaseTimes(body, scene.time.frameRateHz, particles.begin() + std::ptrdiff_t(first), particles.end());
  }
  return particles;
}

}  // namespace firn
