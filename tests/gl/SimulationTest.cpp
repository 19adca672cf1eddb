// The MPM passes on the GPU (llvmpipe in CI), checked against physics with stated tolerances.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "Error.h"
#include "GlTest.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"
#include "support/SimulationProbe.h"

namespace {

using firn::Scene;
using firn::Simulation;

Scene sceneFromJson(const std::string& json) { return firn::parseScene(json, "test scene"); }

// A 0.2 m box of reference snow in a 1.6 m domain; `extra` adds solver/colliders/velocity keys.
std::string boxScene(const std::string& solver, const std::string& velocity, const std::string& colliders,
                     const std::string& boxMin = "[0.7, 0.7, 0.7]", const std::string& boxMax = "[0.9, 0.9, 0.9]") {
  return R"({
    "grid": { "origin": [0, 0, 0], "cells": [32, 32, 32], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 50, "frames": 10 },
    "solver": )" + solver + R"(,
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "box", "min": )" + boxMin + R"(, "max": )" + boxMax + R"(, "material": "snow",
                  "velocity": )" + velocity + R"( } ],
    "colliders": )" + colliders + "}";
}

struct Totals {
  double massKg = 0;
  glm::dvec3 momentum{0.0};
  glm::dvec3 centerOfMassM{0.0};
  float minY = std::numeric_limits<float>::max();
};

Totals particleTotals(const firn::ParticleSnapshot& s) {
  Totals t;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double m = s.positionMass[i].w;
    t.massKg += m;
    t.momentum += m * glm::dvec3(s.velocityVolume[i]);
    t.centerOfMassM += m * glm::dvec3(s.positionMass[i]);
    t.minY = std::min(t.minY, s.positionMass[i].y);
  }
  t.centerOfMassM /= t.massKg;
  return t;
}

// The watchdog's message, or a test failure if the watchdog saw nothing.
std::string watchdogMessage(Simulation& simulation) {
  try {
    simulation.checkWatchdog();
  } catch (const firn::SimulationError& error) {
    EXPECT_EQ(error.code(), firn::ExitCode::Unstable);
    return error.what();
  }
  ADD_FAILURE() << "the watchdog reported nothing";
  return "";
}

class SimulationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { firn::test::glContext(); }
  static const firn::gl::ContextInfo& gl() { return firn::test::glContext().info(); }
};

// P2G conserves mass and momentum: Σ_i m_i = Σ_p m_p and Σ_i p_i = Σ_p m_p v_p, since the weights are a
// partition of unity (and, for APIC, have a vanishing first moment). The only error is fixed-point rounding,
// less than one unit 2^-k of m_ref (or of the momentum unit) per contribution (dithered rounding), plus float32
// rounding of the weights, ≈ 1e-6 relative per particle. Both are bounded below.
TEST_F(SimulationTest, ParticleToGridConservesMassAndMomentum) {
  for (const char* solver : {R"({"kernel": "quadratic", "transfer": "apic"})", R"({"kernel": "cubic", "transfer": "pic_flip"})"}) {
    const Scene scene = sceneFromJson(boxScene(solver, "[1.5, -0.5, 2.0]", "[]"));
    Simulation simulation(scene, firn::sampleBodies(scene), gl());
    const Totals particles = particleTotals(simulation.snapshot());
    const firn::GridTotals grid = simulation.transferToGrid();

    const double stencilNodes = scene.solver.kernel == firn::Kernel::Cubic ? 64 : 27;
    const double contributions = double(simulation.particleCount()) * stencilNodes;
    const auto& fp = simulation.fixedPoint();
    const double massTolerance = contributions * fp.resolution() * fp.referenceMassKg + 1e-6 * particles.massKg;
    const double momentumTolerance =
        contributions * fp.resolution() * fp.momentumUnitKgMPerS + 1e-6 * glm::length(particles.momentum);
    EXPECT_NEAR(grid.massKg, particles.massKg, massTolerance) << solver;
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(grid.momentumKgMPerS[axis], particles.momentum[axis], momentumTolerance) << solver << " axis " << axis;
    }
  }
}

