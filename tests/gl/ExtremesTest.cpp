// Numerics at the extremes (issue "Numerical robustness", part 6): each case either runs stably, with finite
// state and bounded energy, or stops the way the contract says: exit 2 from the pre-flight check when the step
// is far beyond its bound, exit 3 (SimulationError) from the watchdog, with the expected message. Small scenes
// (a 0.2 m ball of about 500 particles on a 24³ grid of 5 cm cells), a few hundred to a few thousand steps.
#include <gtest/gtest.h>

#include <cmath>
#include <ostream>
#include <string>

#include <glm/geometric.hpp>

#include "Error.h"
#include "GlTest.h"
#include "run/Preflight.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"

namespace {

enum class Expect { Stable, PreflightRefuses, WatchdogStops };

struct Case {
  const char* name;
  std::string material;  // the snow material's keys
  std::string time;      // the "time" object's extra keys
  std::string body;      // the ball's extra keys
  double durationS;
  Expect expect;
  const char* message = "";  // a fragment the refusal or the watchdog's message must hold
};

// gtest prints a failing case by its name, not its bytes.
void PrintTo(const Case& c, std::ostream* out) { *out << c.name; }

firn::Scene sceneFor(const Case& c) {
  return firn::parseScene(R"({
    "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
    "time": { "frame_rate": 50, "frames": 1, )" + c.time + R"( },
    "solver": { "kernel": "quadratic", "transfer": "apic" },
    "materials": { "snow": { "preset": "stomakhin" )" + (c.material.empty() ? "" : ", " + c.material) + R"( } },
    "bodies": [ { "shape": "sphere", "center": [0.6, 0.4, 0.6], "radius": 0.1, "material": "snow" )" + c.body + R"( } ],
    "colliders": [ { "type": "plane", "point": [0, 0.2, 0], "normal": [0, 1, 0], "friction": 0.3 } ] })",
                          c.name);
}

// Kinetic plus gravitational potential energy above the ground plane (J).
double mechanicalEnergyJ(const firn::ParticleSnapshot& s) {
  double energy = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double m = s.positionMass[i].w;
    const glm::dvec3 v(s.velocityVolume[i]);
    energy += 0.5 * m * glm::dot(v, v) + m * 9.81 * (double(s.positionMass[i].y) - 0.2);
  }
  return energy;
}

class Extremes : public ::testing::TestWithParam<Case> {
 protected:
  static void SetUpTestSuite() { firn::test::glContext(); }
};

TEST_P(Extremes, StableOrStoppedAsTheContractSays) {
  const Case& c = GetParam();
  const firn::Scene scene = sceneFor(c);
  const std::vector<firn::ParticleSeed> seeds = firn::sampleBodies(scene);
  if (c.expect == Expect::PreflightRefuses) {
    try {
      firn::preflight(scene, seeds);
      FAIL() << "expected the pre-flight check to refuse the scene";
    } catch (const firn::InputError& error) {
      EXPECT_NE(std::string(error.what()).find(c.message), std::string::npos) << error.what();
    }
    return;
  }
  EXPECT_NO_THROW(firn::preflight(scene, seeds));
  firn::Simulation simulation(scene, seeds, firn::test::glContext().info());
  const double startEnergyJ = mechanicalEnergyJ(simulation.snapshot());
  simulation.advanceTo(c.durationS);
  if (c.expect == Expect::WatchdogStops) {
    try {
      simulation.checkWatchdog();
      FAIL() << "expected the watchdog to stop the run";
    } catch (const firn::SimulationError& error) {
      EXPECT_NE(std::string(error.what()).find(c.message), std::string::npos) << error.what();
    }
    return;
  }
  ASSERT_NO_THROW(simulation.checkWatchdog());
  const firn::ParticleSnapshot end = simulation.snapshot();
  ASSERT_EQ(firn::test::firstNonFiniteParticle(end), end.size()) << "a particle is not finite";
  // Collisions, plasticity and the transfers only dissipate; elastic energy stored in the body is at most what
  // the motion brought. 10% over the start allows the elastic energy of a body squeezed at the end, and the
  // float rounding of the sums.
  EXPECT_LE(mechanicalEnergyJ(end), 1.1 * startEnergyJ + 1e-9);
}

