#include "sim/SceneUpload.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_set>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/matrix.hpp>
#include <glm/vector_relational.hpp>

#include "gpu/GpuFunctions.h"
#include "io/Checkpoint.h"
#include "scene/ColliderMotion.h"
#include "scene/FieldLattice.h"

namespace firn {

namespace {

int boundaryCode(Boundary boundary) {
  return boundary == Boundary::Sticky ? gpu::BOUNDARY_STICKY
         : boundary == Boundary::Slip ? gpu::BOUNDARY_SLIP
                                      : gpu::BOUNDARY_SEPARATE;
}

// Bakes `mesh`'s field for the grid at its resolution, appends its samples and says where they lie from `pivotM`;
// a rigid body's also how steep its interpolation is (the list of the snow near it reads that; a collider's is 0).
ColliderFields::Field appendField(std::vector<float>& samples, const voxelizer::TriangleMesh& mesh, double resolution,
                                  const GridSpec& grid, const glm::dvec3& pivotM, bool rigidBody) {
  voxelizer::DistanceField field = bakeField(mesh, grid, resolution);
  ColliderFields::Field placed;
  placed.first = static_cast<int>(samples.size());
  placed.samples = field.samples;
  placed.originFromPivotM = field.originM - pivotM;
  placed.spacingM = field.spacingM;
  if (rigidBody) placed.steepestSlope = voxelizer::steepestSlope(field);
  // φ, each sample's nearest triangle, and the triangles' records (gpu::FIELD_TRIANGLE_FLOATS): the layout
  // meshRestDistance (common/shared_functions.h) reads.
  static_assert(gpu::FIELD_TRIANGLE_FLOATS == 10 * 3 + 3 && gpu::FIELD_TRIANGLE_FLOATS == kFieldTriangleFloats,
                "a triangle's record: ten vec3s and three neighbours, as the budget counts it");
  samples.insert(samples.end(), field.distancesM.begin(), field.distancesM.end());
  for (const std::int32_t triangle : field.nearestTriangles) samples.push_back(float(triangle));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const voxelizer::TriangleFeatures& features = field.features[t];
    const glm::dvec3 vectors[10] = {mesh.vertices[mesh.triangles[t].x] - pivotM,
                                    mesh.vertices[mesh.triangles[t].y] - pivotM,
                                    mesh.vertices[mesh.triangles[t].z] - pivotM,
                                    features.face,
                                    features.edges[0],
                                    features.edges[1],
                                    features.edges[2],
                                    features.corners[0],
                                    features.corners[1],
                                    features.corners[2]};
    for (const glm::dvec3& v : vectors) samples.insert(samples.end(), {float(v.x), float(v.y), float(v.z)});
    for (const std::int32_t other : features.across) samples.push_back(float(other));
  }
  return placed;
}

void setField(gpu::ColliderParams& entry, const ColliderFields::Field& field) {
  entry.shapeBoundary.x = gpu::SHAPE_MESH;
  entry.field = glm::ivec4(field.first, field.samples);
  entry.fieldOrigin = glm::vec4(glm::vec3(field.originFromPivotM), float(field.spacingM));
  entry.shapeA.w = float(field.steepestSlope * (1.0 + 1e-4));  // above the bound's own rounding
}

// The radius of the sphere about an entry's pivot that holds its whole shape at rest (for a mesh, its field's
// lattice, beyond which φ only grows), for colliderWithinReach (common/colliders.glsl); a plane has none (−1). It is
// 10⁻⁴ larger than exact, far beyond the float rounding of the point's turn into the rest frame, so a point it
// leaves out has φ > 0 and the reach changes no result.
float shapeReachM(const gpu::ColliderParams& entry) {
  double reachM = 0;
  switch (entry.shapeBoundary.x) {
    case gpu::SHAPE_PLANE: return -1.0f;
    case gpu::SHAPE_SPHERE: reachM = glm::length(glm::dvec3(entry.shapeA)) + entry.shapeA.w; break;
    case gpu::SHAPE_BOX: reachM = glm::length(glm::dvec3(entry.shapeA)) + glm::length(glm::dvec3(entry.shapeB)); break;
    case gpu::SHAPE_MESH: {
      const glm::dvec3 lowM(entry.fieldOrigin);
      const glm::dvec3 highM = lowM + double(entry.fieldOrigin.w) * (glm::dvec3(glm::ivec3(entry.field.y, entry.field.z,
                                                                                            entry.field.w)) - 1.0);
      reachM = glm::length(glm::max(glm::abs(lowM), glm::abs(highM)));
      break;
    }
  }
  return float(reachM * (1.0 + 1e-4));
}

// An entry's rigid motion from timeS on (pivot, turn, v, ω; colliderDistance advances it).
void setMotion(gpu::ColliderParams& entry, const glm::dvec3& pivotM, const glm::dquat& rotation,
               const glm::dvec3& velocityMPerS, const glm::dvec3& angularVelocityRadPerS, double timeS) {
  entry.pivotTime = glm::vec4(glm::vec3(pivotM), float(timeS));
  entry.rotation = glm::vec4(float(rotation.x), float(rotation.y), float(rotation.z), float(rotation.w));
  entry.velocity = glm::vec4(glm::vec3(velocityMPerS), 0);
  entry.angularVelocity = glm::vec4(glm::vec3(angularVelocityRadPerS), 0);
}

// How an entry meets the snow: its friction, its reach (the shape must be set first) and whether its load is reported
// (gpu::ColliderParams.contact).
void setContact(gpu::ColliderParams& entry, double friction, bool loadReported) {
  entry.contact = glm::vec4(float(friction), shapeReachM(entry), loadReported ? 1.0f : 0.0f, 0);
}

}  // namespace

