#include "voxelizer/Mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
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

#include "voxelizer/ProcessMemory.h"

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

bool isFinite(const glm::dvec3& point) { return std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z); }

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
      const glm::dvec3 fileM(vertex.x, vertex.y, vertex.z);
      // A vertex that is not finite is kept as the file has it, for the message: the product with the transform
      // would spread its infinity to every coordinate as NaN (0 · ∞).
      mesh.vertices.push_back(isFinite(fileM) ? glm::dvec3(nodeTransform * glm::dvec4(fileM, 1.0)) : fileM);
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

// What the child sends back: 'M', the vertex and triangle counts (u64), the vertices (3 doubles each) and the
// triangles (3 u32 each); or 'E' and assimp's error message.
constexpr char kMeshReply = 'M';
constexpr char kErrorReply = 'E';

template <class T>
void appendBytes(std::string& out, const T* data, std::size_t count) {
  out.append(reinterpret_cast<const char*>(data), count * sizeof(T));
}

// Runs in the child process: assimp's import of `path`, as bytes.
std::string importInThisProcess(const std::filesystem::path& path) {
  Assimp::Importer importer;
  // Only triangulation and vertex welding: face removal or normal fixing would change what the winding
  // number sees.
  const aiScene* scene = importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices);
  if (scene == nullptr || scene->mRootNode == nullptr) return kErrorReply + std::string(importer.GetErrorString());
  TriangleMesh mesh;
  appendNode(*scene, *scene->mRootNode, glm::dmat4(1.0), mesh);
  std::string reply(1, kMeshReply);
  const std::uint64_t counts[2] = {mesh.vertices.size(), mesh.triangles.size()};
  appendBytes(reply, counts, 2);
  appendBytes(reply, mesh.vertices.data(), mesh.vertices.size());
  appendBytes(reply, mesh.triangles.data(), mesh.triangles.size());
  return reply;
}

TriangleMesh parseReply(const std::filesystem::path& path, const std::string& reply) {
  if (!reply.empty() && reply[0] == kErrorReply) fail(path, "cannot read mesh (" + reply.substr(1) + ")");
  std::uint64_t counts[2] = {0, 0};
  constexpr std::size_t headerBytes = 1 + sizeof counts;
  if (reply.size() < headerBytes || reply[0] != kMeshReply) fail(path, "the importer's reply was cut short");
  std::memcpy(counts, reply.data() + 1, sizeof counts);
  const std::uint64_t vertexBytes = counts[0] * sizeof(glm::dvec3), triangleBytes = counts[1] * sizeof(glm::uvec3);
  if (counts[0] > reply.size() || counts[1] > reply.size() || reply.size() != headerBytes + vertexBytes + triangleBytes) {
    fail(path, "the importer's reply was cut short");
  }
  TriangleMesh mesh;
  mesh.vertices.resize(counts[0]);
  mesh.triangles.resize(counts[1]);
  std::memcpy(mesh.vertices.data(), reply.data() + headerBytes, vertexBytes);
  std::memcpy(mesh.triangles.data(), reply.data() + headerBytes + vertexBytes, triangleBytes);
  return mesh;
}

std::string describePoint(const glm::dvec3& pointM) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", pointM.x, pointM.y, pointM.z);
  return text;
}