// Float sums (a tile's in private accumulators, added at the node with GL_NV_shader_atomic_float) give the same
// physics: P2G totals agree with the particle sums to float32 accumulation error (each node adds ≤ 216 terms,
// relative error ≤ 216 · 2⁻²⁴ ≈ 1.3e-5; tolerance 2e-5 of the total), and free fall keeps its velocity to
// 1e-5 m/s (float32 noise, measured 5e-7). A tile added twice, or a lost one, would be a percent-sized error.
class FloatSumsTest : public SimulationTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(FloatSumsTest, ConserveAndFallLikeFixedPoint) {
  const std::string atomics = GetParam();
  if (atomics == "float" && !gl().hasFloatAtomics) GTEST_SKIP() << gl().renderer << " has no GL_NV_shader_atomic_float";
  const Scene scene =
      sceneFromJson(boxScene(R"({"kernel": "quadratic", "atomics": ")" + atomics + R"("})", "[0.5, 2.0, -0.25]", "[]"));
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  const Totals particles = particleTotals(simulation.snapshot());
  const firn::GridTotals grid = simulation.transferToGrid();
  EXPECT_NEAR(grid.massKg, particles.massKg, 2e-5 * particles.massKg);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(grid.momentumKgMPerS[axis], particles.momentum[axis], 2e-5 * glm::length(particles.momentum));
  }
  const double t = 0.2;
  simulation.advanceTo(t);
  simulation.checkWatchdog();
  const Totals end = particleTotals(simulation.snapshot());
  const glm::dvec3 expected = glm::dvec3(0.5, 2.0, -0.25) + scene.gravityMPerS2 * t;
  for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(end.momentum[axis] / end.massKg, expected[axis], 1e-5);
}

INSTANTIATE_TEST_SUITE_P(Atomics, FloatSumsTest, ::testing::Values("float"));

// Integer sums do not depend on the order of the additions: the same particles in a shuffled order give the
// same grid sums to the last bit.
TEST_F(SimulationTest, ParticleToGridIsOrderIndependent) {
  const Scene scene = sceneFromJson(boxScene(R"({"kernel": "cubic"})", "[0.3, 1.0, -0.7]", "[]"));
  std::vector<firn::ParticleSeed> seeds = firn::sampleBodies(scene);
  Simulation ordered(scene, seeds, gl());
  const firn::GridTotals orderedTotals = ordered.transferToGrid();
  std::shuffle(seeds.begin(), seeds.end(), std::mt19937(7));
  Simulation shuffled(scene, seeds, gl());
  const firn::GridTotals shuffledTotals = shuffled.transferToGrid();
  EXPECT_EQ(orderedTotals.massKg, shuffledTotals.massKg);
  EXPECT_EQ(orderedTotals.momentumKgMPerS, shuffledTotals.momentumKgMPerS);
}

// A block in free fall moves rigidly (∇v = 0, so the snow never deforms), and its centre of mass follows the
// discrete trajectory of symplectic Euler: x_n = x0 + v0 t + ½ g t² + ½ g Δt t. That differs from the exact
// x0 + v0 t + ½ g t² by ½|g| Δt t, the tolerance against the exact parabola; against the discrete one the
// tolerance is float32 accumulation over the steps, 200 steps × 2⁻²⁴ × 1 m ≈ 1.2e-5 m, rounded up to 5e-5.
// The velocity stays v0 + g t up to the zero-mean noise of dithered fixed-point rounding: one contribution
// errs by at most a quantum, 2⁻²³ momentum units = 2⁻²³ · (h/Δt) / (8 particles per cell) ≈ 7.5e-7 m/s at a
// node; 216 contributions per node give σ ≈ √(216/12) · 7.5e-7 ≈ 3.2e-6 m/s, and a random walk over 200 steps
// ≈ 4.5e-5 m/s. Tolerance 5e-5 m/s (measured: 7e-6 PIC/FLIP, 1.5e-5 APIC). Undithered, biased rounding lost
// up to 1.4e-4 m/s here.
TEST_F(SimulationTest, FreeFallFollowsBallisticTrajectory) {
  for (const char* solver : {R"({"transfer": "pic_flip"})", R"({"transfer": "apic", "kernel": "quadratic"})"}) {
    const Scene scene = sceneFromJson(boxScene(solver, "[0.5, 2.0, -0.25]", "[]"));
    Simulation simulation(scene, firn::sampleBodies(scene), gl());
    const Totals start = particleTotals(simulation.snapshot());
    const double t = 0.2;
    simulation.advanceTo(t);
    simulation.checkWatchdog();
    const Totals end = particleTotals(simulation.snapshot());

    const glm::dvec3 v0(0.5, 2.0, -0.25);
    const glm::dvec3 g = scene.gravityMPerS2;
    const double dt = scene.time.dtS;
    const glm::dvec3 exact = start.centerOfMassM + v0 * t + 0.5 * g * t * t;
    const glm::dvec3 discrete = exact + 0.5 * g * dt * t;
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(end.centerOfMassM[axis], discrete[axis], 5e-5) << solver << " axis " << axis;
      EXPECT_NEAR(end.centerOfMassM[axis], exact[axis], 0.5 * glm::length(g) * dt * t + 5e-5) << solver;
      EXPECT_NEAR(end.momentum[axis] / end.massKg, v0[axis] + g[axis] * t, 5e-5) << solver << " axis " << axis;
    }
  }
}

