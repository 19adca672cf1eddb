#pragma once
// Triangle meshes as files: the snow's surface, with normals, and the scene's moving objects posed at a frame
// (writeMeshPly), binary PLY for Blender, Houdini and anything else that reads PLY.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace firn {

// An indexed triangle mesh: vertices shared between triangles, three indices per triangle, counter-clockwise
// seen from outside.
struct SurfaceMesh {
  std::vector<glm::vec3> positionsM;
  std::vector<glm::vec3> normals;  // unit, outward, or none (an object's flat faces: the reader shades them)
  std::vector<glm::vec3> velocitiesMPerS;  // the snow's velocity at each vertex (m/s), or none
  std::vector<std::uint32_t> indices;
  std::size_t triangleCount() const { return indices.size() / 3; }
};

// Binary little-endian PLY: `element vertex` with float x y z (nx ny nz when the mesh has normals, vx vy vz when it
// has velocities), `element face` with a list of uchar count and uint vertex_indices; `description` follows
// "comment written by Firn: " in the header. Written through a temporary file and a rename (io/AtomicFile.h): a
// disk that fills is an InputError naming the file, and no partial file is left. A non-finite value, an index past
// the vertices, a ragged index list, or normals or velocities not one per vertex is std::invalid_argument (a
// defect, never written).
void writeMeshPly(const std::filesystem::path& path, const SurfaceMesh& mesh,
                  const std::string& description = "the snow's surface");

}  // namespace firn
