// Body sampling: how many particles a body gets, their mass, where they lie, and that a scene always gives the
// same particles.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "Error.h"
#include "scene/Scene.h"

namespace firn {
namespace {

constexpr double pi = 3.14159265358979323846;

// A 64³ grid of 0.02 m cells (interior [0.04, 1.24] m per axis) holding `bodies` (a JSON array) of
// "snow", whose density is 400 kg/m³.
Scene sceneWithBodies(const std::string& bodies) {
  return parseScene(R"({
    "grid": { "cells": [64, 64, 64], "cell_size": 0.02 },
    "time": { "dt": 1e-4 },
    "materials": { "snow": { "preset": "stomakhin" }, "ice": { "preset": "icy" } },
    "bodies": )" + bodies + "}",
                    "scenes/sampling.json");
}

// Radius 0.4 m at 8 particles per cell: spacing s = 0.02 / cbrt(8) = 0.01 m, R = 40 s.
const char* const sphereBody =
    R"([{ "shape": "sphere", "center": [0.64, 0.64, 0.64], "radius": 0.4, "material": "snow",
          "velocity": [1, -2, 3], "particles_per_cell": 8 }])";

TEST(Sampling, SphereParticleCountAndMassMatchItsVolume) {
  const Scene scene = sceneWithBodies(sphereBody);
  const std::vector<ParticleSeed> particles = sampleBodies(scene);
  const double spacingM = 0.01;
  const double radiusM = 0.4;
  const double volumeM3 = 4.0 / 3.0 * pi * radiusM * radiusM * radiusM;

  // Tolerance, a bound rather than an estimate. Each lattice point owns the cube of side s around it; the
  // cubes tile space. A particle's jitter moves it at most j = 0.25·√3 s from its lattice point, and a cube
  // reaches c = (√3/2) s from its centre. So every kept point's cube lies inside the ball of radius
  // R + j + c, and every cube that meets the ball of radius R − j − c has a point that is kept:
  // (R − 1.3 s)³ ≤ N s³ / (4π/3) ≤ (R + 1.3 s)³. At R = 40 s that is N s³ / V in [0.906, 1.101]: the
  // surface-to-volume ratio, 3/R, times the 1.3 s thick boundary layer.
  const double boundaryLayerM = (0.25 * std::sqrt(3.0) + 0.5 * std::sqrt(3.0)) * spacingM;
  const double lowestRatio = std::pow(1 - boundaryLayerM / radiusM, 3);
  const double highestRatio = std::pow(1 + boundaryLayerM / radiusM, 3);

  const double expectedCount = volumeM3 / (spacingM * spacingM * spacingM);
  const double countRatio = static_cast<double>(particles.size()) / expectedCount;
  EXPECT_GE(countRatio, lowestRatio) << particles.size() << " particles, expected about " << expectedCount;
  EXPECT_LE(countRatio, highestRatio) << particles.size() << " particles, expected about " << expectedCount;

  double totalMassKg = 0;
  for (const ParticleSeed& particle : particles) totalMassKg += particle.massKg;
  const double massRatio = totalMassKg / (400 * volumeM3);
  // Each particle's mass is ρ s³ rounded to float: a relative error of at most 2⁻²⁴, far inside the bound.
  EXPECT_GE(massRatio, lowestRatio) << totalMassKg << " kg";
  EXPECT_LE(massRatio, highestRatio) << totalMassKg << " kg";
}

TEST(Sampling, EveryParticleLiesInsideItsSphere) {
  const Scene scene = sceneWithBodies(sphereBody);
  for (const ParticleSeed& particle : sampleBodies(scene)) {
    // Compared squared, in double, from the stored float position: no tolerance is needed.
    const glm::dvec3 offsetM = glm::dvec3(particle.positionM) - glm::dvec3(0.64);
    ASSERT_LE(offsetM.x * offsetM.x + offsetM.y * offsetM.y + offsetM.z * offsetM.z, 0.4 * 0.4);
  }
}

