// The marching-cubes table (engine/surface/MarchingCubes.h), checked by using it: fields on a small grid are
// meshed on the CPU exactly as shaders/surface/classify_cells.comp and emit_mesh.comp do (a vertex per crossed
// edge, owned by the edge's first node; triangles naming them), and every mesh must be closed and oriented.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "surface/MarchingCubes.h"
#include "surface/SurfaceLayout.h"

namespace {

using firn::surface::MarchingCubesCase;
using firn::surface::marchingCubesCases;

struct Mesh {
  std::vector<glm::dvec3> positions;
  std::vector<std::uint32_t> indices;
};

// Marching cubes over values on n³ nodes of spacing 1, inside where value ≥ iso.
Mesh meshField(const std::vector<double>& values, int n, double iso) {
  const auto at = [&](glm::ivec3 p) { return values[std::size_t(p.x + n * (p.y + n * p.z))]; };
  const auto inside = [&](glm::ivec3 p) { return at(p) >= iso; };
  Mesh mesh;
  std::map<std::pair<int, int>, std::uint32_t> vertexOfEdge;  // (node, axis) → vertex
  for (int z = 0; z < n; ++z) {
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) {
        const glm::ivec3 node(x, y, z);
        for (int axis = 0; axis < 3; ++axis) {
          glm::ivec3 next = node;
          next[axis] += 1;
          if (next[axis] >= n || inside(node) == inside(next)) continue;
          const double t = (iso - at(node)) / (at(next) - at(node));
          glm::dvec3 position(node);
          position[axis] += t;
          vertexOfEdge[{x + n * (y + n * z), axis}] = std::uint32_t(mesh.positions.size());
          mesh.positions.push_back(position);
        }
      }
    }
  }
  for (int z = 0; z + 1 < n; ++z) {
    for (int y = 0; y + 1 < n; ++y) {
      for (int x = 0; x + 1 < n; ++x) {
        const glm::ivec3 node(x, y, z);
        int mask = 0;
        for (int corner = 0; corner < 8; ++corner) {
          if (inside(node + firn::gpu::cellCorner(corner))) mask |= 1 << corner;
        }
        const MarchingCubesCase& cell = marchingCubesCases()[std::size_t(mask)];
        for (int i = 0; i < 3 * cell.triangleCount; ++i) {
          const int edge = cell.edges[std::size_t(i)];
          const glm::ivec3 owner = node + firn::gpu::edgeStart(edge);
          mesh.indices.push_back(vertexOfEdge.at({owner.x + n * (owner.y + n * owner.z), firn::gpu::edgeAxis(edge)}));
        }
      }
    }
  }
  return mesh;
}

// Closed and consistently oriented: every directed edge of a triangle appears exactly once, and its reverse
// exactly once (so every undirected edge belongs to exactly two triangles, traversed in opposite directions).
bool closedAndOriented(const Mesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
    for (int k = 0; k < 3; ++k) ++directed[{mesh.indices[t + std::size_t(k)], mesh.indices[t + std::size_t((k + 1) % 3)]}];
  }
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    const auto reverse = directed.find({edge.second, edge.first});
    if (reverse == directed.end() || reverse->second != 1) return false;
  }
  return true;
}

// The volume the mesh encloses, by the divergence theorem: Σ over triangles of a · (b × c) / 6.
double enclosedVolume(const Mesh& mesh) {
  double volume = 0;
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
    volume += glm::dot(mesh.positions[mesh.indices[t]],
                       glm::cross(mesh.positions[mesh.indices[t + 1]], mesh.positions[mesh.indices[t + 2]])) / 6;
  }
  return volume;
}

TEST(MarchingCubes, EmptyAndFullCellsHaveNoTriangles) {
  EXPECT_EQ(marchingCubesCases()[0].triangleCount, 0);
  EXPECT_EQ(marchingCubesCases()[255].triangleCount, 0);
}

// One corner inside: one triangle, its normal (counter-clockwise, right-handed) pointing away from the corner.
TEST(MarchingCubes, SingleCornerIsCutOffByOneOutwardTriangle) {
  for (int corner = 0; corner < 8; ++corner) {
    const MarchingCubesCase& cell = marchingCubesCases()[std::size_t(1 << corner)];
    ASSERT_EQ(cell.triangleCount, 1) << "corner " << corner;
    glm::dvec3 points[3];
    for (int k = 0; k < 3; ++k) {
      glm::dvec3 midpoint(firn::gpu::edgeStart(cell.edges[std::size_t(k)]));
      midpoint[firn::gpu::edgeAxis(cell.edges[std::size_t(k)])] = 0.5;
      points[k] = midpoint;
    }
    const glm::dvec3 normal = glm::cross(points[1] - points[0], points[2] - points[0]);
    EXPECT_GT(glm::dot(normal, points[0] - glm::dvec3(firn::gpu::cellCorner(corner))), 0) << "corner " << corner;
  }
}