// Snow dropped on a ground plane never goes through it: particles moving into a collider lose their normal
// velocity before they move, so for a plane (a linear SDF) y never drops below the plane. Tolerance: float32
// rounding of positions near 0.3 m, 1e-6 m. The snow must also have landed: its centre is within one
// block height of the plane and its momentum has nearly vanished.
TEST_F(SimulationTest, NothingPenetratesGroundPlane) {
  for (const char* boundary : {"slip", "sticky", "separate"}) {
    const std::string colliders = std::string(R"([{ "type": "plane", "point": [0, 0.3, 0], "normal": [0, 1, 0],
                                                    "friction": 0.3, "boundary": ")") + boundary + R"(" }])";
    const Scene scene = sceneFromJson(boxScene(R"({"kernel": "quadratic"})", "[0.4, -1.0, 0]", colliders,
                                               "[0.7, 0.4, 0.7]", "[0.9, 0.6, 0.9]"));
    Simulation simulation(scene, firn::sampleBodies(scene), gl());
    float lowest = std::numeric_limits<float>::max();
    for (int frame = 1; frame <= 15; ++frame) {
      simulation.advanceTo(frame / scene.time.frameRateHz);
      lowest = std::min(lowest, particleTotals(simulation.snapshot()).minY);
    }
    simulation.checkWatchdog();
    EXPECT_GE(lowest, 0.3f - 1e-6f) << boundary;
    const Totals end = particleTotals(simulation.snapshot());
    EXPECT_LT(end.centerOfMassM.y, 0.3 + 0.2) << boundary;
    EXPECT_LT(std::abs(end.momentum.y) / end.massKg, 0.1) << boundary;  // from 1 m/s + g t at impact
  }
}

// A ball of snow falling on a sphere collider stays outside it. The projection acts on the predicted
// position, so along a curved surface a particle may end a step inside by the chord error
// (|v| Δt)² / (2R) = (3 m/s · 1e-3 s)² / 0.3 m = 3e-5 m; tolerance 1e-4 m.
TEST_F(SimulationTest, NothingPenetratesSphereOrBoxCollider) {
  const std::string colliders = R"([
      { "type": "sphere", "center": [0.5, 0.5, 0.8], "radius": 0.15, "boundary": "slip", "friction": 0.2 },
      { "type": "box", "min": [1.0, 0.3, 0.65], "max": [1.3, 0.5, 0.95], "boundary": "separate" } ])";
  std::string json = boxScene(R"({"kernel": "quadratic", "transfer": "apic"})", "[0, -1.0, 0]", colliders,
                              "[0.42, 0.75, 0.72]", "[0.58, 0.85, 0.88]");
  // A second block above the box collider.
  json.replace(json.find("} ],"), 4, R"(}, { "shape": "box", "min": [1.08, 0.7, 0.72], "max": [1.22, 0.8, 0.88],
               "material": "snow", "velocity": [0, -1.0, 0] } ],)");
  const Scene scene = sceneFromJson(json);
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  double deepestInSphere = 0, deepestInBox = 0;
  for (int frame = 1; frame <= 15; ++frame) {
    simulation.advanceTo(frame / scene.time.frameRateHz);
    const firn::ParticleSnapshot s = simulation.snapshot();
    for (std::size_t i = 0; i < s.size(); ++i) {
      const glm::dvec3 x(s.positionMass[i]);
      deepestInSphere = std::max(deepestInSphere, 0.15 - glm::length(x - glm::dvec3(0.5, 0.5, 0.8)));
      const glm::dvec3 lo(1.0, 0.3, 0.65), hi(1.3, 0.5, 0.95);
      const glm::dvec3 inside = glm::min(x - lo, hi - x);
      deepestInBox = std::max(deepestInBox, std::min({inside.x, inside.y, inside.z}));
    }
  }
  simulation.checkWatchdog();
  EXPECT_LT(deepestInSphere, 1e-4);
  EXPECT_LT(deepestInBox, 1e-4);
}

