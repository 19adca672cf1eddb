// The material models of Blažević 2022 on the GPU (docs/algorithm.md, Material models): each runs alone and
// mixed, with its physics checked where a short, small run can check it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

#include "Error.h"
#include "GlTest.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"

namespace {

using firn::Scene;
using firn::Simulation;

class MaterialModels : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { firn::test::glContext(); }
  static const firn::gl::ContextInfo& gl() { return firn::test::glContext().info(); }
};

// A 1.2 m domain of 4 cm cells with a ground plane at y = 0.1 m; `materials` and `bodies` as JSON.
Scene sceneWith(const std::string& materials, const std::string& bodies) {
  return firn::parseScene(R"({
    "grid": { "cells": [30, 30, 30], "cell_size": 0.04 },
    "time": { "dt": 2e-4, "frame_rate": 50, "frames": 10 },
    "solver": { "kernel": "quadratic", "transfer": "apic" },
    "materials": { )" + materials + R"( },
    "bodies": [ )" + bodies + R"( ],
    "colliders": [ { "type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0], "friction": 0.5, "boundary": "slip" } ] })",
                          "materials test");
}

struct Summary {
  double massKg = 0;
  glm::dvec3 centerM{0.0};
  glm::dvec3 velocityMPerS{0.0};  // of the centre of mass
  double maxX = -1e9, minX = 1e9;
};

Summary summarize(const firn::ParticleSnapshot& s) {
  Summary out;
  glm::dvec3 momentum(0.0);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double m = s.positionMass[i].w;
    out.massKg += m;
    out.centerM += m * glm::dvec3(s.positionMass[i]);
    momentum += m * glm::dvec3(s.velocityVolume[i]);
    out.maxX = std::max(out.maxX, double(s.positionMass[i].x));
    out.minX = std::min(out.minX, double(s.positionMass[i].x));
  }
  out.centerM /= out.massKg;
  out.velocityMPerS = momentum / out.massKg;
  return out;
}

// An elastic ball dropped on the ground bounces: its centre of mass moves up again after the impact, where a
// snowball of the same stiffness (which compacts plastically) does not. Ball: r = 0.16 m, 1 m/s down from
// 0.1 m above the ground; after 0.3 s of contact and rebound the elastic ball's centre moves upward at a
// good fraction of its impact speed (≥ 0.2 m/s; an elastic ball keeps most of it, MPM's grid damping some).
TEST_F(MaterialModels, ElasticBallsBounceWhereSnowDoesNot) {
  const std::string ball = R"({ "shape": "sphere", "center": [0.6, 0.36, 0.6], "radius": 0.16, "material": "ball",
                                "velocity": [0, -1, 0] })";
  for (const char* model : {"fixed_corotated", "neo_hookean"}) {
    const Scene scene = sceneWith(std::string(R"("ball": { "model": ")") + model +
                                      R"(", "youngs_modulus": 2e5, "poisson_ratio": 0.3, "density": 1000 })",
                                  ball);
    Simulation simulation(scene, firn::sampleBodies(scene), gl());
    double highestUpwardMPerS = -1e9;
    for (int frame = 1; frame <= 15; ++frame) {
      simulation.advanceTo(frame / 50.0);
      highestUpwardMPerS = std::max(highestUpwardMPerS, summarize(simulation.snapshot()).velocityMPerS.y);
    }
    simulation.checkWatchdog();
    // It meets the ground at sqrt(1² + 2 g · 0.1 m) = 1.72 m/s.
    std::printf("%s ball: rebounds at up to %.2f m/s after hitting the ground at 1.72 m/s\n", model, highestUpwardMPerS);
    EXPECT_GT(highestUpwardMPerS, 0.2) << model;
  }
  const Scene snow = sceneWith(R"("ball": { "model": "snow", "youngs_modulus": 2e5, "poisson_ratio": 0.3, "density": 1000,
                                            "critical_compression": 0.025, "critical_stretch": 0.0075, "hardening": 10 })",
                               ball);
  Simulation simulation(snow, firn::sampleBodies(snow), gl());
  double highestUpwardMPerS = -1e9;
  for (int frame = 1; frame <= 15; ++frame) {
    simulation.advanceTo(frame / 50.0);
    if (frame > 5) highestUpwardMPerS = std::max(highestUpwardMPerS, summarize(simulation.snapshot()).velocityMPerS.y);
  }
  EXPECT_LT(highestUpwardMPerS, 0.2) << "snow compacts instead of bouncing";
}

