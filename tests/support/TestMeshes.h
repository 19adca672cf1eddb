#pragma once
// Meshes made in code for the voxelizer's tests and benchmarks: a UV sphere and a torus, faces counter-clockwise
// seen from outside.
#include <cmath>

#include <glm/vec3.hpp>

#include "voxelizer/Mesh.h"

namespace firn::test {

using voxelizer::uvSphere;  // voxelizer/Mesh.h: the engine draws and benchmarks with it too

// The torus about the z axis with ring radius R and tube radius r: u around the ring, v around the tube.
// 2 · ringSegments · tubeSegments triangles.
inline voxelizer::TriangleMesh torus(double ringRadiusM, double tubeRadiusM, unsigned ringSegments,
                                     unsigned tubeSegments) {
  constexpr double pi = 3.14159265358979323846;
  voxelizer::TriangleMesh mesh;
  for (unsigned u = 0; u < ringSegments; ++u) {
    for (unsigned v = 0; v < tubeSegments; ++v) {
      const double ringRad = 2 * pi * u / ringSegments;
      const double tubeRad = 2 * pi * v / tubeSegments;
      const double axisDistanceM = ringRadiusM + tubeRadiusM * std::cos(tubeRad);
      mesh.vertices.emplace_back(axisDistanceM * std::cos(ringRad), axisDistanceM * std::sin(ringRad),
                                 tubeRadiusM * std::sin(tubeRad));
    }
  }
  auto vertex = [&](unsigned u, unsigned v) { return u % ringSegments * tubeSegments + v % tubeSegments; };
  for (unsigned u = 0; u < ringSegments; ++u) {
    for (unsigned v = 0; v < tubeSegments; ++v) {
      mesh.triangles.emplace_back(vertex(u, v), vertex(u + 1, v), vertex(u + 1, v + 1));
      mesh.triangles.emplace_back(vertex(u, v), vertex(u + 1, v + 1), vertex(u, v + 1));
    }
  }
  return mesh;
}

}  // namespace firn::test