// Two runs of the same scene give identical particle state, bit for bit: fixed-point sums are exact and
// order-independent, and nothing else in a step depends on scheduling.
TEST_F(SimulationTest, TwoRunsAreBitwiseIdentical) {
  const std::string colliders = R"([{ "type": "plane", "point": [0, 0.3, 0], "normal": [0, 1, 0], "friction": 0.5 }])";
  const Scene scene = sceneFromJson(boxScene(R"({"kernel": "cubic", "transfer": "pic_flip"})", "[2, -3, 1]", colliders,
                                             "[0.7, 0.35, 0.7]", "[0.9, 0.55, 0.9]"));
  std::vector<std::vector<glm::vec4>> runs;
  for (int run = 0; run < 2; ++run) {
    Simulation simulation(scene, firn::sampleBodies(scene), gl());
    simulation.advanceTo(0.06);
    simulation.checkWatchdog();
    const firn::ParticleSnapshot s = simulation.snapshot();
    std::vector<glm::vec4> state = s.positionMass;
    state.insert(state.end(), s.velocityVolume.begin(), s.velocityVolume.end());
    runs.push_back(state);
  }
  ASSERT_EQ(runs[0].size(), runs[1].size());
  EXPECT_EQ(0, std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(glm::vec4)));
}

// A body at 2 km/s crosses 40 cells per step: its momentum sums leave the fixed-point range, which the GPU
// detects as it happens; the error names the overflow, the step and what to change.
TEST_F(SimulationTest, FixedPointOverflowIsReported) {
  const Scene scene = sceneFromJson(boxScene(R"({"kernel": "quadratic"})", "[2000, 0, 0]", "[]"));
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  simulation.step(scene.time.dtS);
  const std::string message = watchdogMessage(simulation);
  EXPECT_NE(message.find("fixed-point overflow of the P2G momentum x sum"), std::string::npos) << message;
  EXPECT_NE(message.find("step 0"), std::string::npos) << message;
  EXPECT_NE(message.find("Reduce time.dt"), std::string::npos) << message;
}

// A NaN in a particle's state is caught on the GPU, named (particle, body, material), and never stored.
TEST_F(SimulationTest, NonFiniteParticleIsReportedAndNeverStored) {
  const Scene scene = sceneFromJson(boxScene(R"({"transfer": "pic_flip"})", "[0, 0, 0]", "[]"));
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  simulation.step(scene.time.dtS);
  simulation.checkWatchdog();
  firn::SimulationProbe(simulation).setParticleVelocity(17, glm::vec3(std::numeric_limits<float>::quiet_NaN(), 0, 0));
  simulation.step(scene.time.dtS);
  const std::string message = watchdogMessage(simulation);
  EXPECT_NE(message.find("step 1"), std::string::npos) << message;
  EXPECT_NE(message.find("particle 17 of bodies[0] (material \"snow\")"), std::string::npos) << message;
  EXPECT_NE(message.find("non-finite"), std::string::npos) << message;
  // The NaN stayed where it was injected: no other particle received one through the grid.
  const firn::ParticleSnapshot s = simulation.snapshot();
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (i == 17) continue;
    ASSERT_TRUE(std::isfinite(s.velocityVolume[i].x) && std::isfinite(s.positionMass[i].x)) << "particle " << i;
  }
}

