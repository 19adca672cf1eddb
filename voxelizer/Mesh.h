#pragma once
// Triangle meshes to fill with particles: loading them (assimp), placing them in the scene, measuring them.
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "voxelizer/ChildProcess.h"

namespace firn::voxelizer {

// A mesh file that cannot be used: missing, not a regular file, unreadable, without triangles, with a coordinate
// that is not finite, one the importer fails on, or a mesh that cannot be filled. The message names the file
// ("<file>: <problem>", or "the importer failed on <file>: …"); the engine reports it as bad input.
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
// see the faces as the file gives them; vertices no triangle uses are dropped.
// assimp runs in a child process (voxelizer/ChildProcess.h) held to importLimits(the file's size), so a file
// that makes it abort, crash, exhaust memory or loop ends as a MeshError here ("the importer failed on <file>:
// it was killed by signal 6 (Aborted): <what assimp said>"), within those limits. Throws MeshError naming the file
// and the problem; a vertex that is not finite is one.
TriangleMesh loadMesh(const std::filesystem::path& path);

// What the importer may use for a file of `fileBytes`: memory and time in proportion to the file, with room
// for small files, and never more memory than this process could allocate itself (docs/platform.md, Importing
// meshes).
ChildLimits importLimits(std::uint64_t fileBytes);

// p' = translateM + R · (scale · p), with R = Rz · Ry · Rx: rotate about x first, then y, then z.
struct Transform {
  double scale = 1;
  glm::dvec3 rotateDeg{0.0};
  glm::dvec3 translateM{0.0};
};

glm::dmat3 rotationMatrix(const glm::dvec3& rotateDeg);
TriangleMesh transformed(const TriangleMesh& mesh, const Transform& transform);

// A UV sphere about the origin: rings of constant latitude between the poles (on ±z), every vertex on the sphere
// (so the polyhedron lies inside it), faces counter-clockwise seen from outside; 2 · segments · (rings − 1)
// triangles. For the engine's sphere shapes, the benchmarks and the tests.
TriangleMesh uvSphere(double radiusM, unsigned rings, unsigned segments);

// The box from minM to maxM: two triangles per face, counter-clockwise seen from outside.
TriangleMesh boxMesh(const glm::dvec3& minM, const glm::dvec3& maxM);

// Each vertex's number among the mesh's distinct positions, counted from 0 in lexicographic order of position:
// vertices at the same point share one, so a mesh that repeats its corners per triangle (an STL, a seam split for
// normals or texture coordinates) is still one surface.
std::vector<std::uint32_t> weldByPosition(const TriangleMesh& mesh);

struct Bounds {
  glm::dvec3 minM;
  glm::dvec3 maxM;
};

// The box around all vertices; the mesh must have at least one.
Bounds bounds(const TriangleMesh& mesh);

// Σ (v0 − c) · ((v1 − c) × (v2 − c)) / 6 over the triangles, c the centre of the mesh's box (divergence
// theorem): the enclosed volume for a closed, outward mesh, negative for an inverted one. An open mesh encloses
// no definite volume, and its sum depends on where its holes are (c makes it at least independent of where the
// mesh is placed); MeshSurface says whether the mesh is open. For reporting.
double signedVolume(const TriangleMesh& mesh);

// What the surface is like, for reports and for the checks before filling it.
struct MeshSurface {
  double areaM2 = 0;
  // Edges (of vertices welded by position) that one triangle, or an odd number, uses: they border holes. 0 for a
  // closed mesh.
  std::size_t boundaryEdges = 0;
  // Edges that an even number of triangles share, but not as many running along it one way as the other: triangles
  // on either side of it face opposite ways (their winding disagrees). 0 for a consistently oriented closed mesh.
  std::size_t misorientedEdges = 0;
  // The farthest any vertex lies from the plane of the largest triangle: 0 (to rounding) for a flat mesh.
  double thicknessM = 0;
  bool open() const { return boundaryEdges > 0; }
};
MeshSurface measureSurface(const TriangleMesh& mesh);

// Why `mesh`, placed, cannot be filled with particles `spacingM` apart, or "" if it can: a vertex that is not
// finite (a placement that overflowed); coordinates so far from the origin that 32-bit floats, which the GPU and
// the PLY files hold positions in, are further apart there than a tenth of the spacing; or a flat mesh, which
// encloses no volume. Callers prefix the file.
std::string whyNotFillable(const TriangleMesh& mesh, const MeshSurface& surface, double spacingM);

}  // namespace firn::voxelizer