std::vector<glm::dvec3> bodyProbes(const RigidBody& body) {
  switch (body.shape) {
    case RigidShape::Sphere: return {glm::dvec3(0.0)};
    case RigidShape::Box: {
      // The corners, the edges' midpoints and the faces' centres: a box set squarely on another of the same
      // footprint has its corners on the other's edges, where the other's φ reads 0 along a side face, and meets it
      // at its faces' centres and edges' midpoints.
      std::vector<glm::dvec3> points;
      for (int x = -1; x <= 1; ++x) {
        for (int y = -1; y <= 1; ++y) {
          for (int z = -1; z <= 1; ++z) {
            if (x != 0 || y != 0 || z != 0) points.push_back(body.halfExtentsM * glm::dvec3(x, y, z));
          }
        }
      }
      return points;
    }
    case RigidShape::Mesh: break;
  }
  // Support points: the vertex farthest along each of a Fibonacci lattice's directions, which spread evenly over
  // the sphere, so the probes outline the mesh's convex hull wherever it may touch a floor or a wall.
  std::vector<std::size_t> chosen;
  const double goldenAngle = glm::pi<double>() * (3 - std::sqrt(5.0));
  for (int k = 0; k < kMeshProbeDirections; ++k) {
    const double y = 1 - 2 * (k + 0.5) / kMeshProbeDirections;
    const double ring = std::sqrt(1 - y * y);
    const glm::dvec3 direction(ring * std::cos(goldenAngle * k), y, ring * std::sin(goldenAngle * k));
    std::size_t farthest = 0;
    for (std::size_t v = 1; v < body.mesh->vertices.size(); ++v) {
      if (glm::dot(body.mesh->vertices[v], direction) > glm::dot(body.mesh->vertices[farthest], direction)) {
        farthest = v;
      }
    }
    if (std::find(chosen.begin(), chosen.end(), farthest) == chosen.end()) chosen.push_back(farthest);
  }
  std::vector<glm::dvec3> points;
  for (const std::size_t v : chosen) points.push_back(body.mesh->vertices[v]);
  // A coarse mesh (its support points and its edges together no more than kMeshProbeDirections) takes its edges'
  // midpoints too, each place once: a box's 12-triangle mesh, whose faces' diagonals are edges, then has the analytic
  // box's 26 probes, and meets a box of the same footprint set squarely on it at its faces' centres and edges'
  // midpoints, where corner on corner each reads the other's φ as 0 and they fell into each other.
  std::vector<glm::dvec3> midpoints;
  for (const glm::uvec3& triangle : body.mesh->triangles) {
    for (int e = 0; e < 3; ++e) {
      const glm::dvec3 midpoint = 0.5 * (body.mesh->vertices[triangle[e]] + body.mesh->vertices[triangle[(e + 1) % 3]]);
      if (std::find(midpoints.begin(), midpoints.end(), midpoint) == midpoints.end()) midpoints.push_back(midpoint);
    }
    if (points.size() + midpoints.size() > std::size_t(kMeshProbeDirections)) {
      midpoints.clear();  // a fine mesh: its support points are probes enough
      break;
    }
  }
  for (const glm::dvec3& midpoint : midpoints) {
    if (std::find(points.begin(), points.end(), midpoint) == points.end()) points.push_back(midpoint);
  }
  std::vector<glm::dvec3> probes;
  for (const glm::dvec3& point : points) probes.push_back(point - body.centerOfMassM);
  return probes;
}

