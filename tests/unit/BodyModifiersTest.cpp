// Per-body motion and modifiers (docs/scene-format.md: "angular_velocity", "lambda_scale", "mu_scale", "mass_scale",
// "start_frame", "duration_frames"): what the sampled particles and the GPU material table carry.
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>

#include "gpu/Materials.h"
#include "scene/Scene.h"

namespace firn {
namespace {

constexpr double pi = 3.14159265358979323846;

Scene sceneWithBodies(const std::string& bodies) {
  return parseScene(R"({
    "grid": { "cells": [40, 40, 40], "cell_size": 0.02 },
    "time": { "dt": 1e-3, "frame_rate": 30, "frames": 10 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ )" + bodies + "] }",
                    "bodies.json");
}

// v = v0 + ω × (x − c): the body's momentum is M v0 exactly (Σ m (x − c) = 0 about the centre of mass), and its
// angular momentum about c is I ω. For a solid ball I = (2/5) M R²; the lattice's sampled ball has that to
// within its surface roughness, about one spacing of 6 in R: 2% covers it.
TEST(BodyModifiers, AngularVelocitySpinsTheBodyAboutItsCentreOfMass) {
  const Scene scene = sceneWithBodies(R"({ "shape": "sphere", "center": [0.4, 0.4, 0.4], "radius": 0.1,
      "material": "snow", "velocity": [1, 0, 0], "angular_velocity": [0, 0, 20] })");
  const std::vector<ParticleSeed> particles = sampleBodies(scene);
  double massKg = 0;
  glm::dvec3 centerM(0.0), momentum(0.0);
  for (const ParticleSeed& p : particles) {
    massKg += p.massKg;
    centerM += double(p.massKg) * glm::dvec3(p.positionM);
  }
  centerM /= massKg;
  glm::dvec3 angularMomentum(0.0);
  glm::dmat3 inertia(0.0);  // Σ m (|r|² 1 − r rᵀ)
  for (const ParticleSeed& p : particles) {
    const glm::dvec3 r = glm::dvec3(p.positionM) - centerM;
    momentum += double(p.massKg) * glm::dvec3(p.velocityMPerS);
    angularMomentum += double(p.massKg) * glm::cross(r, glm::dvec3(p.velocityMPerS));
    inertia += double(p.massKg) * (glm::dot(r, r) * glm::dmat3(1.0) - glm::outerProduct(r, r));
  }
  // Float32 velocities: relative rounding 6e-8 per particle, summed over a few thousand: 1e-6 of M·|v|max.
  EXPECT_NEAR(momentum.x, massKg * 1.0, 1e-6 * massKg * 3.0);
  EXPECT_NEAR(momentum.y, 0.0, 1e-6 * massKg * 3.0);
  // L = I ω holds for the particles as sampled (the jitter leaves small products of inertia, so L is not
  // exactly along ω), to the float32 rounding of the velocities: 1e-6 of |L|.
  const glm::dvec3 expected = inertia * glm::dvec3(0, 0, 20);
  for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(angularMomentum[axis], expected[axis], 1e-6 * glm::length(expected));
  const double ballInertia = 0.4 * massKg * 0.1 * 0.1;
  EXPECT_NEAR(angularMomentum.z / (ballInertia * 20), 1.0, 0.02);
}

TEST(BodyModifiers, MassScaleScalesEveryParticle) {
  const std::string body = R"("shape": "box", "min": [0.2, 0.2, 0.2], "max": [0.3, 0.3, 0.3], "material": "snow")";
  const std::vector<ParticleSeed> plain = sampleBodies(sceneWithBodies("{" + body + "}"));
  const std::vector<ParticleSeed> heavy = sampleBodies(sceneWithBodies("{" + body + R"(, "mass_scale": 2.5 })"));
  ASSERT_EQ(plain.size(), heavy.size());
  for (std::size_t i = 0; i < plain.size(); ++i) EXPECT_FLOAT_EQ(heavy[i].massKg, 2.5f * plain[i].massKg);
}

// A body with its own λ and μ scale gets its own GPU material entry; bodies without share the scene's.
TEST(BodyModifiers, LameScalesMakeAMaterialVariantForTheirBodyOnly) {
  const Scene scene = sceneWithBodies(R"(
      { "shape": "sphere", "center": [0.3, 0.3, 0.3], "radius": 0.05, "material": "snow" },
      { "shape": "sphere", "center": [0.5, 0.3, 0.3], "radius": 0.05, "material": "snow",
        "lambda_scale": 3, "mu_scale": 0.5 })");
  const MaterialTable table = buildMaterialTable(scene);
  ASSERT_EQ(table.entries.size(), 2u);
  ASSERT_EQ(table.bodyEntry.size(), 2u);
  EXPECT_EQ(table.bodyEntry[0], 0u);
  EXPECT_EQ(table.bodyEntry[1], 1u);
  const LameParameters lame = lameParameters(1.4e5, 0.2);  // the stomakhin preset
  EXPECT_FLOAT_EQ(table.entries[0].elastic.x, float(lame.muPa));
  EXPECT_FLOAT_EQ(table.entries[1].elastic.x, float(0.5 * lame.muPa));
  EXPECT_FLOAT_EQ(table.entries[1].elastic.y, float(3 * lame.lambdaPa));
  EXPECT_EQ(table.entries[1].plastic, table.entries[0].plastic);
  // A stiffer body tightens the elastic time step bound: c² grows with λ + 2μ.
  const Material& snow = scene.materials[0];
  EXPECT_NEAR(elasticStableDtS(snow, 0.02, 3, 0.5) / elasticStableDtS(snow, 0.02),
              std::sqrt((lame.lambdaPa + 2 * lame.muPa) / (3 * lame.lambdaPa + lame.muPa)), 1e-12);
}

// An emitter releases its particles evenly over [start, start + duration) frames, leading edge first.
TEST(BodyModifiers, EmitterReleasesLeadingEdgeFirstOverItsWindow) {
  const Scene scene = sceneWithBodies(R"(
      { "shape": "box", "min": [0.1, 0.4, 0.3], "max": [0.3, 0.5, 0.4], "material": "snow",
        "velocity": [2, 0, 0], "start_frame": 3, "duration_frames": 6 })");
  ASSERT_TRUE(scene.bodies[0].isEmitter());
  const std::vector<ParticleSeed> particles = sampleBodies(scene);
  const double startS = 3.0 / 30, endS = 9.0 / 30;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    EXPECT_GE(particles[i].releaseTimeS, startS);
    EXPECT_LT(particles[i].releaseTimeS, endS);
    if (i > 0) {
      EXPECT_GE(particles[i].releaseTimeS, particles[i - 1].releaseTimeS);
      EXPECT_LE(particles[i].positionM.x, particles[i - 1].positionM.x) << "the leading edge (largest x) leaves first";
    }
  }
  // Evenly: half of them by the middle of the window (to one particle).
  const double middleS = 0.5 * (startS + endS);
  std::size_t released = 0;
  for (const ParticleSeed& p : particles) released += p.releaseTimeS <= middleS ? 1 : 0;
  EXPECT_NEAR(double(released), 0.5 * double(particles.size()), 1.0);
}

}  // namespace
}  // namespace firn
