#include "render/Geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/geometric.hpp>

#include "scene/ColliderMotion.h"

namespace firn::render {

namespace {

constexpr double kPi = 3.14159265358979323846;
// A ground normal must be within ~25° of +y (cos 25° ≈ 0.9) for the key light to fall steeply enough on it.
constexpr double kMinGroundNormalY = 0.9;
// Vertices closer than this fraction of a mesh's reach from its origin are one point for smoothing normals: far
// above double rounding (1e-16), far below any feature a picture shows.
constexpr double kWeldFraction = 1e-9;

Bounds domainBounds(const Scene& scene) { return {scene.domainMinM(), scene.domainMaxM()}; }

double largestExtentM(const Scene& scene) {
  const glm::dvec3 extentM = scene.domainMaxM() - scene.domainMinM();
  return std::max({extentM.x, extentM.y, extentM.z});
}

glm::dvec3 corner(const Bounds& box, int index) {
  return {(index & 1) ? box.maxM.x : box.minM.x, (index & 2) ? box.maxM.y : box.minM.y,
          (index & 4) ? box.maxM.z : box.minM.z};
}

void include(Bounds& region, bool& empty, const glm::dvec3& minM, const glm::dvec3& maxM) {
  region.minM = empty ? minM : glm::min(region.minM, minM);
  region.maxM = empty ? maxM : glm::max(region.maxM, maxM);
  empty = false;
}

// Clips a box to the domain; false when they do not overlap.
bool clipToDomain(const Scene& scene, glm::dvec3& minM, glm::dvec3& maxM) {
  minM = glm::max(minM, scene.domainMinM());
  maxM = glm::min(maxM, scene.domainMaxM());
  return minM.x <= maxM.x && minM.y <= maxM.y && minM.z <= maxM.z;
}

}  // namespace

bool planeCutsDomain(const Scene& scene, const glm::dvec3& pointM, const glm::dvec3& normal) {
  const Bounds domain = domainBounds(scene);
  const double centreDistanceM = glm::dot(domain.centerM() - pointM, normal);
  // The farthest a box's point gets from its centre along a unit normal.
  const double reachM = glm::dot(0.5 * (domain.maxM - domain.minM), glm::abs(normal));
  return std::abs(centreDistanceM) <= reachM;
}

PlaneQuad planeQuad(const Scene& scene, const glm::dvec3& pointM, const glm::dvec3& normal) {
  const glm::dvec3 unitNormal = glm::normalize(normal);
  const glm::dvec3 domainCentreM = domainBounds(scene).centerM();
  const glm::dvec3 centreM = domainCentreM - unitNormal * glm::dot(domainCentreM - pointM, unitNormal);
  // Any axis far from the normal gives a tangent; for a ground facing +y this makes tangentU = +x.
  const glm::dvec3 helper = std::abs(unitNormal.y) < kMinGroundNormalY ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, -1);
  const glm::dvec3 tangentU = glm::normalize(glm::cross(helper, unitNormal));
  const glm::dvec3 tangentV = glm::cross(unitNormal, tangentU);
  return {glm::vec3(centreM), glm::vec3(unitNormal), glm::vec3(tangentU), glm::vec3(tangentV),
          static_cast<float>(largestExtentM(scene))};
}

Ground findGround(const Scene& scene) {
  for (std::size_t i = 0; i < scene.colliders.size(); ++i) {
    const Collider& collider = scene.colliders[i];
    // The ground is drawn moving at most along itself; a keyframed plane turns, and is drawn as a plane.
    if (collider.shape != ColliderShape::Plane || !collider.keyframes.empty()) continue;
    const glm::dvec3 normal = glm::normalize(collider.normal);
    if (normal.y < kMinGroundNormalY || !planeCutsDomain(scene, collider.pointM, normal)) continue;
    return {planeQuad(scene, collider.pointM, normal), glm::vec3(collider.velocityMPerS), static_cast<int>(i)};
  }
  return {planeQuad(scene, scene.grid.interiorMinM(), glm::dvec3(0, 1, 0)), glm::vec3(0.0f), -1};
}

std::vector<SurfaceVertex> quadTriangles(const PlaneQuad& quad) {
  const float s = quad.halfSizeM;
  const glm::vec2 cornersM[4] = {{-s, -s}, {s, -s}, {s, s}, {-s, s}};  // counter-clockwise seen from +normal
  std::vector<SurfaceVertex> vertices;
  for (int index : {0, 1, 2, 0, 2, 3}) {
    const glm::vec2 uv = cornersM[index];
    vertices.push_back({quad.centerM + uv.x * quad.tangentU + uv.y * quad.tangentV, quad.normal, uv});
  }
  return vertices;
}