// The triangles must index the vertices and every vertex they use must be finite; the vertices no triangle uses
// are dropped, so that a stray vertex does not stretch the mesh's box.
void checkAndCompact(const std::filesystem::path& path, TriangleMesh& mesh) {
  if (mesh.triangles.empty()) fail(path, "the file holds no triangles");
  const auto vertexCount = static_cast<unsigned>(mesh.vertices.size());
  std::vector<unsigned> newIndex(mesh.vertices.size(), std::numeric_limits<unsigned>::max());
  for (const glm::uvec3& triangle : mesh.triangles) {
    for (int corner = 0; corner < 3; ++corner) {
      if (triangle[corner] >= vertexCount) {
        fail(path, "a triangle refers to vertex " + std::to_string(triangle[corner]) + " of " +
                       std::to_string(vertexCount));
      }
      newIndex[triangle[corner]] = 0;
    }
  }
  std::vector<glm::dvec3> used;
  std::size_t notFinite = 0;
  glm::dvec3 firstNotFinite(0.0);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (newIndex[v] != 0) continue;
    if (!isFinite(mesh.vertices[v]) && notFinite++ == 0) firstNotFinite = mesh.vertices[v];
    newIndex[v] = static_cast<unsigned>(used.size());
    used.push_back(mesh.vertices[v]);
  }
  if (notFinite > 0) {
    fail(path, std::to_string(notFinite) + " of its vertices " + (notFinite == 1 ? "has" : "have") +
                   " a coordinate that is not finite (the first: " + describePoint(firstNotFinite) + ")");
  }
  for (glm::uvec3& triangle : mesh.triangles) triangle = {newIndex[triangle.x], newIndex[triangle.y], newIndex[triangle.z]};
  mesh.vertices = std::move(used);
}

}  // namespace

ChildLimits importLimits(std::uint64_t fileBytes) {
  // Measured (docs/platform.md, Importing meshes): the whole of `firn voxelize` peaked at 16, 20 and 13 times the
  // file's size for a million-triangle OBJ, binary PLY and binary STL (38, 19 and 50 MB), and read them at about
  // 10 MB/s. The importer gets 64 times the file's size (room for compressed formats) over a base for small
  // files, and a second per MB, ten times what it needed, over a base for a loaded machine.
  constexpr std::uint64_t baseBytes = std::uint64_t{256} << 20;
  constexpr std::uint64_t bytesPerFileByte = 64;
  constexpr double baseS = 10;
  constexpr double secondsPerFileByte = 1e-6;
  ChildLimits limits;
  const std::uint64_t wanted = baseBytes + bytesPerFileByte * std::min<std::uint64_t>(fileBytes, std::uint64_t{1} << 50);
  limits.memoryBytes = std::min(wanted, allocatableBytes());
  limits.wallS = baseS + secondsPerFileByte * double(fileBytes);
  limits.cpuS = limits.wallS;
  return limits;
}

TriangleMesh loadMesh(const std::filesystem::path& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) fail(path, "no such mesh file");
  if (std::filesystem::is_directory(status)) fail(path, "is a folder, not a mesh file");
  // A device or pipe (/dev/zero) could be read for ever.
  if (!std::filesystem::is_regular_file(status)) fail(path, "is not a regular file (a device, pipe or socket)");
  const std::uintmax_t fileBytes = std::filesystem::file_size(path, error);
  if (error) fail(path, "cannot read mesh (" + error.message() + ")");
  const ChildLimits limits = importLimits(fileBytes);
  const ChildOutcome outcome = runInChildProcess([&] { return importInThisProcess(path); }, limits);
  if (!outcome.succeeded) {
    throw MeshError("the importer failed on " + path.string() + ": it " + outcome.failure +
                    (outcome.lastWords.empty() ? std::string() : " (\"" + outcome.lastWords + "\")"));
  }
  TriangleMesh mesh = parseReply(path, outcome.result);
  checkAndCompact(path, mesh);
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
  const Bounds box = bounds(mesh);
  const glm::dvec3 centerM = 0.5 * (box.minM + box.maxM);
  double sixTimesVolume = 0;
  for (const glm::uvec3& triangle : mesh.triangles) {
    sixTimesVolume += glm::dot(mesh.vertices[triangle.x] - centerM,
                               glm::cross(mesh.vertices[triangle.y] - centerM, mesh.vertices[triangle.z] - centerM));
  }
  return sixTimesVolume / 6;
}