const char* const kAdaptive = R"("dt": 1e-3, "adaptive": true)";
const char* const kFixed = R"("dt": 1e-3)";
const char* const kFalling = R"(, "velocity": [0, -3, 0])";

INSTANTIATE_TEST_SUITE_P(
    Table, Extremes,
    ::testing::Values(
        // Young's modulus from 1e3 to 1e10 Pa.
        Case{"SoftE1e3", R"("youngs_modulus": 1e3)", kFixed, kFalling, 0.1, Expect::Stable},
        Case{"StiffE1e10FixedDtIsRefused", R"("youngs_modulus": 1e10)", kFixed, "", 0.01, Expect::PreflightRefuses,
             "time.dt: 0.001 s is"},
        Case{"StiffE1e10Adaptive", R"("youngs_modulus": 1e10)", kAdaptive, kFalling, 0.004, Expect::Stable},
        Case{"StiffE1e7FixedDtBlowsUp", R"("youngs_modulus": 1e7)", kFixed, kFalling, 0.05, Expect::WatchdogStops,
             "Reduce time.dt"},
        // Poisson's ratio from 0 to 0.49 (λ grows as 1/(1 − 2ν)).
        Case{"PoissonZero", R"("poisson_ratio": 0)", kAdaptive, kFalling, 0.1, Expect::Stable},
        Case{"PoissonNearlyIncompressible", R"("poisson_ratio": 0.49)", kAdaptive, kFalling, 0.05, Expect::Stable},
        // Time steps from 1e-6 to 1e-2 s.
        Case{"TinyDt", "", R"("dt": 1e-6)", kFalling, 0.002, Expect::Stable},
        Case{"HugeDtIsRefused", "", R"("dt": 1e-2)", "", 0.02, Expect::PreflightRefuses, "times the elastic bound"},
        // Impacts up to 200 m/s.
        Case{"Impact200MetresPerSecondAdaptive", "", kAdaptive, R"(, "velocity": [0, -200, 0])", 0.004, Expect::Stable},
        Case{"Impact200MetresPerSecondFixedDtIsStopped", "", R"("dt": 2.6e-4)", R"(, "velocity": [0, -200, 0])", 0.004,
             Expect::WatchdogStops, "cells in one step"},
        // 1 to 64 particles per cell.
        Case{"OneParticlePerCell", "", kAdaptive, R"(, "velocity": [0, -3, 0], "particles_per_cell": 1)", 0.1, Expect::Stable},
        Case{"SixtyFourParticlesPerCell", "", kAdaptive, R"(, "velocity": [0, -3, 0], "particles_per_cell": 64)", 0.03,
             Expect::Stable},
        // Critical compression and stretch from 0 (all plastic) to 0.5, hardening up to 50.
        Case{"ThetaZero", R"("critical_compression": 0, "critical_stretch": 0)", kAdaptive, kFalling, 0.1, Expect::Stable},
        Case{"ThetaHalf", R"("critical_compression": 0.5, "critical_stretch": 0.5)", kAdaptive, kFalling, 0.1,
             Expect::Stable},
        Case{"HardeningFifty", R"("hardening": 50)", kAdaptive, kFalling, 0.1, Expect::Stable},
        // Nearly degenerate F: a very soft ball slammed into the ground flattens to a sheet.
        Case{"NearlyDegenerateF", R"("youngs_modulus": 1e3, "critical_compression": 0.9, "critical_stretch": 5,
                                    "hardening": 0)",
             kAdaptive, R"(, "velocity": [0, -20, 0])", 0.05, Expect::Stable}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

}  // namespace
