#include "io/SurfaceMesh.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "io/AtomicFile.h"

namespace firn {

namespace {

template <class T>
void appendLittleEndian(std::string& out, T value) {
  static_assert(sizeof(T) == 4, "PLY's float and uint are 4 bytes");
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  for (int byte = 0; byte < 4; ++byte) out.push_back(static_cast<char>((bits >> (8 * byte)) & 0xFFu));
}

}  // namespace

void writeMeshPly(const std::filesystem::path& path, const SurfaceMesh& mesh, const std::string& description) {
  const std::size_t vertices = mesh.positionsM.size();
  const bool withNormals = !mesh.normals.empty();
  if (withNormals && mesh.normals.size() != vertices) {
    throw std::invalid_argument("writeMeshPly: positions and normals differ in count");
  }
  if (mesh.indices.size() % 3 != 0) throw std::invalid_argument("writeMeshPly: indices are not triangles");
  const bool withVelocities = !mesh.velocitiesMPerS.empty();
  if (withVelocities && mesh.velocitiesMPerS.size() != vertices) {
    throw std::invalid_argument("writeMeshPly: positions and velocities differ in count");
  }
  std::string data = "ply\nformat binary_little_endian 1.0\ncomment written by Firn: " + description + "\n"
                     "element vertex " + std::to_string(vertices) + "\n"
                     "property float x\nproperty float y\nproperty float z\n" +
                     std::string(withNormals ? "property float nx\nproperty float ny\nproperty float nz\n" : "") +
                     std::string(withVelocities ? "property float vx\nproperty float vy\nproperty float vz\n" : "") +
                     "element face " + std::to_string(mesh.triangleCount()) + "\n"
                     "property list uchar uint vertex_indices\nend_header\n";
  data.reserve(data.size() + vertices * (12 + (withNormals ? 12 : 0) + (withVelocities ? 12 : 0)) +
               mesh.triangleCount() * 13);
  const auto append = [&](std::size_t i, const glm::vec3& vector) {
    for (int axis = 0; axis < 3; ++axis) {
      if (!std::isfinite(vector[axis])) throw std::invalid_argument("writeMeshPly: vertex " + std::to_string(i) + " is not finite");
      appendLittleEndian(data, vector[axis]);
    }
  };
  for (std::size_t i = 0; i < vertices; ++i) {
    append(i, mesh.positionsM[i]);
    if (withNormals) append(i, mesh.normals[i]);
    if (withVelocities) append(i, mesh.velocitiesMPerS[i]);
  }
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    data.push_back(3);
    for (int corner = 0; corner < 3; ++corner) {
      const std::uint32_t index = mesh.indices[3 * t + std::size_t(corner)];
      if (index >= vertices) throw std::invalid_argument("writeMeshPly: triangle " + std::to_string(t) + " names no vertex");
      appendLittleEndian(data, index);
    }
  }
  writeFileAtomically(path, data, "surface mesh");
}

}  // namespace firn
