#pragma once
// Meshes made in code for the voxelizer's tests and benchmarks: a UV sphere and a torus, faces counter-clockwise
// seen from outside.
#include <cmath>

#include <glm/vec3.hpp>

#include "voxelizer/Mesh.h"

namespace firn::test {

// Rings of constant latitude between the poles. Every vertex lies on the sphere, so the polyhedron lies inside it.
// 2 · segments · (rings − 1) triangles.
inline voxelizer::TriangleMesh uvSphere(double radiusM, unsigned rings, unsigned segments) {
  constexpr double pi = 3.14159265358979323846;
  voxelizer::TriangleMesh mesh;
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