std::vector<SurfaceVertex> objectTriangles(const SceneObject& object) {
  const auto& meshM = object.meshM;
  // A face's cross product: its normal, with a length of twice its area, which weights it in the corners' means.
  std::vector<glm::dvec3> faceAreaNormals;
  faceAreaNormals.reserve(meshM.triangles.size());
  for (const glm::uvec3& triangle : meshM.triangles) {
    const glm::dvec3 a = meshM.vertices[triangle.x], b = meshM.vertices[triangle.y], c = meshM.vertices[triangle.z];
    faceAreaNormals.push_back(glm::cross(b - a, c - a));
  }
  // Vertices at the same place are one point of the surface: a sphere's poles and a file's seams (where its
  // texture coordinates or normals split a vertex) repeat a position under several indices, equal to within
  // rounding (sin π is 1.2e-16, not 0). Positions are compared on a grid of kWeldFraction of the mesh's reach.
  double reachM = 0;
  for (const glm::dvec3& positionM : meshM.vertices) reachM = std::max(reachM, glm::length(positionM));
  const double weldM = reachM > 0 ? kWeldFraction * reachM : 1.0;
  std::vector<unsigned> point(meshM.vertices.size());
  std::map<std::array<long long, 3>, unsigned> pointAt;
  for (std::size_t vertex = 0; vertex < meshM.vertices.size(); ++vertex) {
    const glm::dvec3 cell = glm::round(meshM.vertices[vertex] / weldM);
    const std::array<long long, 3> key{(long long)cell.x, (long long)cell.y, (long long)cell.z};
    point[vertex] = pointAt.try_emplace(key, unsigned(pointAt.size())).first->second;
  }
  // The faces at each point, as one list cut into runs (offsets), so a corner looks at its neighbours only.
  std::vector<std::size_t> firstFace(pointAt.size() + 1, 0);
  for (const glm::uvec3& triangle : meshM.triangles) {
    for (int corner = 0; corner < 3; ++corner) ++firstFace[point[triangle[corner]] + 1];
  }
  for (std::size_t i = 0; i < pointAt.size(); ++i) firstFace[i + 1] += firstFace[i];
  std::vector<std::size_t> facesAtPoint(firstFace.back());
  std::vector<std::size_t> filled(firstFace.begin(), firstFace.end() - 1);
  for (std::size_t face = 0; face < meshM.triangles.size(); ++face) {
    for (int corner = 0; corner < 3; ++corner) facesAtPoint[filled[point[meshM.triangles[face][corner]]]++] = face;
  }

  const double minCosine = std::cos(kCreaseAngleDeg * kPi / 180);
  std::vector<SurfaceVertex> vertices;
  vertices.reserve(3 * meshM.triangles.size());
  for (std::size_t face = 0; face < meshM.triangles.size(); ++face) {
    const double faceLength = glm::length(faceAreaNormals[face]);
    const glm::dvec3 faceNormal = faceLength > 0 ? faceAreaNormals[face] / faceLength : glm::dvec3(0.0);
    for (int corner = 0; corner < 3; ++corner) {
      const unsigned vertex = meshM.triangles[face][corner];
      glm::dvec3 sum = faceAreaNormals[face];
      for (std::size_t i = firstFace[point[vertex]]; i < firstFace[point[vertex] + 1]; ++i) {
        const std::size_t other = facesAtPoint[i];
        const double otherLength = glm::length(faceAreaNormals[other]);
        if (other == face || otherLength == 0) continue;
        if (glm::dot(faceNormal, faceAreaNormals[other]) >= minCosine * otherLength) sum += faceAreaNormals[other];
      }
      const double sumLength = glm::length(sum);
      // A degenerate face (no area, no neighbours within the crease angle) covers no pixels; any unit normal does.
      const glm::dvec3 normal = sumLength > 0 ? sum / sumLength : glm::dvec3(0, 1, 0);
      vertices.push_back({glm::vec3(meshM.vertices[vertex]), glm::vec3(normal)});
    }
  }
  return vertices;
}

std::vector<glm::vec3> boxEdges(const glm::vec3& minM, const glm::vec3& maxM) {
  const Bounds box{glm::dvec3(minM), glm::dvec3(maxM)};
  std::vector<glm::vec3> points;
  for (int from = 0; from < 8; ++from) {
    for (int bit : {1, 2, 4}) {
      if (from & bit) continue;  // each edge once, from its lower end
      points.emplace_back(corner(box, from));
      points.emplace_back(corner(box, from | bit));
    }
  }
  return points;
}

float checkerCellM(const Scene& scene) {
  return static_cast<float>(std::pow(10.0, std::floor(std::log10(largestExtentM(scene) / 4))));
}