TEST(Sampling, LatticeAlignedBoxGetsExactlyOneParticlePerLatticePoint) {
  // Lattice points sit at (i + 0.5) s, s = 0.01 m; the box faces at 0.2 and 0.6 m lie half a spacing from the
  // nearest lattice planes, and jitter (at most s/4) cannot carry a point across them. So the box holds exactly
  // the 40 lattice points per axis between its faces.
  const Scene scene =
      sceneWithBodies(R"([{ "shape": "box", "min": [0.2, 0.2, 0.2], "max": [0.6, 0.6, 0.6], "material": "ice" }])");
  const std::vector<ParticleSeed> particles = sampleBodies(scene);
  EXPECT_EQ(particles.size(), 40u * 40u * 40u);

  const double spacingM = 0.01;
  bool anyParticleIsJittered = false;
  for (const ParticleSeed& particle : particles) {
    for (int axis = 0; axis < 3; ++axis) {
      const double positionM = particle.positionM[axis];
      ASSERT_GE(positionM, 0.2);
      ASSERT_LE(positionM, 0.6);
      // Within a quarter spacing of its lattice point; 1e-4 s allows for the float rounding of the position.
      const double latticeOffset = positionM / spacingM - 0.5 - std::round(positionM / spacingM - 0.5);
      ASSERT_LE(std::abs(latticeOffset), 0.25 + 1e-4);
      anyParticleIsJittered = anyParticleIsJittered || std::abs(latticeOffset) > 0.1;
    }
  }
  EXPECT_TRUE(anyParticleIsJittered);
}

TEST(Sampling, ParticlesCarryTheirBodyVelocityMaterialAndIndex) {
  const Scene scene = sceneWithBodies(R"([
    { "shape": "sphere", "center": [0.4, 0.4, 0.4], "radius": 0.1, "material": "snow", "velocity": [1, -2, 3] },
    { "shape": "box", "min": [0.7, 0.7, 0.7], "max": [0.9, 0.9, 0.9], "material": "ice", "particles_per_cell": 1 }
  ])");
  const std::vector<ParticleSeed> particles = sampleBodies(scene);
  int particlesPerBody[2] = {0, 0};
  for (const ParticleSeed& particle : particles) {
    ASSERT_TRUE(particle.bodyIndex == 0 || particle.bodyIndex == 1);
    ++particlesPerBody[particle.bodyIndex];
    const Body& body = scene.bodies[particle.bodyIndex];
    EXPECT_EQ(particle.materialIndex, body.materialIndex);
    EXPECT_EQ(glm::dvec3(particle.velocityMPerS), body.velocityMPerS);
    // m = ρ s³ with s = h / cbrt(particles per cell).
    const double spacingM = 0.02 / std::cbrt(body.particlesPerCell);
    const double densityKgPerM3 = scene.materials[body.materialIndex].densityKgPerM3;
    EXPECT_FLOAT_EQ(particle.massKg, static_cast<float>(densityKgPerM3 * spacingM * spacingM * spacingM));
  }
  EXPECT_GT(particlesPerBody[0], 0);
  // 0.2 m at spacing 0.02 m, with faces half a spacing from the lattice planes: 10 points per axis.
  EXPECT_EQ(particlesPerBody[1], 1000);
}

TEST(Sampling, SameSceneGivesIdenticalParticles) {
  const Scene scene = sceneWithBodies(sphereBody);
  const std::vector<ParticleSeed> first = sampleBodies(scene);
  const std::vector<ParticleSeed> second = sampleBodies(sceneWithBodies(sphereBody));
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    // Exact equality: the jitter comes from a fixed seed.
    ASSERT_EQ(first[i].positionM, second[i].positionM) << "particle " << i;
    ASSERT_EQ(first[i].velocityMPerS, second[i].velocityMPerS) << "particle " << i;
    ASSERT_EQ(first[i].massKg, second[i].massKg) << "particle " << i;
    ASSERT_EQ(first[i].materialIndex, second[i].materialIndex) << "particle " << i;
    ASSERT_EQ(first[i].bodyIndex, second[i].bodyIndex) << "particle " << i;
  }
}

TEST(Sampling, BodySmallerThanTheSpacingIsAnError) {
  // Centred on a lattice cell corner, so every lattice point is at least (0.5 − 0.25)·√3 s ≈ 0.0043 m away
  // even after jitter: none lands within the 0.001 m radius.
  const Scene scene = sceneWithBodies(
      R"([{ "shape": "sphere", "center": [0.64, 0.64, 0.64], "radius": 0.001, "material": "snow" }])");
  try {
    sampleBodies(scene);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind("scenes/sampling.json: bodies[0]: no particles: ", 0), 0u) << message;
    EXPECT_NE(message.find("s = 0.01 m"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace firn
