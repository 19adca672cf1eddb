// The energy audit on the GPU (sim/EnergyAudit.h; docs/numerics.md, The energy audit): each run's budget from its own
// numbers, checked against what the physics says of small scenes: a free fall loses exactly symplectic Euler's share,
// an elastic ball bounces on a frictionless floor without making energy, a snowball's landing only dissipates, and a
// semi-implicit step ten times the elastic bound makes none.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "Error.h"
#include "GlTest.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"

namespace {

using firn::EnergyBudget;
using firn::Scene;
using firn::Simulation;

class EnergyBudgetTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { firn::test::glContext(); }
  static const firn::gl::ContextInfo& gl() { return firn::test::glContext().info(); }
};

// A 24³ domain of 2.5 cm cells with `solver`, `materials`, `bodies` and `colliders` as JSON.
Scene sceneWith(const std::string& name, const std::string& time, const std::string& solver,
                const std::string& materials, const std::string& bodies, const std::string& colliders = "") {
  return firn::parseScene(R"({
    "grid": { "cells": [24, 24, 24], "cell_size": 0.025 },
    "time": )" + time + R"(, "solver": )" + solver + R"(,
    "materials": { )" + materials + R"( },
    "bodies": [ )" + bodies + R"( ],
    "colliders": [ )" + colliders + R"( ] })",
                          name);
}

// Kinetic, potential (above the domain's floor, y = 0) and the mass of the particles, summed in double on the host.
struct HostEnergy {
  double kineticJ = 0;
  double potentialJ = 0;
  double massKg = 0;
};
HostEnergy hostEnergy(const firn::ParticleSnapshot& particles) {
  HostEnergy energy;
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const double m = particles.positionMass[p].w;
    const glm::dvec3 v(particles.velocityVolume[p]);
    energy.kineticJ += 0.5 * m * glm::dot(v, v);
    energy.potentialJ += m * 9.81 * double(particles.positionMass[p].y);
    energy.massKg += m;
  }
  return energy;
}

// Symplectic Euler drops a falling mass's energy by ½ m g² Δt² a step: v gains g Δt, x moves by the new v, so ΔKE =
// m g·v Δt + ½ m g² Δt² and ΔPE = −m g·v Δt − m g² Δt². With APIC, a uniform velocity crosses both transfers exactly
// and the block is never strained, so after S steps the dissipated energy is ½ M g² Δt² S, and nothing else moves: no
// elastic energy, no walls, the audit's step term 0. Tolerance: the dithered fixed-point sums (docs/numerics.md) give
// each node's momentum an unbiased error below 2^−k of m_ref h / Δt per contribution, which moves the kinetic energy
// by ±M |v| 2^−k h / Δt per step at most (one sign for all, the worst case), S of them; and the audit's own rounding.
TEST_F(EnergyBudgetTest, FreeFallLosesExactlySymplecticEulersShare) {
  const Scene scene = sceneWith("free fall", R"({ "dt": 1e-3, "frame_rate": 20, "frames": 3 })",
                                R"({ "kernel": "quadratic", "transfer": "apic" })",
                                R"("jelly": { "model": "fixed_corotated", "youngs_modulus": 1e4, "poisson_ratio": 0.3,
                                              "density": 500 })",
                                R"({ "shape": "box", "min": [0.2, 0.35, 0.2], "max": [0.35, 0.45, 0.35],
                                     "material": "jelly", "velocity": [0.5, 0, 0] })");
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  const int steps = 150;  // 0.15 s: the block falls 0.11 m, well clear of the walls at 0.05 m
  simulation.advanceTo(steps * 1e-3);
  simulation.checkWatchdog();
  const EnergyBudget budget = simulation.energyBudget();
  const HostEnergy host = hostEnergy(simulation.snapshot());
  const double dtS = 1e-3, g = 9.81;
  const double expectedJ = 0.5 * host.massKg * g * g * dtS * dtS * steps;
  const double fastestMPerS = std::sqrt(0.25 + std::pow(g * steps * dtS, 2));
  const double ditherJ = steps * host.massKg * fastestMPerS * std::ldexp(0.025 / dtS, -simulation.fixedPoint().fractionBits);
  const double roundingJ = std::ldexp(2 * (budget.totalJ() + std::abs(budget.dissipatedJ)), -20);
  EXPECT_NEAR(budget.dissipatedJ, expectedJ, ditherJ + roundingJ);
  EXPECT_GT(expectedJ, 10 * (ditherJ + roundingJ));  // the share is what is measured, not the noise
  EXPECT_EQ(budget.wallsRemovedJ, 0.0);
  EXPECT_EQ(budget.colliderWorkJ, 0.0);
  EXPECT_LT(budget.elasticJ, 1e-9 * budget.kineticJ);
  EXPECT_LT(std::abs(budget.stepTermJ), 1e-9 * budget.kineticJ);
  // The GPU's sums are the particles' own, to float rounding (2^−20 of each).
  EXPECT_NEAR(budget.kineticJ, host.kineticJ, std::ldexp(host.kineticJ, -20));
  EXPECT_NEAR(budget.potentialJ, host.potentialJ, std::ldexp(host.potentialJ, -20));
}