namespace {

// The box a body's free flight x(t) = x₀ + v t + ½ g t² sweeps over t in [0, T]: per axis, the flight's extremes
// lie at t = 0, at t = T and where the velocity v + g t changes sign. The walls stop the snow at the interior's
// bounds, so the sweep is clamped to them (clamping each axis commutes with taking its extremes).
Bounds freeFlightSweep(const Scene& scene, const Body& body, double durationS) {
  const glm::dvec3 gravity = scene.gravityMPerS2;
  const glm::dvec3 velocity = body.velocityMPerS;
  glm::dvec3 lowShiftM(0.0), highShiftM(0.0);
  for (int axis = 0; axis < 3; ++axis) {
    const auto shiftM = [&](double t) { return velocity[axis] * t + 0.5 * gravity[axis] * t * t; };
    double low = std::min(0.0, shiftM(durationS)), high = std::max(0.0, shiftM(durationS));
    if (gravity[axis] != 0) {
      const double turnS = -velocity[axis] / gravity[axis];
      if (turnS > 0 && turnS < durationS) {
        low = std::min(low, shiftM(turnS));
        high = std::max(high, shiftM(turnS));
      }
    }
    lowShiftM[axis] = low;
    highShiftM[axis] = high;
  }
  const glm::dvec3 interiorMinM = scene.grid.interiorMinM(), interiorMaxM = scene.grid.interiorMaxM();
  return {glm::clamp(body.boundsMinM() + lowShiftM, interiorMinM, interiorMaxM),
          glm::clamp(body.boundsMaxM() + highShiftM, interiorMinM, interiorMaxM)};
}

bool overlaps(const Bounds& a, const glm::dvec3& minM, const glm::dvec3& maxM) {
  return a.minM.x <= maxM.x && minM.x <= a.maxM.x && a.minM.y <= maxM.y && minM.y <= a.maxM.y &&
         a.minM.z <= maxM.z && minM.z <= a.maxM.z;
}

}  // namespace

Bounds usedRegion(const Scene& scene) {
  const double durationS = scene.time.frames / scene.time.frameRateHz;
  Bounds snow{};
  bool empty = true;
  for (const Body& body : scene.bodies) {
    const Bounds sweep = freeFlightSweep(scene, body, durationS);
    include(snow, empty, sweep.minM, sweep.maxM);
  }
  // Without bodies there is no snow to follow: the whole domain.
  if (empty) return domainBounds(scene);
  Bounds region = snow;
  for (const Collider& collider : scene.colliders) {
    if (collider.shape == ColliderShape::Plane) {
      // A plane the sweep reaches (its corners on both sides): the part under the snow, the sweep's corners
      // dropped onto the plane, within the domain.
      const glm::dvec3 normal = glm::normalize(collider.normal);
      bool below = false, above = false;
      for (int index = 0; index < 8; ++index) {
        const double heightM = glm::dot(corner(snow, index) - collider.pointM, normal);
        below = below || heightM <= 0;
        above = above || heightM >= 0;
      }
      if (!below || !above) continue;
      for (int index = 0; index < 8; ++index) {
        const glm::dvec3 cornerM = corner(snow, index);
        glm::dvec3 footM = cornerM - glm::dot(cornerM - collider.pointM, normal) * normal;
        glm::dvec3 footMaxM = footM;
        if (clipToDomain(scene, footM, footMaxM)) include(region, empty, footM, footMaxM);
      }
      continue;
    }
    glm::dvec3 minM = collider.minM, maxM = collider.maxM;
    if (collider.shape == ColliderShape::Sphere) {
      minM = collider.centerM - collider.radiusM;
      maxM = collider.centerM + collider.radiusM;
    } else if (collider.shape == ColliderShape::Mesh) {
      const voxelizer::Bounds meshBounds = voxelizer::bounds(*collider.mesh);
      minM = meshBounds.minM;
      maxM = meshBounds.maxM;
    }
    if (!collider.keyframes.empty()) {
      // Wherever its keyframes take it, turned any way: within its reach of the pivot's positions.
      const double reachM = colliderReachM(scene, collider);
      minM = glm::dvec3(std::numeric_limits<double>::infinity());
      maxM = -minM;
      for (const ColliderKeyframe& key : collider.keyframes) {
        minM = glm::min(minM, collider.pivotM + key.translateM - reachM);
        maxM = glm::max(maxM, collider.pivotM + key.translateM + reachM);
      }
    }
    // A collider the snow's flight reaches, as far as it lies in the domain.
    if (overlaps(snow, minM, maxM) && clipToDomain(scene, minM, maxM)) include(region, empty, minM, maxM);
  }
  return region;
}

double drawnRadiusM(const Scene& scene) {
  const double halfDiagonalM = 0.5 * glm::length(scene.domainMaxM() - scene.domainMinM());
  const double durationS = scene.time.frames / scene.time.frameRateHz;
  double travelM = 0;
  for (const Collider& collider : scene.colliders) {
    travelM = std::max(travelM, glm::length(collider.velocityMPerS) * durationS);
    for (const ColliderKeyframe& key : collider.keyframes) travelM = std::max(travelM, glm::length(key.translateM));
  }
  // A plane quad's centre lies within the domain; its corners are √2 half-sides further.
  return halfDiagonalM + std::sqrt(2.0) * largestExtentM(scene) + travelM;
}

}  // namespace firn::render
