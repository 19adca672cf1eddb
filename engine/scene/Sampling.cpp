// Fills each body with particles: sphere, box and mesh bodies through the voxelizer's samplers (a jittered
// lattice aligned with the grid, or Poisson-disk samples), points bodies with the cloud as it is.
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

}  // namespace

std::vector<ParticleSeed> sampleBodies(const Scene& scene) {
  std::vector<ParticleSeed> particles;
  for (std::size_t bodyIndex = 0; bodyIndex < scene.bodies.size(); ++bodyIndex) {
    const Body& body = scene.bodies[bodyIndex];
    const std::string bodyName = sceneFileName(scene) + ": bodies[" + std::to_string(bodyIndex) + "]";
    const SnowMaterial& material = scene.materials.at(body.materialIndex);
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

    // A lattice body has one particle per s³ of material. Poisson-disk samples pack a little denser along the
    // surface (voxelizer/Samplers.h), so their mass is ρ V / N with V the lattice's measure of the same shape.
    // A points body brings its own masses.
    double sampledMassKg = material.densityKgPerM3 * spacingM * spacingM * spacingM;
    if (options.sampler == voxelizer::Sampler::PoissonDisk) {
      voxelizer::SamplingOptions lattice = options;
      lattice.sampler = voxelizer::Sampler::Lattice;
      sampledMassKg *= double(sampleShape(body, lattice).size()) / double(positionsM.size());
    }
    for (std::size_t i = 0; i < positionsM.size(); ++i) {
      double massKg = sampledMassKg;
      if (body.shape == BodyShape::Points) {
        massKg = body.pointMassesKg.size() == 1 ? body.pointMassesKg.front() : body.pointMassesKg[i];
      }
      particles.push_back({glm::vec3(positionsM[i]), glm::vec3(body.velocityMPerS), static_cast<float>(massKg),
                           body.materialIndex, static_cast<int>(bodyIndex)});
    }
  }
  return particles;
}

}  // namespace firn