// Martin & Moyce's dam break (1952, part IV): a water column of width a and height 2a released against a wall
// on a dry frictionless floor. Their front positions Z = x/a against T = t sqrt(2g/a), for n² = H/a = 2, as
// digitized in the dam-break literature (e.g. Koshizuka & Oka 1996): Z ≈ 1.88 at T = 1.62 and Z ≈ 2.37 at
// T = 2.02. Here a = 0.3 m in a 4-cell-deep channel of 2 cm cells (15 cells across the column), water with
// k = 1e5 Pa and γ = 7 (sound speed sqrt(kγ/ρ) = 26 m/s, dt = 2e-4 s inside h/c = 7.6e-4 s). Tolerance 15%:
// the experiment's own scatter between its two column sizes is 5–10% at these times, the front is a thin
// tongue whose tip a few particles define, and the water is weakly compressible (measured: +9% and +6%).
// Mass is unchanged, and the water stays nearly incompressible: |J − 1| < 7.5% (it compresses by about
// ρ g H / (k γ) ≈ 0.8% under its own weight, plus the transient of the release; measured 0.945–1.061, the largest
// at the tongue's tip. Volumes of m / ρ at the free surface give that; the grid density's, up to 1.8× there before
// they gave way to ρ, stiffened the surface to 1.046).
TEST_F(MaterialModels, WaterDamBreakFrontFollowsMartinAndMoyce) {
  const Scene scene = firn::parseScene(R"({
    "grid": { "cells": [60, 40, 8], "cell_size": 0.02 },
    "time": { "dt": 2e-4, "frame_rate": 50, "frames": 10 },
    "solver": { "kernel": "quadratic", "transfer": "apic" },
    "materials": { "water": { "model": "water", "density": 1000, "bulk_modulus": 1e5, "gamma": 7 } },
    "bodies": [ { "shape": "box", "min": [0.04, 0.06, 0.04], "max": [0.34, 0.66, 0.12], "material": "water",
                  "particles_per_cell": 4 } ],
    "colliders": [ { "type": "plane", "point": [0, 0.06, 0], "normal": [0, 1, 0], "friction": 0, "boundary": "slip" } ] })",
                                       "dam break");
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  const Summary start = summarize(simulation.snapshot());
  const double a = 0.3, wallX = 0.04;
  for (const auto& [timeS, expectedZ] : {std::pair{0.2, 1.88}, std::pair{0.25, 2.37}}) {
    simulation.advanceTo(timeS);
    const Summary now = summarize(simulation.snapshot());
    const double z = (now.maxX - wallX) / a;
    std::printf("dam break: T = %.2f, Z = %.2f (Martin & Moyce %.2f)\n", timeS * std::sqrt(2 * 9.81 / a), z, expectedZ);
    EXPECT_NEAR(z / expectedZ, 1.0, 0.15) << "at t = " << timeS << " s";
  }
  simulation.checkWatchdog();
  const firn::ParticleSnapshot state = simulation.snapshot();
  EXPECT_NEAR(summarize(state).massKg, start.massKg, 1e-6 * start.massKg);
  for (float J : state.plasticJ) ASSERT_NEAR(J, 1.0f, 0.075f);
}