std::vector<std::uint32_t> weldByPosition(const TriangleMesh& mesh) {
  std::vector<std::uint32_t> byPosition(mesh.vertices.size());
  for (std::size_t v = 0; v < byPosition.size(); ++v) byPosition[v] = std::uint32_t(v);
  const auto lexicographic = [&](std::uint32_t first, std::uint32_t second) {
    const glm::dvec3& a = mesh.vertices[first];
    const glm::dvec3& b = mesh.vertices[second];
    return a.x != b.x ? a.x < b.x : (a.y != b.y ? a.y < b.y : (a.z != b.z ? a.z < b.z : first < second));
  };
  std::sort(byPosition.begin(), byPosition.end(), lexicographic);
  std::vector<std::uint32_t> welded(mesh.vertices.size());
  std::uint32_t number = 0;
  for (std::size_t rank = 0; rank < byPosition.size(); ++rank) {
    if (rank > 0 && mesh.vertices[byPosition[rank]] != mesh.vertices[byPosition[rank - 1]]) ++number;
    welded[byPosition[rank]] = number;
  }
  return welded;
}

MeshSurface measureSurface(const TriangleMesh& mesh) {
  MeshSurface surface;
  // Vertices welded by position, so that a vertex split for its normals or texture coordinates (or an STL's
  // corners, one per triangle) does not leave a seam that looks like a hole.
  const std::vector<std::uint32_t> weld = weldByPosition(mesh);
  // An edge of a closed surface is shared by an even number of triangles (two, for a manifold); of a consistently
  // oriented one, by as many triangles that run along it one way as the other. Each edge is held as its two welded
  // vertices in order, and the lowest bit says which way the triangle ran.
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * mesh.triangles.size());
  double largestAreaM2 = -1;
  glm::dvec3 planePointM(0.0), planeNormal(0.0);
  for (const glm::uvec3& triangle : mesh.triangles) {
    for (int corner = 0; corner < 3; ++corner) {
      const std::uint64_t a = weld[triangle[corner]], b = weld[triangle[(corner + 1) % 3]];
      if (a != b) edges.push_back((std::min(a, b) << 32 | std::max(a, b)) << 1 | (a < b ? 1 : 0));
    }
    const glm::dvec3& a = mesh.vertices[triangle.x];
    const glm::dvec3 areaNormal = glm::cross(mesh.vertices[triangle.y] - a, mesh.vertices[triangle.z] - a);
    const double areaM2 = 0.5 * glm::length(areaNormal);
    surface.areaM2 += areaM2;
    if (areaM2 > largestAreaM2) {
      largestAreaM2 = areaM2;
      planePointM = a;
      planeNormal = areaM2 > 0 ? glm::normalize(areaNormal) : glm::dvec3(0.0);
    }
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t first = 0, next = 0; first < edges.size(); first = next) {
    std::size_t forward = 0;
    for (; next < edges.size() && edges[next] >> 1 == edges[first] >> 1; ++next) forward += edges[next] & 1;
    const std::size_t uses = next - first;
    if (uses % 2 == 1) {
      ++surface.boundaryEdges;
    } else if (2 * forward != uses) {
      ++surface.misorientedEdges;
    }
  }
  // With every triangle of zero area there is no plane, and the mesh is as flat as can be.
  if (planeNormal != glm::dvec3(0.0)) {
    for (const glm::dvec3& vertexM : mesh.vertices) {
      surface.thicknessM = std::max(surface.thicknessM, std::abs(glm::dot(vertexM - planePointM, planeNormal)));
    }
  }
  return surface;
}

