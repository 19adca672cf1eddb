#pragma once
// What the renderer draws besides particles, as plain data: the colliders' and rigid bodies' meshes with their
// normals, the planes' finite quads, the ground, the domain's edges, and the extents the camera frames. No GL here.
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/Scene.h"
#include "scene/SceneObjects.h"

namespace firn::render {

// Vertex of a collider's or rigid body's surface (shaders/render/surface.vert).
struct SurfaceVertex {
  glm::vec3 positionM;
  glm::vec3 normal;
  glm::vec2 planeCoordinatesM{0.0f};  // planes: position in the quad's frame from its centre
};
static_assert(sizeof(SurfaceVertex) == 32, "SurfaceVertex is tightly packed for glVertexAttribPointer");

// An axis-aligned box, in metres.
struct Bounds {
  glm::dvec3 minM;
  glm::dvec3 maxM;
  glm::dvec3 centerM() const { return 0.5 * (minM + maxM); }
};

// A plane drawn as a finite square: (tangentU, tangentV, normal) is right-handed.
struct PlaneQuad {
  glm::vec3 centerM;
  glm::vec3 normal;
  glm::vec3 tangentU;
  glm::vec3 tangentV;
  float halfSizeM;
};

// The quad of a plane: centred on the domain centre's projection onto it, with a side twice the domain's
// largest extent, so that it reaches well past the domain, where it fades into the sky.
PlaneQuad planeQuad(const Scene& scene, const glm::dvec3& pointM, const glm::dvec3& normal);
// Whether a plane passes through the domain (planes wholly outside it are not drawn).
bool planeCutsDomain(const Scene& scene, const glm::dvec3& pointM, const glm::dvec3& normal);

// The plane shadows fall on: the first plane collider that cuts the domain with a normal within ~25° of +y
// (colliderIndex ≥ 0), else the floor of the domain's interior, where the walls stop the snow (−1).
struct Ground {
  PlaneQuad quad;
  glm::vec3 velocityMPerS{0.0f};
  int colliderIndex = -1;
};
Ground findGround(const Scene& scene);

// Two triangles, counter-clockwise seen from the plane's normal side.
std::vector<SurfaceVertex> quadTriangles(const PlaneQuad& quad);
// An object's mesh (SceneObjects.h: a sphere's, a box's, a file's) in its own frame, three corners per triangle, in
// its winding. Each corner's normal is the area-weighted mean of the faces at that point (vertices at the same place
// count as one) that turn from this face by less than kCreaseAngleDeg, so that a tessellated sphere shades round
// while a box's or a model's sharp edges stay sharp; the normals point to the side the winding makes the front (the
// renderer lights back faces from behind).
std::vector<SurfaceVertex> objectTriangles(const SceneObject& object);
constexpr double kCreaseAngleDeg = 40;
// The 12 edges of a box as 24 line end points.
std::vector<glm::vec3> boxEdges(const glm::vec3& minM, const glm::vec3& maxM);

// Side of the planes' checkerboard cells: a power of ten, about a quarter of the domain's largest extent
// or less, so that a metre-sized domain gets 10 cm cells.
float checkerCellM(const Scene& scene);

// The region a default camera frames: the snow and what it touches, not the empty domain. That is each body's
// bounds swept along its free flight x₀ + v t + ½ g t² over the scene's frames, clamped to the domain's interior
// where the walls stop it (a first guess at where the snow goes, computed without simulating); the sphere, box and
// mesh colliders that sweep reaches; and the ground under it, the sweep's corners dropped onto each plane collider it
// reaches.
// Without bodies, the whole domain.
Bounds usedRegion(const Scene& scene);
// Radius around the domain centre that holds everything drawn during the scene's frames: the domain, the
// plane quads, and colliders as far as they travel.
double drawnRadiusM(const Scene& scene);

}  // namespace firn::render