// Snow thrown at a wall at 20 m/s compacts far past its critical compression within a few steps, and hardening
// e^{ξ(1 − J_P)} (unbounded) lifts its wave speed past the fixed step, well inside the scene's bound (2e-4 s against
// 8.95e-4 s, which assumes J_P ≥ 1 − θc). The watchdog names that, and the advice holds: with "adaptive" steps, which
// follow the hardened wave speed, the same impact stays finite past its first 0.04 s.
TEST_F(SimulationTest, SnowCompactedPastTheStepIsNamedAsTheCause) {
  for (const char* adaptive : {"false", "true"}) {
    const Scene scene = sceneFromJson(std::string(R"({ "grid": { "cells": [48, 32, 32], "cell_size": 0.02 },
      "time": { "dt": 2e-4, "frame_rate": 40, "adaptive": )") + adaptive + R"( },
      "solver": { "kernel": "quadratic", "transfer": "apic" }, "materials": { "snow": { "preset": "stomakhin" } },
      "bodies": [ { "shape": "sphere", "center": [0.3, 0.3, 0.32], "radius": 0.08, "material": "snow",
                    "velocity": [20, 0, 0] } ],
      "colliders": [ { "type": "plane", "point": [0.7, 0, 0], "normal": [-1, 0, 0], "friction": 1.0,
                       "boundary": "separate" } ] })");
    firn::SimulationOptions options;
    options.blockCapacity = 4096;
    Simulation simulation(scene, firn::sampleBodies(scene), gl(), options);
    simulation.advanceTo(0.04);
    if (std::string(adaptive) == "true") {
      simulation.checkWatchdog();
      const firn::ParticleSnapshot s = simulation.snapshot();
      EXPECT_EQ(firn::test::firstNonFiniteParticle(s), s.size());
      continue;
    }
    const std::string message = watchdogMessage(simulation);
    EXPECT_NE(message.find("Snow had compacted beyond what the step can take"), std::string::npos) << message;
    EXPECT_NE(message.find("reached J_P = "), std::string::npos) << message;
    EXPECT_NE(message.find("Set time.adaptive"), std::string::npos) << message;
  }
}

// Grid passes cover the region the particles occupy: the same snowball in a 48³ and a 192³ domain has the same
// active blocks, so the grid passes do the same work (the timing ratio is measured by benchmarks, not here).
TEST_F(SimulationTest, ActiveGridFollowsParticlesNotDomain) {
  std::vector<std::uint64_t> activeNodes;
  for (int cells : {48, 192}) {
    const std::string json = R"({
      "grid": { "cells": [)" + std::to_string(cells) + "," + std::to_string(cells) + "," + std::to_string(cells) +
                             R"(], "cell_size": 0.02 },
      "time": { "dt": 2e-4, "frame_rate": 30, "frames": 1 },
      "materials": { "snow": { "preset": "stomakhin" } },
      "bodies": [ { "shape": "sphere", "center": [0.48, 0.48, 0.48], "radius": 0.1, "material": "snow" } ] })";
    const Scene scene = sceneFromJson(json);
    Simulation simulation(scene, firn::sampleBodies(scene), gl());
    simulation.step(scene.time.dtS);
    activeNodes.push_back(static_cast<std::uint64_t>(simulation.blockUsage().lastStep) * firn::gpu::BLOCK_NODES);
  }
  EXPECT_EQ(activeNodes[0], activeNodes[1]);
  // A 0.2 m ball at h = 0.02 spans 10–11 cells; with the stencil margin its nodes span at most 15 a side, which
  // 4-node blocks cover with at most 5 a side.
  EXPECT_LE(activeNodes[0], 5u * 5u * 5u * std::uint64_t(firn::gpu::BLOCK_NODES));
  EXPECT_LT(activeNodes[1], 193ull * 193ull * 193ull / 1000ull);
}

