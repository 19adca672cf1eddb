#include "sim/SceneUpload.h"

#include <algorithm>
#include <unordered_set>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "gpu/GpuFunctions.h"
#include "io/Checkpoint.h"
#include "scene/ColliderMotion.h"

namespace firn {

std::vector<gpu::ColliderParams> buildColliderTable(const Scene& scene, double timeS) {
  std::vector<gpu::ColliderParams> colliders(std::max<std::size_t>(scene.colliders.size(), 1), gpu::ColliderParams{});
  for (std::size_t i = 0; i < scene.colliders.size(); ++i) {
    const Collider& c = scene.colliders[i];
    gpu::ColliderParams& out = colliders[i];
    // The shape at rest, from the pivot: with the default pivot its defining point is the pivot itself, 0.
    switch (c.shape) {
      case ColliderShape::Plane:
        out.shapeA = glm::vec4(glm::vec3(c.pointM - c.pivotM), 0);
        out.shapeB = glm::vec4(glm::vec3(glm::normalize(c.normal)), 0);
        out.shapeBoundary.x = gpu::SHAPE_PLANE;
        break;
      case ColliderShape::Sphere:
        out.shapeA = glm::vec4(glm::vec3(c.centerM - c.pivotM), float(c.radiusM));
        out.shapeBoundary.x = gpu::SHAPE_SPHERE;
        break;
      case ColliderShape::Box:
        out.shapeA = glm::vec4(glm::vec3(0.5 * (c.minM + c.maxM) - c.pivotM), 0);
        out.shapeB = glm::vec4(glm::vec3(0.5 * (c.maxM - c.minM)), 0);
        out.shapeBoundary.x = gpu::SHAPE_BOX;
        break;
    }
    const RigidPose segment = colliderPose(c, colliderPose(c, timeS).segmentStartS);
    out.pivotTime = glm::vec4(glm::vec3(segment.pivotM), float(segment.segmentStartS));
    out.rotation = glm::vec4(float(segment.rotation.x), float(segment.rotation.y), float(segment.rotation.z),
                             float(segment.rotation.w));
    out.velocityFriction = glm::vec4(glm::vec3(segment.velocityMPerS), float(c.friction));
    out.angularVelocity = glm::vec4(glm::vec3(segment.angularVelocityRadPerS), 0);
    out.shapeBoundary.y = c.boundary == Boundary::Sticky ? gpu::BOUNDARY_STICKY
                          : c.boundary == Boundary::Slip ? gpu::BOUNDARY_SLIP
                                                         : gpu::BOUNDARY_SEPARATE;
  }
  return colliders;
}

const std::vector<gpu::ColliderParams>& ColliderTableAt::operator()(double timeS) {
  if (table_.empty() || timeS != timeS_) {
    table_ = buildColliderTable(scene_, timeS);
    timeS_ = timeS;
  }
  return table_;
}

ColliderEscape escapeColliders(const GridSpec& grid, const std::vector<gpu::ColliderParams>& colliders,
                               const ParticleSeed& seed) {
  // A few passes settle a particle in overlapping colliders (a box resting on a plane); one still inside after
  // them is wedged between colliders.
  constexpr int passes = 4;
  // Just past the surface, so that rounding to float leaves it outside.
  constexpr double marginCells = 1e-3;
  const auto timeS = static_cast<float>(seed.releaseTimeS);
  const auto marginM = static_cast<float>(marginCells * grid.cellSizeM);
  ColliderEscape escape;
  escape.positionM = seed.positionM;
  bool inside = false;
  for (int pass = 0; pass < passes; ++pass) {
    inside = false;
    for (std::size_t c = 0; c < colliders.size(); ++c) {
      glm::vec3 normal;
      const float distanceM = gpu::colliderDistance(colliders[c], escape.positionM, timeS, normal);
      if (!(distanceM < 0)) continue;
      if (escape.collider < 0) {
        escape.collider = static_cast<int>(c);
        escape.depthM = -distanceM;
      }
      inside = true;
      escape.positionM += (marginM - distanceM) * normal;
    }
    if (!inside) break;
  }
  if (escape.collider < 0) return escape;
  const glm::dvec3 movedM(escape.positionM);
  escape.stuck = inside || !glm::all(glm::greaterThanEqual(movedM, grid.interiorMinM())) ||
                 !glm::all(glm::lessThanEqual(movedM, grid.interiorMaxM()));
  if (escape.stuck) escape.positionM = seed.positionM;
  return escape;
}

ParticleRecords particleRecords(const Scene& scene, const MaterialTable& table, const std::vector<ParticleSeed>& seeds) {
  ColliderTableAt colliders(scene);
  const bool hasColliders = !scene.colliders.empty();
  ParticleRecords records;
  records.positionMass.reserve(seeds.size());
  records.velocityVolume.reserve(seeds.size());
  records.plastic.reserve(seeds.size());
  for (const ParticleSeed& seed : seeds) {
    const Material& material = scene.materials.at(std::size_t(seed.materialIndex));
    const glm::vec3 positionM = hasColliders && seed.bodyIndex >= 0 ? escapeColliders(scene.grid, colliders(seed.releaseTimeS), seed).positionM
                                                                    : seed.positionM;
    records.positionMass.emplace_back(positionM, seed.massKg);
    records.velocityVolume.emplace_back(seed.velocityMPerS, float(seed.massKg / material.densityKgPerM3));
    // Particles added while running (bodyIndex −1) use their material's own entry.
    const std::uint32_t entry = seed.bodyIndex >= 0 ? table.bodyEntry.at(std::size_t(seed.bodyIndex))
                                                    : static_cast<std::uint32_t>(seed.materialIndex);
    // Sand's hardening state q starts at 0; J_P (snow) and J (water) start at 1.
    const bool sand = material.model == MaterialModel::DruckerPrager;
    records.plastic.push_back({sand ? 0.0f : 1.0f, entry, 0.0f, 0.0f});
  }
  return records;
}

std::size_t blocksReached(const Scene& scene, const std::vector<ParticleSeed>& seeds) {
  const int kernelWidth = scene.solver.kernel == Kernel::Cubic ? 4 : 3;
  const glm::ivec3 blocks = (scene.grid.cells + 1 + gpu::BLOCK_WIDTH - 1) / gpu::BLOCK_WIDTH;
  std::unordered_set<std::int64_t> reached;
  for (const ParticleSeed& seed : seeds) {
    // The stencil's base node (shaders/common/kernel.glsl): the node below the particle's cell (cubic), or the
    // nearest node below its position minus half a cell (quadratic).
    const glm::dvec3 cells = (glm::dvec3(seed.positionM) - scene.grid.originM) / scene.grid.cellSizeM;
    const glm::ivec3 base = glm::ivec3(glm::floor(kernelWidth == 4 ? cells - 1.0 : cells - 0.5));
    const glm::ivec3 first = glm::max(base, 0) / gpu::BLOCK_WIDTH;
    const glm::ivec3 last = glm::min((glm::max(base, 0) + kernelWidth - 1) / gpu::BLOCK_WIDTH, blocks - 1);
    for (int z = first.z; z <= last.z; ++z)
      for (int y = first.y; y <= last.y; ++y)
        for (int x = first.x; x <= last.x; ++x) reached.insert(x + std::int64_t(blocks.x) * (y + std::int64_t(blocks.y) * z));
  }
  return reached.size();
}

std::uint64_t sceneFingerprint(const Scene& scene, std::size_t particleCapacity, const MaterialTable& table,
                               const std::vector<ParticleSeed>& seeds) {
  const glm::ivec3 gridNodes = scene.grid.cells + 1;
  std::uint64_t hash = fingerprint(&gridNodes, sizeof gridNodes);
  for (const double value : {scene.grid.cellSizeM, scene.time.dtS, double(particleCapacity)}) {
    hash = fingerprint(&value, sizeof value, hash);
  }
  hash = fingerprint(table.entries.data(), table.entries.size() * sizeof(gpu::MaterialParams), hash);
  for (const ParticleSeed& seed : seeds) {
    hash = fingerprint(&seed.positionM, sizeof seed.positionM, hash);
    hash = fingerprint(&seed.velocityMPerS, sizeof seed.velocityMPerS, hash);
    hash = fingerprint(&seed.massKg, sizeof seed.massKg, hash);
    hash = fingerprint(&seed.releaseTimeS, sizeof seed.releaseTimeS, hash);
  }
  return hash;
}

}  // namespace firn