std::string whyNotFillable(const TriangleMesh& mesh, const MeshSurface& surface, double spacingM) {
  const Bounds box = bounds(mesh);
  if (!isFinite(box.minM) || !isFinite(box.maxM)) {
    return "placing the mesh (scale, rotation, translation) takes a vertex beyond the range of a double";
  }
  // Positions live in 32-bit floats on the GPU and in the PLY files; far enough from the origin, neighbouring
  // floats are further apart than the particles, which would pile onto them.
  const glm::dvec3 reachM = glm::max(glm::abs(box.minM), glm::abs(box.maxM));
  const double farthestM = std::max({reachM.x, reachM.y, reachM.z});
  const auto farthest = static_cast<float>(farthestM);
  const double floatGapM = double(std::nextafter(farthest, std::numeric_limits<float>::infinity()) - farthest);
  constexpr double floatGapPerSpacing = 0.1;
  if (floatGapM > floatGapPerSpacing * spacingM) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "the mesh reaches %.4g m from the origin, where 32-bit floats (the GPU's and the PLY's positions) "
                  "are %.3g m apart, more than a tenth of the spacing %.3g m; move it nearer the origin",
                  farthestM, floatGapM, spacingM);
    return text;
  }
  // A mesh is flat when its thickness is at the level of the rounding of its coordinates (files hold floats):
  // a millionth of its size, and a few float steps where it lies.
  constexpr double flatThicknessPerSize = 1e-6;
  constexpr double flatThicknessFloatGaps = 4;
  const double flatThicknessM = flatThicknessPerSize * glm::length(box.maxM - box.minM) + flatThicknessFloatGaps * floatGapM;
  if (surface.thicknessM <= flatThicknessM) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "the mesh is flat (its vertices lie within %.3g m of one plane), so it encloses no volume: a body, a "
                  "mesh collider and a rigid body each need a solid; give the sheet a thickness",
                  surface.thicknessM);
    return text;
  }
  return "";
}

TriangleMesh uvSphere(double radiusM, unsigned rings, unsigned segments) {
  constexpr double pi = 3.14159265358979323846;
  TriangleMesh mesh;
  mesh.vertices.emplace_back(0, 0, radiusM);
  for (unsigned ring = 1; ring < rings; ++ring) {
    const double polarRad = pi * ring / rings;
    for (unsigned segment = 0; segment < segments; ++segment) {
      const double azimuthRad = 2 * pi * segment / segments;
      mesh.vertices.push_back(radiusM * glm::dvec3(std::sin(polarRad) * std::cos(azimuthRad),
                                                   std::sin(polarRad) * std::sin(azimuthRad), std::cos(polarRad)));
    }
  }
  mesh.vertices.emplace_back(0, 0, -radiusM);
  const auto southPole = static_cast<unsigned>(mesh.vertices.size() - 1);
  auto vertex = [&](unsigned ring, unsigned segment) { return 1 + (ring - 1) * segments + segment % segments; };
  for (unsigned segment = 0; segment < segments; ++segment) {
    mesh.triangles.emplace_back(0, vertex(1, segment), vertex(1, segment + 1));
    for (unsigned ring = 1; ring + 1 < rings; ++ring) {
      mesh.triangles.emplace_back(vertex(ring, segment), vertex(ring + 1, segment), vertex(ring + 1, segment + 1));
      mesh.triangles.emplace_back(vertex(ring, segment), vertex(ring + 1, segment + 1), vertex(ring, segment + 1));
    }
    mesh.triangles.emplace_back(vertex(rings - 1, segment), southPole, vertex(rings - 1, segment + 1));
  }
  return mesh;
}

TriangleMesh boxMesh(const glm::dvec3& minM, const glm::dvec3& maxM) {
  TriangleMesh mesh;
  for (int corner = 0; corner < 8; ++corner) {
    mesh.vertices.emplace_back(corner & 1 ? maxM.x : minM.x, corner & 2 ? maxM.y : minM.y, corner & 4 ? maxM.z : minM.z);
  }
  // Faces −x, +x, −y, +y, −z, +z as corner quads wound counter-clockwise from outside.
  const unsigned faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& face : faces) {
    mesh.triangles.emplace_back(face[0], face[1], face[2]);
    mesh.triangles.emplace_back(face[0], face[2], face[3]);
  }
  return mesh;
}

}  // namespace firn::voxelizer