// Particles added while running (the viewer's snowballs, within the capacity reserved up front) join the
// simulation at once: the grid sums count them (conservation tolerance as in ParticleToGridConservesMassAndMomentum)
// and they fall freely with everything else: after 0.1 s at rest, their velocity is g t to float32 noise (5e-5,
// as in FreeFallFollowsBallisticTrajectory). Adding more than the capacity is refused.
TEST_F(SimulationTest, AddedParticlesJoinTheGridAndFall) {
  const Scene scene = sceneFromJson(boxScene(R"({"transfer": "apic", "kernel": "quadratic"})", "[0, 0, 0]", "[]"));
  const std::vector<firn::ParticleSeed> seeds = firn::sampleBodies(scene);
  firn::SimulationOptions options;
  options.particleCapacity = 2 * seeds.size();
  Simulation simulation(scene, seeds, gl(), options);
  EXPECT_EQ(simulation.particleCapacity(), 2 * seeds.size());
  simulation.advanceTo(0.05);

  // The same box again, 0.5 m higher (clear of the first box's grid nodes, so neither drags the other), at rest.
  std::vector<firn::ParticleSeed> added = seeds;
  for (firn::ParticleSeed& seed : added) {
    seed.positionM.y += 0.5f;
    seed.bodyIndex = -1;
  }
  simulation.addParticles(added);
  ASSERT_EQ(simulation.particleCount(), 2 * seeds.size());
  const Totals particles = particleTotals(simulation.snapshot());
  const firn::GridTotals grid = simulation.transferToGrid();
  const auto& fp = simulation.fixedPoint();
  EXPECT_NEAR(grid.massKg, particles.massKg, double(simulation.particleCount()) * 27 * fp.resolution() * fp.referenceMassKg +
                                                 1e-6 * particles.massKg);

  simulation.advanceTo(0.15);
  simulation.checkWatchdog();
  const firn::ParticleSnapshot state = simulation.snapshot();
  double momentumY = 0, massKg = 0;
  for (std::size_t i = seeds.size(); i < state.size(); ++i) {
    momentumY += state.positionMass[i].w * state.velocityVolume[i].y;
    massKg += state.positionMass[i].w;
    // V0 = m / ρ for particles added while running.
    ASSERT_FLOAT_EQ(state.velocityVolume[i].w, state.positionMass[i].w / 400.0f);
  }
  EXPECT_NEAR(momentumY / massKg, scene.gravityMPerS2.y * 0.1, 5e-5);

  EXPECT_THROW(simulation.addParticles({seeds.front()}), std::length_error);
}

// An emitter body (start_frame 2, duration_frames 4 at 50 Hz) joins over 0.04–0.12 s: before its window only
// the other body is simulated, during it the count follows the release times exactly (a particle joins at the
// first step starting at or after its time), after it everything is in, and the grid carries all the mass
// (conservation tolerance as in ParticleToGridConservesMassAndMomentum).
TEST_F(SimulationTest, EmitterReleasesItsParticlesOverItsWindow) {
  const Scene scene = sceneFromJson(R"({
    "grid": { "cells": [32, 32, 32], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 50, "frames": 8 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [
      { "shape": "box", "min": [0.2, 0.2, 0.2], "max": [0.4, 0.4, 0.4], "material": "snow" },
      { "shape": "box", "min": [0.8, 0.9, 0.7], "max": [1.0, 1.1, 0.9], "material": "snow",
        "velocity": [0, -1, 0], "start_frame": 2, "duration_frames": 4 } ] })");
  const std::vector<firn::ParticleSeed> seeds = firn::sampleBodies(scene);
  std::size_t still = 0;
  for (const firn::ParticleSeed& seed : seeds) still += seed.bodyIndex == 0 ? 1 : 0;
  Simulation simulation(scene, seeds, gl());
  EXPECT_EQ(simulation.particleCount(), still);
  EXPECT_EQ(simulation.pendingParticleCount(), seeds.size() - still);

  for (int frame = 1; frame <= 7; ++frame) {
    const double timeS = frame / 50.0;
    simulation.advanceTo(timeS);
    // Released by the last step's start, t − dt.
    std::size_t expected = still;
    for (const firn::ParticleSeed& seed : seeds) {
      if (seed.bodyIndex == 1 && seed.releaseTimeS <= timeS - 1e-3 + 1e-12) ++expected;
    }
    EXPECT_EQ(simulation.particleCount(), expected) << "frame " << frame;
  }
  simulation.checkWatchdog();
  EXPECT_EQ(simulation.particleCount(), seeds.size());
  EXPECT_EQ(simulation.pendingParticleCount(), 0u);
  const Totals particles = particleTotals(simulation.snapshot());
  double seededKg = 0;
  for (const firn::ParticleSeed& seed : seeds) seededKg += seed.massKg;
  EXPECT_NEAR(particles.massKg, seededKg, 1e-6 * seededKg);
  const firn::GridTotals grid = simulation.transferToGrid();
  const auto& fp = simulation.fixedPoint();
  EXPECT_NEAR(grid.massKg, seededKg, double(seeds.size()) * 64 * fp.resolution() * fp.referenceMassKg + 1e-6 * seededKg);
}