ColliderFields bakeColliderFields(const Scene& scene) {
  ColliderFields fields;
  fields.colliders.resize(scene.colliders.size());
  for (std::size_t i = 0; i < scene.colliders.size(); ++i) {
    const Collider& c = scene.colliders[i];
    if (c.shape == ColliderShape::Mesh) {
      fields.colliders[i] = appendField(fields.samples, *c.mesh, c.fieldResolution, scene.grid, c.pivotM, false);
    }
  }
  fields.bodies.resize(scene.rigidBodies.size());
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i) {
    const RigidBody& body = scene.rigidBodies[i];
    if (body.shape == RigidShape::Mesh) {
      fields.bodies[i] =
          appendField(fields.samples, *body.mesh, body.fieldResolution, scene.grid, body.centerOfMassM, true);
    }
    const std::vector<glm::dvec3> probes = bodyProbes(body);
    fields.bodyProbes.emplace_back(static_cast<int>(fields.samples.size()), static_cast<int>(probes.size()));
    for (const glm::dvec3& probe : probes) {
      fields.samples.insert(fields.samples.end(), {float(probe.x), float(probe.y), float(probe.z)});
    }
  }
  return fields;
}

gpu::ColliderParams rigidBodyEntry(const RigidBody& body, const ColliderFields& fields, std::size_t index,
                                   const ObjectPose& pose, double timeS) {
  gpu::ColliderParams entry{};
  switch (body.shape) {
    case RigidShape::Sphere:
      entry.shapeA = glm::vec4(0, 0, 0, float(body.radiusM));
      entry.shapeBoundary.x = gpu::SHAPE_SPHERE;
      break;
    case RigidShape::Box:
      entry.shapeB = glm::vec4(glm::vec3(body.halfExtentsM), 0);
      entry.shapeBoundary.x = gpu::SHAPE_BOX;
      break;
    case RigidShape::Mesh: setField(entry, fields.bodies.at(index)); break;
  }
  setMotion(entry, pose.positionM, pose.orientation, pose.velocityMPerS, pose.angularVelocityRadPerS, timeS);
  setContact(entry, body.friction, true);
  entry.shapeBoundary.y = boundaryCode(body.boundary);
  entry.shapeBoundary.z = 1;
  entry.shapeBoundary.w = body.parked ? 0 : 1;
  return entry;
}

gpu::BodyRecord rigidBodyRecord(const RigidBody& body, const ColliderFields& fields, std::size_t index,
                                const ObjectPose& pose) {
  gpu::BodyRecord record{};
  const float contactRadiusM = body.shape == RigidShape::Sphere ? float(body.radiusM) : 0.0f;
  record.massRadius = glm::vec4(float(body.massKg), contactRadiusM, 0, 0);
  record.probes = glm::ivec4(fields.bodyProbes.at(index), 0, 0);
  // L = R I Rᵀ ω: the inertia is the body's own frame's, ω the world's.
  const glm::dmat3 turn = glm::mat3_cast(pose.orientation);
  record.angularMomentum =
      glm::vec4(glm::vec3(turn * body.inertiaKgM2 * glm::transpose(turn) * pose.angularVelocityRadPerS), 0);
  const glm::dmat3 inverseInertia = glm::inverse(body.inertiaKgM2);
  for (int column = 0; column < 3; ++column) {
    record.inverseInertia[column] = glm::vec4(glm::vec3(inverseInertia[column]), 0);
  }
  return record;
}

std::vector<gpu::BodyRecord> buildBodyRecords(const Scene& scene, const ColliderFields& fields) {
  std::vector<gpu::BodyRecord> records;
  for (std::size_t b = 0; b < scene.rigidBodies.size(); ++b) {
    const RigidBody& body = scene.rigidBodies[b];
    records.push_back(rigidBodyRecord(body, fields, b, initialBodyPose(body)));
  }
  if (records.empty()) records.emplace_back();  // a zeroed record, so that the binding is always a valid buffer
  return records;
}

