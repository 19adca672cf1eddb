// The energy audit's host side (sim/EnergyAudit.h; docs/numerics.md, The energy audit): the models' energy densities
// against the stresses the step uses, the ledger's scale, the rigid bodies' energy, the account's residual and
// checkpoint, and the watchdog's tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "gpu/GpuFunctions.h"
#include "gpu/Materials.h"
#include "io/Checkpoint.h"
#include "scene/Scene.h"
#include "sim/EnergyAudit.h"
#include "sim/FixedPoint.h"

namespace {

using namespace firn;

// The derivative of f at x by central differences, step s: its error is f''' s² / 6, below 1e-8 relative for the
// smooth densities here at s = 1e-5, and its rounding ε |f| / s about 1e-11 relative.
template <class F>
double derivative(F f, double x, double s = 1e-5) {
  return (f(x + s) - f(x - s)) / (2 * s);
}

// Each density's derivative is the Kirchhoff stress the step's materials use (common/materials.glsl), in the principal
// frame of F = diag(σ): σᵢ ∂Ψ/∂σᵢ = τᵢ. Checked at a compressed, sheared and stretched state of each model;
// tolerance 1e-7 of the stress's scale (the differences' error, above).
TEST(EnergyAudit, EnergyDensitiesAreTheStressesPotentials) {
  const double mu = 5.8e4, lambda = 3.9e4;
  const double sigma[3] = {0.93, 1.04, 1.11};
  const double scale = 1e-7 * (2 * mu + lambda);
  for (int i = 0; i < 3; ++i) {
    double s[3] = {sigma[0], sigma[1], sigma[2]};
    const double J = s[0] * s[1] * s[2];
    // Fixed corotated (Stomakhin et al. 2013 eq. 6): τᵢ = 2μ(σᵢ − 1)σᵢ + λ(J − 1)J.
    const double corotated = sigma[i] * derivative([&](double x) {
      s[i] = x;
      return gpu::fixedCorotatedEnergyDensity(mu, lambda, s[0], s[1], s[2]);
    }, sigma[i]);
    s[i] = sigma[i];
    EXPECT_NEAR(corotated, 2 * mu * (sigma[i] - 1) * sigma[i] + lambda * (J - 1) * J, scale) << "axis " << i;
    // Neo-Hookean: τᵢ = μ(σᵢ² − 1) + λ ln J.
    const double neoHookean = sigma[i] * derivative([&](double x) {
      s[i] = x;
      return gpu::neoHookeanEnergyDensity(mu, lambda, s[0] * s[0] + s[1] * s[1] + s[2] * s[2],
                                          std::log(s[0] * s[1] * s[2]));
    }, sigma[i]);
    s[i] = sigma[i];
    EXPECT_NEAR(neoHookean, mu * (sigma[i] * sigma[i] - 1) + lambda * std::log(J), scale) << "axis " << i;
    // Hencky (sand): τᵢ = 2μ ln σᵢ + λ Σ ln σ.
    const double hencky = derivative([&](double l) {
      double logs[3] = {std::log(s[0]), std::log(s[1]), std::log(s[2])};
      logs[i] = l;
      return gpu::henckyEnergyDensity(mu, lambda, logs[0], logs[1], logs[2]);
    }, std::log(sigma[i]));
    EXPECT_NEAR(hencky, 2 * mu * std::log(sigma[i]) + lambda * std::log(J), scale) << "axis " << i;
  }
  // Every density is 0 undeformed.
  EXPECT_EQ(gpu::fixedCorotatedEnergyDensity(mu, lambda, 1.0, 1.0, 1.0), 0.0);
  EXPECT_EQ(gpu::neoHookeanEnergyDensity(mu, lambda, 3.0, 0.0), 0.0);
  EXPECT_EQ(gpu::henckyEnergyDensity(mu, lambda, 0.0, 0.0, 0.0), 0.0);
}

// Water's: dΨ/d(ln J) = J dΨ/dJ = −p J with p = k (J^−γ − 1), on both sides of where its series hands over to the
// exponentials (|ln J| = 1/8), for γ = 7 (a = −6) and γ = 1 (a = 0, where the direct form divides by nothing), and Ψ ≥ 0
// with Ψ(1) = 0. Tolerance 1e-7 of k (the differences' error); the series' own is below 1e-7 of Ψ (shared_functions.h).
TEST(EnergyAudit, WatersEnergyIsItsPressuresPotential) {
  const double k = 2e5;
  for (const double gamma : {7.0, 1.0}) {
    for (const double J : {0.97, 1.003, 0.8826, 0.8825, 1.1331, 1.1334, 0.6, 1.4}) {
      const double dPsi = derivative([&](double l) { return gpu::waterEnergyDensity(k, gamma, l); }, std::log(J));
      const double pressure = k * (std::pow(J, -gamma) - 1);
      EXPECT_NEAR(dPsi, -pressure * J, 1e-7 * k) << "gamma " << gamma << ", J " << J;
      EXPECT_GE(gpu::waterEnergyDensity(k, gamma, std::log(J)), 0.0);
    }
    EXPECT_EQ(gpu::waterEnergyDensity(k, gamma, 0.0), 0.0);
  }
}

// The ledger's unit is a power of two (exact in the GPU's float and back), and the scene's bound, capacity × e, is
// 2^54 units of it, within the factor 2 of rounding down to a power: what deriveEnergyScale states.
TEST(EnergyAudit, LedgerScaleGivesTheScenesBound2To54Units) {
  const Scene scene = parseScene(R"({
    "grid": { "cells": [20, 20, 20], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 50, "frames": 3 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "sphere", "center": [0.5, 0.5, 0.5], "radius": 0.1, "material": "snow" } ] })",
                                 "energy scale");
  std::vector<ParticleSeed> seeds(1);
  seeds[0].massKg = 2e-3f;
  seeds[0].velocityMPerS = glm::vec3(3, 0, 4);  // 5 m/s
  FixedPointScale scale;
  scale.referenceMassKg = 2e-3;
  deriveEnergyScale(scale, scene, seeds, 1000);
  int exponent = 0;
  EXPECT_EQ(std::frexp(scale.energyUnitsPerJ, &exponent), 0.5);
  const double h = 0.05, dt = 1e-3, diagonal = std::sqrt(3.0) * 20 * h;
  const double c = stiffestBody(scene).waveSpeedMPerS;
  const double boundJ = 1000 * 2e-3 * ((h / dt) * (h / dt) + c * c + 2 * 9.81 * diagonal + 25);
  EXPECT_LE(boundJ * scale.energyUnitsPerJ, std::ldexp(1.0, 54));
  EXPECT_GT(boundJ * scale.energyUnitsPerJ, std::ldexp(1.0, 53));
  EXPECT_EQ(scale.particleEnergyLimit, std::ldexp(1.0, 62) / 1000);
}