// Adaptive stepping (time.adaptive) runs a scene whose fixed dt is unstable (E = 6e6 Pa; the CLI test shows it
// blowing up at dt = 1e-3 s) in steps of cfl · h / (|v| + c): the snow's wave speed at rest is
// c = sqrt((λ + 2μ) / ρ) = 129.1 m/s and the falling ball reaches under 1 m/s, so each step is 1.537e-4 to
// 1.549e-4 s and 0.1 s takes 646 to 651 steps (one more where the last two share what is left), landing
// exactly on 0.1 s.
TEST_F(SimulationTest, AdaptiveStepRunsAStiffSceneStablyAndLandsOnFrames) {
  const Scene scene = sceneFromJson(R"({
    "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 10, "frames": 1, "adaptive": true, "cfl": 0.4 },
    "materials": { "snow": { "preset": "stomakhin", "youngs_modulus": 6e6 } },
    "bodies": [ { "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.15, "material": "snow" } ] })");
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  const int steps = simulation.advanceTo(0.1);
  simulation.checkWatchdog();
  EXPECT_EQ(simulation.timeS(), 0.1);
  EXPECT_GE(steps, 646);
  EXPECT_LE(steps, 652);
}

// A body thrown at 40 m/s: the step is cfl · h / (|v| + c) = 0.4 · 0.05 / (40 + 19.7) = 3.35e-4 s (19.7 m/s is
// the reference snow's wave speed at rest), so 0.02 s takes 60 or 61 steps, with the watchdog quiet.
TEST_F(SimulationTest, AdaptiveStepFollowsTheFastestParticle) {
  const Scene scene = sceneFromJson(R"({
    "grid": { "cells": [32, 24, 24], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 50, "frames": 1, "adaptive": true },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "sphere", "center": [0.4, 0.6, 0.6], "radius": 0.15, "material": "snow",
                  "velocity": [40, 0, 0] } ] })");
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  const int steps = simulation.advanceTo(0.02);
  simulation.checkWatchdog();
  EXPECT_GE(steps, 60);
  EXPECT_LE(steps, 61);
  EXPECT_EQ(simulation.timeS(), 0.02);
}

// The state saved at a frame's start brings a failed stretch back exactly (what the adaptive retry relies on):
// a NaN injected after saving trips the watchdog; restored, the watchdog is quiet again and the same 0.02 s
// gives bit-identical particles to a run that never failed (the fixed-point sums are order independent).
TEST_F(SimulationTest, RestoredStateRedoesAStretchBitForBit) {
  const Scene scene = sceneFromJson(boxScene(R"({"transfer": "apic", "kernel": "quadratic"})", "[0.5, 1.0, 0]", "[]"));
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  simulation.advanceTo(0.01);
  simulation.saveState();
  simulation.advanceTo(0.03);
  const firn::ParticleSnapshot clean = simulation.snapshot();

  simulation.restoreState();
  EXPECT_EQ(simulation.timeS(), 0.01);
  firn::SimulationProbe(simulation).setParticleVelocity(3, glm::vec3(std::numeric_limits<float>::quiet_NaN()));
  simulation.advanceTo(0.03);
  EXPECT_THROW(simulation.checkWatchdog(), firn::SimulationError);

  simulation.restoreState();
  simulation.advanceTo(0.03);
  EXPECT_NO_THROW(simulation.checkWatchdog());
  const firn::ParticleSnapshot redone = simulation.snapshot();
  ASSERT_EQ(redone.size(), clean.size());
  for (std::size_t i = 0; i < clean.size(); ++i) {
    ASSERT_EQ(redone.positionMass[i], clean.positionMass[i]) << "particle " << i;
    ASSERT_EQ(redone.velocityVolume[i], clean.velocityVolume[i]) << "particle " << i;
  }
}

}  // namespace
