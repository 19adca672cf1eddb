// Fills each body with particles: sphere, box and mesh bodies through the voxelizer's samplers (a jittered
// lattice aligned with the grid, or Poisson-disk samples), points bodies with the cloud as it is.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "Error.h"
#include "io/Text.h"
#include "scene/Sampling.h"
#include "voxelizer/Voxelizer.h"

namespace firn {
namespace {

// Body i is sampled with seed jitterSeedBase + i, so a scene always gives the same particles, and adding a
// body leaves the others' particles unchanged.
constexpr std::uint32_t jitterSeedBase = 0x4669726e;  // "Firn" in ASCII; any fixed value would do
// Particle and body indices are 32-bit on the GPU.
constexpr std::size_t maxParticleIndices = std::numeric_limits<std::int32_t>::max();
constexpr double pi = 3.14159265358979323846;

voxelizer::SamplingOptions samplingOptions(const Scene& scene, std::size_t bodyIndex) {
  const Body& body = scene.bodies[bodyIndex];
  voxelizer::SamplingOptions options;
  options.spacingM = particleSpacingM(body, scene.grid);
  options.sampler = body.sampler == BodySampler::PoissonDisk ? voxelizer::Sampler::PoissonDisk
                                                             : voxelizer::Sampler::Lattice;
  options.seed = jitterSeedBase + static_cast<std::uint32_t>(bodyIndex);
  options.latticeOriginM = scene.grid.originM;
  return options;
}

// Why a sphere or box body yields no particle, and the particles per cell that would fill it.
std::string whyShapeHasNoParticles(const Body& body, const GridSpec& grid) {
  const glm::dvec3 extentM = body.boundsMaxM() - body.boundsMinM();
  const double thinnestM = std::min({extentM.x, extentM.y, extentM.z});
  // A lattice a quarter of the thinnest extent apart puts points across it (voxelizer::whyNoParticles).
  const double fillingSpacingM = thinnestM / 4;
  const double fillingParticlesPerCell = std::pow(grid.cellSizeM / fillingSpacingM, 3.0);
  std::string message = "no particles: the body, " + format("%.3g m", thinnestM) +
                        " at its thinnest, is smaller than the particle spacing s = " +
                        format("%.3g m", particleSpacingM(body, grid)) + " (cell_size / cbrt(particles_per_cell)); ";
  if (fillingParticlesPerCell <= 1000) {
    return message + "particles_per_cell " + format("%.3g", std::ceil(fillingParticlesPerCell)) + " would fill it";
  }
  return message + "make it larger, or use a smaller cell_size (" + format("%.3g m", fillingSpacingM * 10) +
         " with 1000 particles per cell)";
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

double particleSpacingM(const Body& body, const GridSpec& grid) {
  return grid.cellSizeM / std::cbrt(body.particlesPerCell);
}

double shapeVolumeM3(const Body& body) {
  const glm::dvec3 extentM = body.maxM - body.minM;
  switch (body.shape) {
    case BodyShape::Sphere: return 4.0 / 3.0 * pi * body.radiusM * body.radiusM * body.radiusM;
    case BodyShape::Box: return extentM.x * extentM.y * extentM.z;
    default: return 0;
  }
}

std::string bodyName(const Scene& scene, std::size_t bodyIndex) {
  return sceneFileName(scene) + ": bodies[" + std::to_string(bodyIndex) + "]";
}

BodyEstimate estimateBody(const Body& body, const GridSpec& grid) {
  if (body.shape == BodyShape::Points) return {double(body.pointsM->size()), 0};
  voxelizer::SamplingOptions options;
  options.spacingM = particleSpacingM(body, grid);
  options.sampler = body.sampler == BodySampler::PoissonDisk ? voxelizer::Sampler::PoissonDisk
                                                             : voxelizer::Sampler::Lattice;
  options.latticeOriginM = grid.originM;
  const voxelizer::Bounds box{body.boundsMinM(), body.boundsMaxM()};
  voxelizer::SampleEstimate estimate;
  if (body.shape == BodyShape::Mesh) {
    estimate = voxelizer::estimateVoxelize(*body.mesh, options);
  } else if (body.shape == BodyShape::Sphere) {
    const double r = body.radiusM;
    estimate = voxelizer::estimateSamples(box, shapeVolumeM3(body), 4 * pi * r * r, options);
  } else {
    const glm::dvec3 e = body.maxM - body.minM;
    estimate = voxelizer::estimateSamples(box, shapeVolumeM3(body), 2 * (e.x * e.y + e.y * e.z + e.z * e.x), options);
  }
  return {estimate.points, estimate.insideTests};
}

std::vector<BodyEstimate> estimateBodies(const Scene& scene) {
  std::vector<BodyEstimate> estimates;
  for (const Body& body : scene.bodies) estimates.push_back(estimateBody(body, scene.grid));
  return estimates;
}

std::vector<ParticleSeed> sampleBodies(const Scene& scene) {
  SamplingLimits limits;
  limits.maxParticles = maxParticleIndices;
  limits.reason = "the GPU's 32-bit particle indices";
  return sampleBodies(scene, limits);
}

std::vector<ParticleSeed> sampleBodies(const Scene& scene, const SamplingLimits& limits) {
  const std::size_t maxParticles = std::min(limits.maxParticles, maxParticleIndices);
  std::vector<ParticleSeed> particles;
  particles.reserve(std::min(limits.expectedParticles, maxParticles));
  for (std::size_t bodyIndex = 0; bodyIndex < scene.bodies.size(); ++bodyIndex) {
    const Body& body = scene.bodies[bodyIndex];
    const std::string name = bodyName(scene, bodyIndex);
    const Material& material = scene.materials.at(body.materialIndex);
    voxelizer::SamplingOptions options = samplingOptions(scene, bodyIndex);
    options.maxPoints = maxParticles - std::min(maxParticles, particles.size());
    if (limits.progress) options.progress = [&](double fraction) { limits.progress(bodyIndex, fraction); };
    const auto tooMany = [&] {
      return InputError(name + ": sampling stopped past " + format("%.0f", double(options.maxPoints)) + " particles" +
                        (particles.empty() ? "" : " (beyond the other bodies' " + format("%.0f", double(particles.size())) + ")") +
                        ", the most " + limits.reason + " leaves room for; lower particles_per_cell or the body's size");
    };
    std::vector<glm::dvec3> positionsM;
    try {
      positionsM = sampleShape(body, options);
    } catch (const voxelizer::TooManySamples&) {
      throw tooMany();
    }
    if (positionsM.size() > options.maxPoints) throw tooMany();  // a points body's cloud
    if (positionsM.empty()) {
      throw InputError(name + ": " + (body.shape == BodyShape::Mesh
                                          ? voxelizer::whyNoParticles(*body.mesh, voxelizer::measureSurface(*body.mesh),
                                                                      options.spacingM)
                                          : whyShapeHasNoParticles(body, scene.grid)));
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