// A rigid body's kinetic energy is ½ M |V|² + ½ ω · (R I Rᵀ ω): a box of inertia diag(1, 2, 3) kg·m² turned a
// quarter about z spins about world x at 2 rad/s, which is its own y (I = 2): ½ 2 · 4 = 4 J, with ½ 3 · 1 = 1.5 J of
// its motion at 1 m/s. The potential energy is measured from the domain's floor: a body 0.3 m above it, of 3 kg.
TEST(EnergyAudit, RigidBodyEnergyTurnsItsInertia) {
  RigidBody body;
  body.massKg = 3;
  body.inertiaKgM2 = glm::dmat3(1, 0, 0, 0, 2, 0, 0, 0, 3);
  ObjectPose pose;
  pose.orientation = glm::angleAxis(glm::radians(90.0), glm::dvec3(0, 0, 1));
  pose.angularVelocityRadPerS = glm::dvec3(2, 0, 0);
  pose.velocityMPerS = glm::dvec3(0, 1, 0);
  EXPECT_NEAR(rigidBodyKineticEnergyJ(body, pose), 5.5, 1e-12);
  EXPECT_NEAR(potentialEnergyJ(glm::dvec3(0, -9.81, 0), glm::dvec3(0, 0.1, 0), 3, glm::dvec3(0.2, 0.4, 0.7)),
              3 * 9.81 * 0.3, 1e-12);
}

// The floor is the domain's corner lowest along gravity: the origin for gravity down y, the top for gravity up.
TEST(EnergyAudit, PotentialFloorIsTheCornerLowestAlongGravity) {
  Scene scene;
  scene.grid.originM = glm::dvec3(1, 2, 3);
  scene.grid.cells = glm::ivec3(10, 20, 30);
  scene.grid.cellSizeM = 0.1;
  scene.gravityMPerS2 = glm::dvec3(0, -9.81, 0);
  EXPECT_EQ(potentialFloorM(scene), glm::dvec3(1, 2, 3));
  scene.gravityMPerS2 = glm::dvec3(1, 9.81, 0);
  EXPECT_EQ(potentialFloorM(scene), glm::dvec3(2, 4, 3));
}

// A closed scene's energy at rest, then a frame whose particles gained energy from nothing: the reading says so once
// the gain passes the tolerance, and not before; the dissipated energy is the residual of the budget.
class EnergyAccountTest : public ::testing::Test {
 protected:
  static Scene scene(const char* integrator) {
    return parseScene(std::string(R"({
      "grid": { "cells": [20, 20, 20], "cell_size": 0.05 },
      "time": { "dt": 1e-3, "frame_rate": 50, "frames": 3 },
      "solver": { "integrator": ")") + integrator + R"(" },
      "materials": { "snow": { "preset": "stomakhin" } },
      "bodies": [ { "shape": "sphere", "center": [0.5, 0.5, 0.5], "radius": 0.1, "material": "snow" } ] })",
                      "energy account");
  }
  static FixedPointScale scale() {
    FixedPointScale fixed;
    fixed.energyUnitsPerJ = std::ldexp(1.0, 40);
    fixed.particleEnergyLimit = std::ldexp(1.0, 52);
    return fixed;
  }
  static EnergySums sums(double kineticJ, double potentialJ, double elasticJ) {
    EnergySums s;
    s.particles = {std::int64_t(std::ldexp(kineticJ, 40)), std::int64_t(std::ldexp(potentialJ, 40)),
                   std::int64_t(std::ldexp(elasticJ, 40))};
    return s;
  }
};

