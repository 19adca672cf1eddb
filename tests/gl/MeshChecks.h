#pragma once
// What the surface tests measure of a triangle mesh: whether it is closed and consistently oriented, the volume
// it encloses, and its connected components.
#include <cstdint>
#include <istream>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "io/SurfaceMesh.h"

namespace firn::test {

// The faces of a binary PLY written by Firn (io/SurfaceMesh.h: a uchar count, 3, then three uint32 corners each),
// read from `in` after the vertices, appended to `indices`; nothing may follow them.
inline void readPlyTriangles(std::istream& in, std::size_t faces, std::vector<std::uint32_t>& indices) {
  for (std::size_t f = 0; f < faces; ++f) {
    unsigned char count = 0;
    in.read(reinterpret_cast<char*>(&count), 1);
    EXPECT_EQ(count, 3);
    std::uint32_t corners[3];
    in.read(reinterpret_cast<char*>(corners), sizeof corners);
    indices.insert(indices.end(), corners, corners + 3);
  }
  EXPECT_TRUE(in.good());
  EXPECT_EQ(in.peek(), std::char_traits<char>::eof()) << "nothing after the faces";
}

// Closed and consistently oriented: every directed edge of a triangle appears exactly once and its reverse exactly
// once, so every edge is shared by exactly two triangles, which run along it in opposite directions. Returns the
// number of directed edges that break this.
inline std::size_t edgesNotSharedByTwoOrientedTriangles(const SurfaceMesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    for (std::size_t k = 0; k < 3; ++k) ++directed[{mesh.indices[3 * t + k], mesh.indices[3 * t + (k + 1) % 3]}];
  }
  std::size_t broken = 0;
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    if (count != 1 || reverse == directed.end() || reverse->second != 1) ++broken;
  }
  return broken;
}

// The volume enclosed, by the divergence theorem (Σ a · (b × c) / 6 over counter-clockwise triangles): positive
// when the triangles face outwards.
inline double enclosedVolumeM3(const SurfaceMesh& mesh) {
  double volume = 0;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const glm::dvec3 a(mesh.positionsM[mesh.indices[3 * t]]), b(mesh.positionsM[mesh.indices[3 * t + 1]]),
        c(mesh.positionsM[mesh.indices[3 * t + 2]]);
    volume += glm::dot(a, glm::cross(b, c)) / 6;
  }
  return volume;
}

// Connected components: vertices joined by triangles (union–find).
inline std::size_t componentCount(const SurfaceMesh& mesh) {
  std::vector<std::uint32_t> parent(mesh.positionsM.size());
  std::iota(parent.begin(), parent.end(), 0u);
  const auto root = [&](std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    for (std::size_t k = 1; k < 3; ++k) parent[root(mesh.indices[3 * t + k])] = root(mesh.indices[3 * t]);
  }
  std::size_t roots = 0;
  for (std::uint32_t v = 0; v < parent.size(); ++v) roots += root(v) == v ? 1 : 0;
  return roots;
}

}  // namespace firn::test