TEST(MarchingCubes, NoCaseNeedsMoreTrianglesThanTheGpuTableHolds) {
  int most = 0;
  for (const MarchingCubesCase& cell : marchingCubesCases()) most = std::max(most, cell.triangleCount);
  EXPECT_LE(most, firn::gpu::MAX_CELL_TRIANGLES);
  // The packed table keeps every edge: unpack and compare.
  const std::vector<glm::uvec4> packed = firn::surface::packedMarchingCubesCases();
  ASSERT_EQ(packed.size(), 256u);
  for (std::size_t c = 0; c < 256; ++c) {
    ASSERT_EQ(int(packed[c].x), marchingCubesCases()[c].triangleCount);
    for (int i = 0; i < 3 * marchingCubesCases()[c].triangleCount; ++i) {
      EXPECT_EQ((packed[c][1 + i / 8] >> (4 * (i % 8))) & 0xFu, marchingCubesCases()[c].edges[std::size_t(i)]);
    }
  }
}

// Random fields exercise every case, ambiguous faces included, next to every other: 200 fields of 10³ nodes
// whose outer nodes are outside must each give a closed, consistently oriented mesh enclosing a positive volume.
TEST(MarchingCubes, RandomFieldsGiveClosedOrientedMeshes) {
  constexpr int n = 10;
  std::mt19937 random(0x4669726e);
  std::uniform_real_distribution<double> value(0.0, 1.0);
  std::vector<bool> seen(256, false);
  for (int field = 0; field < 200; ++field) {
    std::vector<double> values(n * n * n, 0.0);
    for (int z = 1; z + 1 < n; ++z) {
      for (int y = 1; y + 1 < n; ++y) {
        for (int x = 1; x + 1 < n; ++x) values[std::size_t(x + n * (y + n * z))] = value(random);
      }
    }
    const Mesh mesh = meshField(values, n, 0.5);
    ASSERT_TRUE(closedAndOriented(mesh)) << "field " << field;
    EXPECT_GT(enclosedVolume(mesh), 0) << "field " << field;
    for (int z = 0; z + 1 < n; ++z) {
      for (int y = 0; y + 1 < n; ++y) {
        for (int x = 0; x + 1 < n; ++x) {
          int mask = 0;
          for (int corner = 0; corner < 8; ++corner) {
            const glm::ivec3 p = glm::ivec3(x, y, z) + firn::gpu::cellCorner(corner);
            if (values[std::size_t(p.x + n * (p.y + n * p.z))] >= 0.5) mask |= 1 << corner;
          }
          seen[std::size_t(mask)] = true;
        }
      }
    }
  }
  int casesSeen = 0;
  for (const bool s : seen) casesSeen += s ? 1 : 0;
  EXPECT_EQ(casesSeen, 256) << "every case met at least once";
}

// A ball's field: the mesh of the iso surface of a smooth radial field encloses the ball's volume to within
// what linear interpolation between nodes loses (a few per cent at 8 cells per radius).
TEST(MarchingCubes, BallFieldEnclosesTheBallsVolume) {
  constexpr int n = 24;
  constexpr double radius = 8;
  const glm::dvec3 centre(11.3, 11.7, 12.1);
  std::vector<double> values(n * n * n);
  for (int z = 0; z < n; ++z) {
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) values[std::size_t(x + n * (y + n * z))] = radius - glm::length(glm::dvec3(x, y, z) - centre);
    }
  }
  const Mesh mesh = meshField(values, n, 0.0);
  ASSERT_TRUE(closedAndOriented(mesh));
  // Chords of a sphere of radius 8 cells cut inside it by at most 1/(8·8·2) of the radius per cell face:
  // the volume is within 1% of 4/3 π r³.
  EXPECT_NEAR(enclosedVolume(mesh) / (4.0 / 3.0 * M_PI * radius * radius * radius), 1.0, 0.01);
}

}  // namespace
