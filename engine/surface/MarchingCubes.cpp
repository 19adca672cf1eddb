#include "surface/MarchingCubes.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "surface/SurfaceLayout.h"

namespace firn::surface {

namespace {

constexpr int kNoEdge = -1;

glm::vec3 edgeMidpoint(int edge) {
  glm::vec3 point(gpu::edgeStart(edge));
  point[gpu::edgeAxis(edge)] = 0.5f;
  return point;
}

// Whether two edges lie on one face of the cell: an edge lies on the two faces across its axis at its start's
// other two coordinates.
bool shareFace(int a, int b) {
  const glm::ivec3 startA = gpu::edgeStart(a), startB = gpu::edgeStart(b);
  for (int axis = 0; axis < 3; ++axis) {
    if (axis != gpu::edgeAxis(a) && axis != gpu::edgeAxis(b) && startA[axis] == startB[axis]) return true;
  }
  return false;
}

int edgeEndCorner(int edge, int end) {
  glm::ivec3 corner = gpu::edgeStart(edge);
  corner[gpu::edgeAxis(edge)] = end;
  return corner.x | (corner.y << 1) | (corner.z << 2);
}

MarchingCubesCase buildCase(int insideMask) {
  const auto inside = [&](int corner) { return ((insideMask >> corner) & 1) != 0; };
  const auto crossed = [&](int edge) { return inside(edgeEndCorner(edge, 0)) != inside(edgeEndCorner(edge, 1)); };

  // next[e]: the edge the oriented segment leaving edge e's vertex goes to.
  std::array<int, 12> next;
  next.fill(kNoEdge);
  const auto addSegment = [&](int from, int to, int insideCorner, const glm::vec3& outward) {
    // Inside on the right seen from outside the cell: (to − from) × (corner − from) points into the cell.
    const glm::vec3 a = edgeMidpoint(from), b = edgeMidpoint(to);
    if (glm::dot(glm::cross(b - a, glm::vec3(gpu::cellCorner(insideCorner)) - a), outward) > 0) std::swap(from, to);
    if (next[from] != kNoEdge) throw std::logic_error("marching cubes: two segments leave one edge");
    next[from] = to;
  };

  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      glm::vec3 outward(0.0f);
      outward[axis] = side == 0 ? -1.0f : 1.0f;
      std::vector<int> faceCorners, faceEdges;
      for (int corner = 0; corner < 8; ++corner) {
        if (gpu::cellCorner(corner)[axis] == side) faceCorners.push_back(corner);
      }
      for (int edge = 0; edge < 12; ++edge) {
        if (gpu::edgeAxis(edge) != axis && gpu::edgeStart(edge)[axis] == side && crossed(edge)) {
          faceEdges.push_back(edge);
        }
      }
      const auto insideCorner = std::find_if(faceCorners.begin(), faceCorners.end(), inside);
      if (faceEdges.size() == 2) {
        addSegment(faceEdges[0], faceEdges[1], *insideCorner, outward);
      } else if (faceEdges.size() == 4) {
        // The ambiguous face: each inside corner is cut off between its two edges on this face.
        for (const int corner : faceCorners) {
          if (!inside(corner)) continue;
          int ends[2], found = 0;
          for (const int edge : faceEdges) {
            if (edgeEndCorner(edge, 0) == corner || edgeEndCorner(edge, 1) == corner) ends[found++] = edge;
          }
          addSegment(ends[0], ends[1], corner, outward);
        }
      }
    }
  }

  MarchingCubesCase result;
  std::array<bool, 12> visited{};
  for (int start = 0; start < 12; ++start) {
    if (!crossed(start) || visited[start]) continue;
    std::vector<int> loop;
    for (int edge = start; !visited[edge]; edge = next[edge]) {
      if (next[edge] == kNoEdge) throw std::logic_error("marching cubes: a loop does not close");
      visited[edge] = true;
      loop.push_back(edge);
    }
    // A fan from an apex none of whose diagonals lies on a face: a diagonal between two vertices of one face
    // (the ambiguous face's loops pass it twice) could be drawn by the neighbouring cell too, and an edge of the
    // mesh would belong to four triangles.
    const std::size_t n = loop.size();
    std::size_t apex = 0;
    const auto diagonalsInside = [&](std::size_t a) {
      for (std::size_t i = 2; i + 1 < n; ++i) {
        if (shareFace(loop[a], loop[(a + i) % n])) return false;
      }
      return true;
    };
    while (apex < n && !diagonalsInside(apex)) ++apex;
    if (apex == n) throw std::logic_error("marching cubes: no fan of a loop keeps its diagonals off the faces");
    for (std::size_t i = 1; i + 1 < n; ++i) {
      if (result.triangleCount == gpu::MAX_CELL_TRIANGLES) throw std::logic_error("marching cubes: too many triangles");
      std::uint8_t* triangle = &result.edges[std::size_t(3 * result.triangleCount++)];
      triangle[0] = std::uint8_t(loop[apex]);
      triangle[1] = std::uint8_t(loop[(apex + i) % n]);
      triangle[2] = std::uint8_t(loop[(apex + i + 1) % n]);
    }
  }
  return result;
}

}  // namespace

const std::array<MarchingCubesCase, 256>& marchingCubesCases() {
  static const std::array<MarchingCubesCase, 256> cases = [] {
    std::array<MarchingCubesCase, 256> table;
    for (int mask = 0; mask < 256; ++mask) table[std::size_t(mask)] = buildCase(mask);
    return table;
  }();
  return cases;
}

std::vector<glm::uvec4> packedMarchingCubesCases() {
  std::vector<glm::uvec4> packed;
  for (const MarchingCubesCase& cell : marchingCubesCases()) {
    glm::uvec4 entry(std::uint32_t(cell.triangleCount), 0u, 0u, 0u);
    for (int i = 0; i < 3 * cell.triangleCount; ++i) entry[1 + i / 8] |= std::uint32_t(cell.edges[std::size_t(i)]) << (4 * (i % 8));
    packed.push_back(entry);
  }
  return packed;
}

}  // namespace firn::surface