// A column of sand collapses and spreads: Lube et al. 2005 (Phys. Rev. E 72, 041301), collapsing columns in a
// narrow channel, found the runout (L∞ − L0)/L0 ≈ 1.2 a for aspect ratios a = H/L0 below about 2.3, whatever
// the granular material. Here the same quasi-2-D set-up: a column of a = 2 against a wall in a 4-cell-deep
// channel (frictionless side walls), 2 cm cells, 8 particles per cell, the runout at t = 1 s.
//
// Friction, inside and at the base, of a 30° sand (Lube's materials lie at 30–37°):
// - Firn's Drucker–Prager cone (Klár et al. 2016) matches Mohr–Coulomb in triaxial compression, α_c(φ) =
//   2 sin φ / (√3 (3 − sin φ)); a channel flow is plane strain, where the matching cone is α_ps(φ) =
//   tan φ / √(9 + 12 tan² φ), 0.69 of α_c at 30°. A plane-strain 30° is friction_angle_deg =
//   asin(3√3 α_ps / (2 + √3 α_ps)) = 21.4° (with 30° in the compression cone the sand is 1.44× too strong
//   and runs out 0.6 of Lube's).
// - The base is rough: Coulomb friction μ = tan 30° (slip). A sticky base is not a rough one in MPM: zeroing the
//   ground nodes every step drains the flow through the stencil once per step, so the runout shrank with dt at
//   first order (3.19, 2.79, 2.47, 2.17 for dt = 4, 2, 1, 0.5 × 1e-4 s). With Coulomb friction it is 2.74,
//   2.55, 2.61 for dt = 2, 1, 0.5 × 1e-4 s: converged to ±2.5% at dt = 1e-4 s.
//
// Tolerance 20%: Lube's materials scatter by about 15% about the fit, the front is resolved to a particle
// spacing (1 cm, 5% of L0), and the dt dependence above. Measured: 1.05 of Lube's. Not asserted, because not
// converged in dt: at a = 1 the runout is 1.28, 1.12, 0.99 for dt = 2, 1, 0.5 × 1e-4 s (Lube 1.22; issue 5).
TEST_F(MaterialModels, SandColumnRunoutFollowsLube) {
  const double wallX = 0.04, heightM = 0.4;
  const Scene scene = firn::parseScene(R"({
    "grid": { "cells": [90, 30, 8], "cell_size": 0.02 },
    "time": { "dt": 1e-4, "frame_rate": 10, "frames": 10 },
    "solver": { "kernel": "quadratic", "transfer": "apic" },
    "materials": { "sand": { "model": "drucker_prager", "youngs_modulus": 3.537e5, "poisson_ratio": 0.3,
                             "density": 2200, "friction_angle_deg": 21.4 } },
    "bodies": [ { "shape": "box", "min": [0.04, 0.06, 0.04], "max": [0.2375, 0.46, 0.12], "material": "sand",
                  "particles_per_cell": 8 } ],
    "colliders": [ { "type": "plane", "point": [0, 0.06, 0], "normal": [0, 1, 0], "friction": 0.577,
                     "boundary": "slip" } ] })",
                                       "sand column");
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  const Summary start = summarize(simulation.snapshot());
  simulation.advanceTo(1.0);
  simulation.checkWatchdog();
  const Summary end = summarize(simulation.snapshot());
  const double initialLengthM = start.maxX - wallX;
  const double aspect = heightM / initialLengthM;
  const double runout = (end.maxX - start.maxX) / initialLengthM;
  std::printf("sand column: aspect %.2f, runout (L - L0)/L0 = %.2f (Lube et al. 2005: %.2f), centre moving at %.3f m/s\n",
              aspect, runout, 1.2 * aspect, glm::length(end.velocityMPerS));
  EXPECT_NEAR(runout / (1.2 * aspect), 1.0, 0.2) << "aspect " << aspect;
  EXPECT_LT(glm::length(end.velocityMPerS), 0.05) << "the heap has stopped";
  EXPECT_NEAR(end.massKg, start.massKg, 1e-6 * start.massKg);
}

// Every model in one scene, interacting through the shared grid: no NaN, mass unchanged, the watchdog quiet.
TEST_F(MaterialModels, AllModelsTogetherStayFinite) {
  const Scene scene = sceneWith(
      R"("snow": { "preset": "stomakhin" },
         "jelly": { "model": "neo_hookean", "youngs_modulus": 5e4, "poisson_ratio": 0.3, "density": 1000 },
         "rubber": { "model": "fixed_corotated", "youngs_modulus": 1e5, "poisson_ratio": 0.3, "density": 1000 },
         "water": { "model": "water", "density": 1000, "bulk_modulus": 1e5, "gamma": 7 },
         "sand": { "model": "drucker_prager", "youngs_modulus": 3.537e5, "poisson_ratio": 0.3, "density": 2200,
                   "hardening": [35, 9, 0.2, 10] })",
      R"({ "shape": "box", "min": [0.4, 0.1, 0.4], "max": [0.8, 0.22, 0.8], "material": "water" },
         { "shape": "sphere", "center": [0.4, 0.5, 0.4], "radius": 0.1, "material": "snow", "velocity": [1, -2, 0] },
         { "shape": "sphere", "center": [0.8, 0.5, 0.4], "radius": 0.1, "material": "jelly", "velocity": [-1, -2, 0] },
         { "shape": "box", "min": [0.3, 0.4, 0.7], "max": [0.5, 0.6, 0.9], "material": "rubber", "mu_scale": 2 },
         { "shape": "box", "min": [0.7, 0.4, 0.7], "max": [0.9, 0.7, 0.9], "material": "sand" })");
  const std::vector<firn::ParticleSeed> seeds = firn::sampleBodies(scene);
  Simulation simulation(scene, seeds, gl());
  const Summary start = summarize(simulation.snapshot());
  simulation.advanceTo(0.2);
  simulation.checkWatchdog();
  const firn::ParticleSnapshot state = simulation.snapshot();
  ASSERT_EQ(firn::test::firstNonFiniteParticle(state), state.size()) << "a particle is not finite";
  EXPECT_NEAR(summarize(state).massKg, start.massKg, 1e-6 * start.massKg);
}

}  // namespace