// Explicit, at θ = c Δt / h (stomakhin snow: c = 22.35 m/s, Δt = 1e-3 s, h = 0.05 m: θ = 0.447): a frame may make
// 2θ / (1 − θ) = 1.62 times the mechanical energy at the reference (here 2 J of kinetic energy), and rounding.
TEST_F(EnergyAccountTest, ExplicitStepsMayMakeWhatTheirTruncationAllows) {
  EnergyAudit audit(scene("explicit"), scale());
  audit.start(sums(2, 10, 0), {});
  const double theta = 22.35 * 1e-3 / 0.05;
  const double allowedJ = 2 * theta / (1 - theta) * 2;
  EXPECT_NEAR(audit.toleranceJ(audit.account().reference, 0, 0), 0.0, 1e-12);  // nothing since the reference
  const EnergyAudit::Reading within = audit.read(sums(2 + 0.95 * allowedJ, 10, 0), {}, 10, 1e-3, 0, 100, 0);
  EXPECT_FALSE(within.creation);
  EXPECT_NEAR(within.account.toleranceJ, allowedJ, 1e-3 * allowedJ);
  const EnergyAudit::Reading beyond = audit.read(sums(2 + 1.05 * allowedJ, 10, 0), {}, 10, 1e-3, 0, 100, 0);
  ASSERT_TRUE(beyond.creation);
  EXPECT_NEAR(beyond.creation->createdJ, 1.05 * allowedJ, 1e-9);
  // The residual: what the particles lost is dissipated.
  audit.commit(audit.read(sums(1.5, 10, 0.1), {}, 10, 1e-3, 0, 100, 0));
  EXPECT_NEAR(audit.budget().dissipatedJ, 0.4, 1e-9);
  // A step at the elastic bound or beyond explains no growth: the tolerance is the rounding alone.
  const EnergyAudit::Reading longStep = audit.read(sums(1.5 + 1e-3, 10, 0.1), {}, 10, 2.5e-3, 0, 100, 0);
  EXPECT_TRUE(longStep.creation);
}

// Semi-implicit: 2 × the solve's tolerance (1e-4) per step of the mechanical energy; 100 steps of 2 J allow 0.04 J.
TEST_F(EnergyAccountTest, SemiImplicitStepsMayMakeWhatTheirSolveLeaves) {
  EnergyAudit audit(scene("semi_implicit"), scale());
  audit.start(sums(2, 10, 0), {});
  EXPECT_FALSE(audit.read(sums(2.039, 10, 0), {}, 100, 1e-2, 0, 100, 0).creation);
  EXPECT_TRUE(audit.read(sums(2.041, 10, 0), {}, 100, 1e-2, 0, 100, 0).creation);
}

// What arrives (an emitter's particles) and what the walls take are no creation; the checkpoint carries the account to
// the bit.
TEST_F(EnergyAccountTest, ArrivalsAndWallsBalanceAndTheAccountSurvivesACheckpoint) {
  EnergyAudit audit(scene("explicit"), scale());
  audit.start(sums(0, 10, 0), {});
  audit.noteArrival(5);
  EnergySums walled = sums(2.5, 12, 0);
  walled.flows[1] = std::int64_t(std::ldexp(0.5, 40));  // the walls took 0.5 J of the 15 J
  const EnergyAudit::Reading reading = audit.read(walled, {}, 10, 1e-3, 0, 100, 0);
  EXPECT_FALSE(reading.creation);
  audit.commit(reading);
  const EnergyBudget budget = audit.budget();
  EXPECT_EQ(budget.arrivedJ, 5.0);
  EXPECT_EQ(budget.wallsRemovedJ, 0.5);
  EXPECT_NEAR(budget.dissipatedJ, 10 + 5 - 0.5 - 14.5, 1e-12);
  Checkpoint checkpoint;
  packEnergyAccount(audit.account(), checkpoint);
  EnergyAudit resumed(scene("explicit"), scale());
  resumed.setAccount(unpackEnergyAccount(checkpoint));
  const EnergyBudget again = resumed.budget();
  EXPECT_EQ(again.dissipatedJ, budget.dissipatedJ);
  EXPECT_EQ(again.arrivedJ, budget.arrivedJ);
  EXPECT_EQ(again.kineticJ, budget.kineticJ);
  EXPECT_EQ(resumed.account().reference.dissipatedJ, audit.account().reference.dissipatedJ);
}

}  // namespace