std::vector<gpu::ColliderParams> colliderEntries(const Scene& scene, const ColliderFields& fields, double timeS) {
  std::vector<gpu::ColliderParams> colliders(scene.colliders.size(), gpu::ColliderParams{});
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
      case ColliderShape::Mesh: setField(out, fields.colliders.at(i)); break;
    }
    const RigidPose segment = colliderPose(c, colliderPose(c, timeS).segmentStartS);
    setMotion(out, segment.pivotM, segment.rotation, segment.velocityMPerS, segment.angularVelocityRadPerS,
              segment.segmentStartS);
    setContact(out, c.friction, colliderMoves(c));
    out.shapeBoundary.y = boundaryCode(c.boundary);
    out.shapeBoundary.w = 1;
  }
  return colliders;
}

std::vector<gpu::ColliderParams> buildColliderTable(const Scene& scene, const ColliderFields& fields, double timeS) {
  std::vector<gpu::ColliderParams> table = colliderEntries(scene, fields, timeS);
  for (std::size_t b = 0; b < scene.rigidBodies.size(); ++b) {
    const RigidBody& body = scene.rigidBodies[b];
    table.push_back(rigidBodyEntry(body, fields, b, initialBodyPose(body), 0));
  }
  if (table.empty()) table.emplace_back();  // a zeroed entry, so that the binding is always a valid buffer
  return table;
}

const std::vector<gpu::ColliderParams>& ColliderTableAt::operator()(double timeS) {
  if (table_.empty() || timeS != timeS_) {
    table_ = buildColliderTable(scene_, fields_, timeS);
    timeS_ = timeS;
  }
  return table_;
}

ColliderEscape escapeColliders(const GridSpec& grid, const std::vector<gpu::ColliderParams>& colliders,
                               const std::vector<float>& fieldSamples, const ParticleSeed& seed) {
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
      if (colliders[c].shapeBoundary.w == 0) continue;  // a parked body, out of the simulation
      glm::vec3 normal;
      const float distanceM = gpu::colliderDistance(colliders[c], fieldSamples, escape.positionM, timeS, normal);
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

ParticleRecords particleRecords(const Scene& scene, const MaterialTable& table, const ColliderFields& fields,
                                const std::vector<ParticleSeed>& seeds) {
  ColliderTableAt colliders(scene, fields);
  const bool hasColliders = !scene.colliders.empty() || !scene.rigidBodies.empty();
  ParticleRecords records;
  records.positionMass.reserve(seeds.size());
  records.velocityVolume.reserve(seeds.size());
  records.plastic.reserve(seeds.size());
  for (const ParticleSeed& seed : seeds) {
    const Material& material = scene.materials.at(std::size_t(seed.materialIndex));
    const glm::vec3 positionM =
        hasColliders && seed.bodyIndex >= 0
            ? escapeColliders(scene.grid, colliders(seed.releaseTimeS), fields.samples, seed).positionM
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
                               const ColliderFields& fields, const std::vector<ParticleSeed>& seeds) {
  const glm::ivec3 gridNodes = scene.grid.cells + 1;
  std::uint64_t hash = fingerprint(&gridNodes, sizeof gridNodes);
  for (const double value : {scene.grid.cellSizeM, scene.time.dtS, double(particleCapacity)}) {
    hash = fingerprint(&value, sizeof value, hash);
  }
  hash = fingerprint(table.entries.data(), table.entries.size() * sizeof(gpu::MaterialParams), hash);
  // The colliders and rigid bodies as they start (every member a vec4: no padding), and the fields they read.
  const std::vector<gpu::ColliderParams> colliders = buildColliderTable(scene, fields, 0);
  hash = fingerprint(colliders.data(), colliders.size() * sizeof(gpu::ColliderParams), hash);
  hash = fingerprint(fields.samples.data(), fields.samples.size() * sizeof(float), hash);
  for (const ParticleSeed& seed : seeds) {
    hash = fingerprint(&seed.positionM, sizeof seed.positionM, hash);
    hash = fingerprint(&seed.velocityMPerS, sizeof seed.velocityMPerS, hash);
    hash = fingerprint(&seed.massKg, sizeof seed.massKg, hash);
    hash = fingerprint(&seed.releaseTimeS, sizeof seed.releaseTimeS, hash);
  }
  return hash;
}

std::string fingerprintHex(std::uint64_t fingerprint) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(fingerprint));
  return hex;
}

}  // namespace firn
