// Fills each body with particles on a jittered lattice aligned with the grid.
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "Error.h"
#include "scene/Scene.h"

namespace firn {
namespace {

// Body i draws its jitter from std::mt19937 seeded with jitterSeedBase + i, so a scene always gives the same
// particles, and adding a body leaves the others' particles unchanged.
constexpr std::uint32_t jitterSeedBase = 0x4669726e;  // "Firn" in ASCII; any fixed value would do
// Offsets of up to a quarter spacing break the lattice's alignment with the grid (which otherwise shows as
// regular patterns in the stress) while keeping neighbours at least half a spacing apart.
constexpr double jitterFraction = 0.25;
// Particle and body indices are 32-bit on the GPU.
constexpr std::int64_t maxParticles = std::numeric_limits<std::int32_t>::max();

// A uniform offset in [-jitterFraction, jitterFraction) spacings. Built from mt19937's raw output, which the
// C++ standard fixes bit for bit, not from std::uniform_real_distribution, whose output the standard leaves
// to each library: the same scene then gives the same particles with libstdc++, libc++ and MSVC.
double jitterM(std::mt19937& random, double spacingM) {
  constexpr double twoTo32 = 4294967296.0;
  const double unit = static_cast<double>(random()) / twoTo32;  // [0, 1), 32 bits of resolution
  return (2 * unit - 1) * jitterFraction * spacingM;
}

bool contains(const Body& body, const glm::dvec3& pointM) {
  switch (body.shape) {
    case BodyShape::Sphere: {
      const glm::dvec3 offsetM = pointM - body.centerM;
      return glm::dot(offsetM, offsetM) <= body.radiusM * body.radiusM;
    }
    case BodyShape::Box:
      return glm::all(glm::greaterThanEqual(pointM, body.minM)) && glm::all(glm::lessThanEqual(pointM, body.maxM));
  }
  return false;
}

std::string sceneFileName(const Scene& scene) {
  return scene.sourcePath.empty() ? kBuiltInSceneName : scene.sourcePath.string();
}

}  // namespace

std::vector<ParticleSeed> sampleBodies(const Scene& scene) {
  std::vector<ParticleSeed> particles;
  const glm::dvec3 originM = scene.grid.originM;
  for (std::size_t bodyIndex = 0; bodyIndex < scene.bodies.size(); ++bodyIndex) {
    const Body& body = scene.bodies[bodyIndex];
    const std::string bodyName = sceneFileName(scene) + ": bodies[" + std::to_string(bodyIndex) + "]";
    const SnowMaterial& material = scene.materials.at(body.materialIndex);
    const double spacingM = scene.grid.cellSizeM / std::cbrt(body.particlesPerCell);
    const float massKg = static_cast<float>(material.densityKgPerM3 * spacingM * spacingM * spacingM);

    // Lattice points sit at originM + (i + 0.5) spacing; take every one whose jittered position could land in
    // the bounding box.
    const glm::dvec3 firstIndexReal = glm::floor((body.boundsMinM() - originM) / spacingM - 0.5 - jitterFraction);
    const glm::dvec3 lastIndexReal = glm::ceil((body.boundsMaxM() - originM) / spacingM - 0.5 + jitterFraction);
    const glm::dvec3 pointsPerAxis = lastIndexReal - firstIndexReal + 1.0;
    if (static_cast<double>(particles.size()) + pointsPerAxis.x * pointsPerAxis.y * pointsPerAxis.z >
        static_cast<double>(maxParticles)) {
      throw InputError(bodyName + ": too many particles: the scene would exceed " + std::to_string(maxParticles) +
                       "; lower particles_per_cell or the body's size");
    }
    const glm::ivec3 firstIndex(firstIndexReal);
    const glm::ivec3 lastIndex(lastIndexReal);

    std::mt19937 random(jitterSeedBase + static_cast<std::uint32_t>(bodyIndex));
    const std::size_t countBefore = particles.size();
    for (int k = firstIndex.z; k <= lastIndex.z; ++k) {
      for (int j = firstIndex.y; j <= lastIndex.y; ++j) {
        for (int i = firstIndex.x; i <= lastIndex.x; ++i) {
          // Separate statements fix the order of the draws (argument evaluation order is unspecified).
          const double jitterXM = jitterM(random, spacingM);
          const double jitterYM = jitterM(random, spacingM);
          const double jitterZM = jitterM(random, spacingM);
          const glm::dvec3 latticePointM = originM + (glm::dvec3(i, j, k) + 0.5) * spacingM;
          const glm::vec3 positionM(latticePointM + glm::dvec3(jitterXM, jitterYM, jitterZM));
          // Tested after rounding to float, so the stored position itself lies in the shape.
          if (!contains(body, glm::dvec3(positionM))) continue;
          particles.push_back({positionM, glm::vec3(body.velocityMPerS), massKg, body.materialIndex,
                               static_cast<int>(bodyIndex)});
        }
      }
    }
    if (particles.size() == countBefore) {
      std::ostringstream message;
      message << bodyName << ": no particles: the body is smaller than the particle spacing s = " << spacingM
              << " m (cell_size / cbrt(particles_per_cell))";
      throw InputError(message.str());
    }
  }
  return particles;
}

}  // namespace firn
