#pragma once
// Triangle meshes of the snow's surface as files: binary PLY with normals (writeMeshPly), for Blender, Houdini
// and anything else that reads PLY.
#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/vec3.hpp>

namespace firn {

// An indexed triangle mesh: vertices shared between triangles, three indices per triangle, counter-clockwise
// seen from outside.
struct SurfaceMesh {
  std::vector<glm::vec3> positionsM;
  std::vector<glm::vec3> normals;  // unit, outward
  std::vector<glm::vec3> velocitiesMPerS;  // the snow's velocity at each vertex (m/s), or none
  std::vector<std::uint32_t> indices;
  std::size_t triangleCount() const { return indices.size() / 3; }
};

// Binary little-endian PLY: `element vertex` with float x y z nx ny nz (and vx vy vz when the mesh has
// velocities), `element face` with a list of uchar count and uint vertex_indices. Written through a temporary file and a rename (io/AtomicFile.h): a disk that fills is
// an InputError naming the file, and no partial file is left. A non-finite value, an index past the vertices, a
// ragged index list or velocities not one per vertex is std::invalid_argument (a defect, never written).
void writeMeshPly(const std::filesystem::path& path, const SurfaceMesh& mesh);

}  // namespace firn
