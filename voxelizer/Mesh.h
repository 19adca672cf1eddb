#pragma once
// Triangle meshes to fill with particles: loading them (assimp), placing them in the scene, measuring them.
#include <filesystem>
#include <stdexcept>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace firn::voxelizer {

// A mesh file that cannot be used: missing, not a regular file, unreadable, or without triangles. The message
// reads "<file>: <problem>"; the engine reports it as bad input.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Triangles index `vertices`; their order (counter-clockwise seen from outside for an outward surface) is kept
// as the file gives it, because the winding number reads orientation from it.
struct TriangleMesh {
  std::vector<glm::dvec3> vertices;
  std::vector<glm::uvec3> triangles;
};

// Loads anything assimp reads (OBJ, PLY, STL, glTF/GLB, ...): every mesh of the file's node hierarchy with the
// node transforms applied, polygons triangulated. No normal fixing and no face removal: the winding number must
// see the faces as the file gives them. Throws MeshError naming the file and the problem.
TriangleMesh loadMesh(const std::filesystem::path& path);

// p' = translateM + R · (scale · p), with R = Rz · Ry · Rx: rotate about x first, then y, then z.
struct Transform {
  double scale = 1;
  glm::dvec3 rotateDeg{0.0};
  glm::dvec3 translateM{0.0};
};

glm::dmat3 rotationMatrix(const glm::dvec3& rotateDeg);
TriangleMesh transformed(const TriangleMesh& mesh, const Transform& transform);

struct Bounds {
  glm::dvec3 minM;
  glm::dvec3 maxM;
};

// The box around all vertices; the mesh must have at least one.
Bounds bounds(const TriangleMesh& mesh);

// Σ v0 · (v1 × v2) / 6 over the triangles (divergence theorem): the enclosed volume for a closed, outward
// mesh, negative for an inverted one. For reporting.
double signedVolume(const TriangleMesh& mesh);

}  // namespace firn::voxelizer
