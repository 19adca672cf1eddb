#include "render/Geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/geometric.hpp>

#include "scene/ColliderMotion.h"

namespace firn::render {

namespace {

constexpr double kPi = 3.14159265358979323846;
// UV sphere resolution: smooth at the sizes colliders take on screen.
constexpr int kSphereSlices = 48;
constexpr int kSphereStacks = 24;
// A ground normal must be within ~25° of +y (cos 25° ≈ 0.9) for the key light to fall steeply enough on it.
constexpr double kMinGroundNormalY = 0.9;

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

std::vector<SurfaceVertex> sphereTriangles(const glm::vec3& centerM, float radiusM) {
  auto vertex = [&](int slice, int stack) {
    const double azimuth = 2 * kPi * slice / kSphereSlices;
    const double polar = kPi * stack / kSphereStacks;  // 0 at +y
    const glm::vec3 normal(static_cast<float>(std::sin(polar) * std::cos(azimuth)), static_cast<float>(std::cos(polar)),
                           static_cast<float>(-std::sin(polar) * std::sin(azimuth)));
    return SurfaceVertex{centerM + radiusM * normal, normal};
  };
  std::vector<SurfaceVertex> vertices;
  vertices.reserve(std::size_t(kSphereSlices) * kSphereStacks * 6);
  for (int stack = 0; stack < kSphereStacks; ++stack) {
    for (int slice = 0; slice < kSphereSlices; ++slice) {
      const SurfaceVertex a = vertex(slice, stack), b = vertex(slice, stack + 1);
      const SurfaceVertex c = vertex(slice + 1, stack + 1), d = vertex(slice + 1, stack);
      // Counter-clockwise from outside; the triangles at the poles are degenerate on one side, and harmless.
      for (const SurfaceVertex& v : {a, b, c, a, c, d}) vertices.push_back(v);
    }
  }
  return vertices;
}

std::vector<SurfaceVertex> boxTriangles(const glm::vec3& minM, const glm::vec3& maxM) {
  std::vector<SurfaceVertex> vertices;
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      glm::vec3 normal(0.0f);
      normal[axis] = side == 0 ? -1.0f : 1.0f;
      // Tangents u, v with u × v = normal, so the corners below run counter-clockwise seen from outside.
      glm::vec3 u(0.0f), v(0.0f);
      u[(axis + 1) % 3] = 1.0f;
      v[(axis + 2) % 3] = 1.0f;
      if (side == 0) std::swap(u, v);
      const glm::vec3 centreM = 0.5f * (minM + maxM) + normal * 0.5f * (maxM - minM);
      const glm::vec3 halfU = 0.5f * u * (maxM - minM), halfV = 0.5f * v * (maxM - minM);
      const glm::vec3 corners[4] = {centreM - halfU - halfV, centreM + halfU - halfV, centreM + halfU + halfV,
                                    centreM - halfU + halfV};
      for (int index : {0, 1, 2, 0, 2, 3}) vertices.push_back({corners[index], normal});
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
    glm::dvec3 minM = collider.shape == ColliderShape::Sphere ? collider.centerM - collider.radiusM : collider.minM;
    glm::dvec3 maxM = collider.shape == ColliderShape::Sphere ? collider.centerM + collider.radiusM : collider.maxM;
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