// Steps a simulation frame by frame to `frames` audits `frameS` apart, each one checked by the watchdog (which stops
// the test with its message if the audit finds energy made from nothing), and returns every audit's budget, the
// start's first.
std::vector<EnergyBudget> auditedFrames(Simulation& simulation, int frames, double frameS) {
  std::vector<EnergyBudget> budgets = {simulation.energyBudget()};
  for (int frame = 1; frame <= frames; ++frame) {
    simulation.advanceTo(frame * frameS);
    simulation.checkWatchdog();
    budgets.push_back(simulation.energyBudget());
  }
  return budgets;
}

// A neo-Hookean ball (APIC, quadratic) dropped 12 cm onto a frictionless floor bounces. Energy made from nothing: the
// audit's tolerance at every frame, as the watchdog checks it, and never more than the energy at the start plus that
// tolerance. Energy lost: the floor is inelastic for the nodes it holds (docs/algorithm.md, Colliders), which are those
// a particle within the quadratic kernel's reach of 1.5 h above it reaches; so a bounce loses at most the kinetic
// energy of the ball's cap of that height plus its flattening δ (δ ≈ R v / c, the impact's strain v / c over the
// radius), π H² (R − H / 3) of its volume with H = 1.5 h + δ (19% here), and APIC's transfers' own loss while the ball
// is deformed, at most what they take from the free elastic bar, which is deformed all the time: 6% of its energy
// over two periods (amplitude 0.973, benchmarks/README.md's tradeoff baseline).
TEST_F(EnergyBudgetTest, ElasticBallBouncesOnAFrictionlessFloorWithoutMakingEnergy) {
  const Scene scene = sceneWith("elastic ball", R"({ "dt": 4e-4, "frame_rate": 50, "frames": 14 })",
                                R"({ "kernel": "quadratic", "transfer": "apic" })",
                                R"("rubber": { "model": "neo_hookean", "youngs_modulus": 2e5, "poisson_ratio": 0.3,
                                               "density": 1000 })",
                                R"({ "shape": "sphere", "center": [0.3, 0.3, 0.3], "radius": 0.08, "material": "rubber" })",
                                R"({ "type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0], "friction": 0,
                                     "boundary": "slip" })");
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  const std::vector<EnergyBudget> budgets = auditedFrames(simulation, 14, 0.02);
  const double startJ = budgets.front().totalJ();
  double lowestJ = startJ, mostElasticJ = 0, mostKineticAfterJ = 0;
  for (std::size_t frame = 1; frame < budgets.size(); ++frame) {
    const EnergyBudget& b = budgets[frame];
    EXPECT_LE(b.totalJ(), startJ + b.toleranceJ) << "frame " << frame;
    lowestJ = std::min(lowestJ, b.totalJ());
    if (b.elasticJ > mostElasticJ) {
      mostElasticJ = b.elasticJ;
      mostKineticAfterJ = 0;
    }
    mostKineticAfterJ = std::max(mostKineticAfterJ, b.kineticJ);
  }
  const double radiusM = 0.08, h = 0.025, speedMPerS = std::sqrt(2 * 9.81 * 0.12);
  const double impactKineticJ = 9.81 * 0.12 * hostEnergy(simulation.snapshot()).massKg;
  const double waveMPerS = std::sqrt(2e5 * 0.7 / (1.3 * 0.4) / 1000);  // (λ + 2μ) / ρ for ν = 0.3
  const double capM = 1.5 * h + radiusM * speedMPerS / waveMPerS;
  const double capShare = std::acos(-1.0) * capM * capM * (radiusM - capM / 3) / (4.0 / 3 * std::acos(-1.0) * std::pow(radiusM, 3));
  EXPECT_GE(lowestJ, startJ - (capShare + 0.06) * impactKineticJ);
  // It bounced: the strain the impact stored came back as motion.
  EXPECT_GT(mostElasticJ, 0.3 * impactKineticJ);
  EXPECT_GT(mostKineticAfterJ, 0.4 * impactKineticJ);
}

