// The snow's surface rebuilt on the GPU (engine/surface, docs/surfaces.md) from resting bodies whose surfaces are
// known: closed, oriented, where the body is and of its volume.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "Error.h"
#include "GlTest.h"
#include "MeshChecks.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"
#include "surface/SurfaceReconstruction.h"

namespace {

using firn::Scene;
using firn::Simulation;
using firn::SurfaceMesh;
using firn::surface::SurfaceReconstruction;

// A 0.8 m domain of 32³ cells of h = 2.5 cm; spheres of R = 0.2 m (8 cells) at 8 particles per cell: 17k particles.
constexpr double kCellM = 0.025;
constexpr double kRadiusM = 0.2;

Scene sceneWithBodies(const std::string& bodies, const std::string& surface = "{}") {
  return firn::parseScene(R"({
    "grid": { "cells": [32, 32, 32], "cell_size": 0.025 },
    "time": { "dt": 1e-3, "frame_rate": 50, "frames": 1 },
    "gravity": [0, 0, 0],
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": )" + bodies + R"(, "surface": )" + surface + "}",
                          "surface test scene");
}

std::string sphere(const glm::dvec3& centreM, double radiusM) {
  return R"({ "shape": "sphere", "material": "snow", "center": [)" + std::to_string(centreM.x) + "," +
         std::to_string(centreM.y) + "," + std::to_string(centreM.z) + R"(], "radius": )" + std::to_string(radiusM) + "}";
}

struct Reconstructed {
  SurfaceMesh mesh;
  firn::surface::SurfaceStats stats;
};

Reconstructed reconstruct(const Scene& scene) {
  const auto seeds = firn::sampleBodies(scene);
  Simulation simulation(scene, seeds, firn::test::glContext().info());
  SurfaceReconstruction surface(scene, seeds, firn::test::glContext().info());
  surface.reconstruct(simulation.particleView());
  return {surface.readMesh(), surface.stats()};
}

// A resting sphere of radius R at frame 0. Its particles fill the cells of a jittered lattice of spacing s =
// h/2 inside it (engine/scene/Sampling.cpp), so their volume fraction is 1 inside, ½ where their cells end, which
// is the sphere to within the lattice's staircase. The kernel (radius 3s, variance 0.075 (3s)² per axis) rounds a
// curved surface inwards by about σ²/R = 0.021 h (measured: 0.024 h on average); linear interpolation between
// nodes h/2 apart cuts chords inside by at most (h/2)²/(8R) = 0.004 h. The issue's bounds, 5% of the volume and
// half a cell per vertex, leave room for the jittered lattice's bumps (measured: 1.0% and 0.24 h, RMS 0.06 h).
TEST(Surface, RestingSphereGivesAClosedMeshOfItsVolumeWhereItIs) {
  const glm::dvec3 centreM(0.4, 0.4, 0.4);
  const Reconstructed result = reconstruct(sceneWithBodies("[" + sphere(centreM, kRadiusM) + "]"));
  const SurfaceMesh& mesh = result.mesh;
  ASSERT_GT(mesh.triangleCount(), 1000u);
  EXPECT_EQ(firn::test::edgesNotSharedByTwoOrientedTriangles(mesh), 0u);
  EXPECT_EQ(firn::test::componentCount(mesh), 1u);
  const double sphereVolumeM3 = 4.0 / 3.0 * M_PI * std::pow(kRadiusM, 3);
  EXPECT_NEAR(firn::test::enclosedVolumeM3(mesh) / sphereVolumeM3, 1.0, 0.05);
  double worstM = 0;
  std::size_t inward = 0;
  for (std::size_t v = 0; v < mesh.positionsM.size(); ++v) {
    const glm::dvec3 offset = glm::dvec3(mesh.positionsM[v]) - centreM;
    worstM = std::max(worstM, std::abs(glm::length(offset) - kRadiusM));
    if (glm::dot(glm::dvec3(mesh.normals[v]), offset) <= 0) ++inward;
  }
  EXPECT_LE(worstM, 0.5 * kCellM);
  EXPECT_EQ(inward, 0u) << "every normal points out of the sphere";
}

// Two spheres 4 cells apart (more than two kernel radii, 2 × 3s = 3h): two closed surfaces.
TEST(Surface, SeparatedSpheresGiveTwoComponents) {
  const double radiusM = 0.12;
  const Reconstructed result = reconstruct(sceneWithBodies(
      "[" + sphere({0.25, 0.4, 0.4}, radiusM) + "," + sphere({0.25 + 2 * radiusM + 4 * kCellM, 0.4, 0.4}, radiusM) + "]"));
  EXPECT_EQ(firn::test::componentCount(result.mesh), 2u);
  EXPECT_EQ(firn::test::edgesNotSharedByTwoOrientedTriangles(result.mesh), 0u);
}

// Integer sums and places fixed by a scan: the same particles give the same mesh, to the bit.
TEST(Surface, SameParticlesGiveTheSameMeshBytes) {
  const Scene scene = sceneWithBodies("[" + sphere({0.4, 0.4, 0.4}, 0.15) + "]");
  const Reconstructed first = reconstruct(scene), second = reconstruct(scene);
  EXPECT_EQ(first.mesh.positionsM, second.mesh.positionsM);
  EXPECT_EQ(first.mesh.normals, second.mesh.normals);
  EXPECT_EQ(first.mesh.indices, second.mesh.indices);
}

}  // namespace
