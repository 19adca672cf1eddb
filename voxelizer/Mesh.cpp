#include "voxelizer/Mesh.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <system_error>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/trigonometric.hpp>

namespace firn::voxelizer {
namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& problem) {
  throw MeshError(path.string() + ": " + problem);
}

// assimp's matrices are row-major (a1 a2 a3 a4 is the first row); glm's are column-major.
glm::dmat4 toGlm(const aiMatrix4x4& matrix) {
  glm::dmat4 result;
  for (int row = 0; row < 4; ++row) {
    for (int column = 0; column < 4; ++column) result[column][row] = matrix[row][column];
  }
  return result;
}

// Appends the meshes that `node` and its descendants place, each with its node's transform composed with its
// ancestors'. A mesh placed by several nodes is appended once per placement.
void appendNode(const aiScene& scene, const aiNode& node, const glm::dmat4& parentTransform, TriangleMesh& mesh) {
  const glm::dmat4 nodeTransform = parentTransform * toGlm(node.mTransformation);
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    const aiMesh& part = *scene.mMeshes[node.mMeshes[m]];
    if ((part.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) continue;  // points or lines only
    const auto firstVertex = static_cast<unsigned>(mesh.vertices.size());
    for (unsigned v = 0; v < part.mNumVertices; ++v) {
      const aiVector3D& vertex = part.mVertices[v];
      mesh.vertices.emplace_back(nodeTransform * glm::dvec4(vertex.x, vertex.y, vertex.z, 1.0));
    }
    for (unsigned f = 0; f < part.mNumFaces; ++f) {
      const aiFace& face = part.mFaces[f];
      if (face.mNumIndices != 3) continue;  // a point or line in a mixed mesh
      mesh.triangles.emplace_back(firstVertex + face.mIndices[0], firstVertex + face.mIndices[1],
                                  firstVertex + face.mIndices[2]);
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) appendNode(scene, *node.mChildren[c], nodeTransform, mesh);
}

}  // namespace

TriangleMesh loadMesh(const std::filesystem::path& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) fail(path, "no such mesh file");
  if (std::filesystem::is_directory(status)) fail(path, "is a folder, not a mesh file");
  // A device or pipe (/dev/zero) could be read for ever.
  if (!std::filesystem::is_regular_file(status)) fail(path, "is not a regular file (a device, pipe or socket)");
  Assimp::Importer importer;
  // Only triangulation and vertex welding: face removal or normal fixing would change what the winding
  // number sees.
  const aiScene* scene = importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices);
  if (scene == nullptr || scene->mRootNode == nullptr) {
    fail(path, std::string("cannot read mesh (") + importer.GetErrorString() + ")");
  }
  TriangleMesh mesh;
  appendNode(*scene, *scene->mRootNode, glm::dmat4(1.0), mesh);
  if (mesh.triangles.empty()) fail(path, "the file holds no triangles");
  return mesh;
}

glm::dmat3 rotationMatrix(const glm::dvec3& rotateDeg) {
  const glm::dvec3 angleRad = glm::radians(rotateDeg);
  const double cx = std::cos(angleRad.x), sx = std::sin(angleRad.x);
  const double cy = std::cos(angleRad.y), sy = std::sin(angleRad.y);
  const double cz = std::cos(angleRad.z), sz = std::sin(angleRad.z);
  // Right-handed rotations about each axis, written column by column.
  const glm::dmat3 rotateX(1, 0, 0, 0, cx, sx, 0, -sx, cx);
  const glm::dmat3 rotateY(cy, 0, -sy, 0, 1, 0, sy, 0, cy);
  const glm::dmat3 rotateZ(cz, sz, 0, -sz, cz, 0, 0, 0, 1);
  return rotateZ * rotateY * rotateX;
}

TriangleMesh transformed(const TriangleMesh& mesh, const Transform& transform) {
  const glm::dmat3 rotation = rotationMatrix(transform.rotateDeg);
  TriangleMesh result = mesh;
  for (glm::dvec3& vertexM : result.vertices) vertexM = transform.translateM + rotation * (transform.scale * vertexM);
  return result;
}

Bounds bounds(const TriangleMesh& mesh) {
  if (mesh.vertices.empty()) throw std::invalid_argument("bounds: the mesh has no vertices");
  Bounds box{mesh.vertices.front(), mesh.vertices.front()};
  for (const glm::dvec3& vertexM : mesh.vertices) {
    box.minM = glm::min(box.minM, vertexM);
    box.maxM = glm::max(box.maxM, vertexM);
  }
  return box;
}

double signedVolume(const TriangleMesh& mesh) {
  double sixTimesVolume = 0;
  for (const glm::uvec3& triangle : mesh.triangles) {
    sixTimesVolume += glm::dot(mesh.vertices[triangle.x],
                               glm::cross(mesh.vertices[triangle.y], mesh.vertices[triangle.z]));
  }
  return sixTimesVolume / 6;
}

}  // namespace firn::voxelizer