// A snowball of Stomakhin's snow (PIC/FLIP) lands on a floor with friction: its energy only falls, frame after frame
// (within the audit's tolerance), the dissipated energy takes what it loses (plasticity, friction, the transfers), and
// the GPU's kinetic and potential energy are the particles' own (to 2^−20: float rounding of each).
TEST_F(EnergyBudgetTest, SnowballLandingOnlyDissipates) {
  const Scene scene = sceneWith("snowball landing", R"({ "dt": 5e-4, "frame_rate": 50, "frames": 8 })",
                                R"({ "kernel": "quadratic", "transfer": "pic_flip" })",
                                R"("snow": { "preset": "stomakhin" })",
                                R"({ "shape": "sphere", "center": [0.3, 0.22, 0.3], "radius": 0.08, "material": "snow",
                                     "velocity": [0.5, -1, 0] })",
                                R"({ "type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0], "friction": 0.3,
                                     "boundary": "slip" })");
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  const std::vector<EnergyBudget> budgets = auditedFrames(simulation, 8, 0.02);
  for (std::size_t frame = 1; frame < budgets.size(); ++frame) {
    const EnergyBudget& b = budgets[frame];
    const EnergyBudget& before = budgets[frame - 1];
    EXPECT_LE(b.totalJ(), before.totalJ() + b.hardeningJ - before.hardeningJ + b.toleranceJ) << "frame " << frame;
    EXPECT_GE(b.dissipatedJ + b.wallsRemovedJ, before.dissipatedJ + before.wallsRemovedJ - b.toleranceJ)
        << "frame " << frame;
  }
  const EnergyBudget& last = budgets.back();
  EXPECT_GT(last.dissipatedJ, 0.5 * (budgets.front().totalJ() - last.totalJ()));  // the landing's loss is there
  const HostEnergy host = hostEnergy(simulation.snapshot());
  EXPECT_NEAR(last.kineticJ, host.kineticJ, std::ldexp(host.kineticJ, -20));
  EXPECT_NEAR(last.potentialJ, host.potentialJ, std::ldexp(host.potentialJ, -20));
}

// The semi-implicit step at ten times the snow's elastic bound h / c (1.1 ms: 11 ms) lands a snowball: stable, and its
// energy is never above what it was at any earlier frame (β = 1 damps; docs/numerics.md). The landing is in frame 2.
TEST_F(EnergyBudgetTest, SemiImplicitStepAtTenTimesTheBoundNeverMakesEnergy) {
  const Scene scene = sceneWith("semi-implicit snowball", R"({ "dt": 1.1e-2, "frame_rate": 50, "frames": 4 })",
                                R"({ "kernel": "quadratic", "transfer": "apic", "integrator": "semi_implicit" })",
                                R"("snow": { "preset": "stomakhin" })",
                                R"({ "shape": "sphere", "center": [0.3, 0.2, 0.3], "radius": 0.06, "material": "snow",
                                     "velocity": [0.5, -1, 0] })",
                                R"({ "type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0], "friction": 0.3,
                                     "boundary": "slip" })");
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  const std::vector<EnergyBudget> budgets = auditedFrames(simulation, 4, 0.02);
  for (std::size_t frame = 1; frame < budgets.size(); ++frame) {
    const EnergyBudget& b = budgets[frame];
    EXPECT_LE(b.createdJ, std::ldexp(b.totalJ(), -20)) << "frame " << frame;  // none, to float rounding
  }
  EXPECT_GT(budgets.back().dissipatedJ, 0.1 * budgets.front().totalJ());  // it landed
}

}  // namespace
