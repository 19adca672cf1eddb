// A long run at rest (issue "Numerical robustness": "snow resting on the ground for 20,000 steps keeps its height
// within 2%"). The source thesis's own snow slowly bloated over some thousands of steps; Firn's must not drift.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "GlTest.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"

namespace {

// The height of the block: the 99th percentile of the particles' y above the ground (a stray surface
// particle does not move it), and the centre of mass.
struct Height {
  double topM = 0;
  double centerM = 0;
};

Height measure(const firn::ParticleSnapshot& s, double groundM) {
  std::vector<float> y;
  double weighted = 0, mass = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    y.push_back(s.positionMass[i].y);
    weighted += double(s.positionMass[i].w) * s.positionMass[i].y;
    mass += s.positionMass[i].w;
  }
  std::nth_element(y.begin(), y.begin() + std::ptrdiff_t(0.99 * double(y.size())), y.end());
  return {double(y[std::size_t(0.99 * double(y.size()))]) - groundM, weighted / mass - groundM};
}

// A 0.1 × 0.2 × 0.1 m column of the reference snow (1,024 particles, 8 cells tall) on a sticky floor, 20,000
// steps of 2e-4 s.
// Under its own weight it compresses elastically by ρ g H / (2E) ≈ 0.3% on average (well inside the 2%, and
// below the plastic limit θc = 2.5%, so it does not compact); what the test guards against is drift: swelling
// from accumulated error in F_E or J_P, or sinking from a leaky floor.
TEST(Soak, SnowAtRestKeepsItsHeightFor20000Steps) {
  const firn::Scene scene = firn::parseScene(R"({
    "grid": { "cells": [24, 24, 24], "cell_size": 0.025 },
    "time": { "dt": 2e-4, "frame_rate": 10, "frames": 40 },
    "solver": { "kernel": "quadratic", "transfer": "apic" },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "box", "min": [0.25, 0.1, 0.25], "max": [0.35, 0.3, 0.35], "material": "snow" } ],
    "colliders": [ { "type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0], "boundary": "sticky" } ] })",
                                             "soak");
  firn::Simulation simulation(scene, firn::sampleBodies(scene), firn::test::glContext().info());
  const Height start = measure(simulation.snapshot(), 0.1);
  int steps = 0;
  for (int frame = 1; frame <= 40; ++frame) steps += simulation.advanceTo(frame / 10.0);
  simulation.checkWatchdog();
  EXPECT_EQ(steps, 20000);
  const Height end = measure(simulation.snapshot(), 0.1);
  std::printf("soak: top %.4f -> %.4f m, centre of mass %.4f -> %.4f m after %d steps\n", start.topM, end.topM,
              start.centerM, end.centerM, steps);
  EXPECT_NEAR(end.topM / start.topM, 1.0, 0.02);
  EXPECT_NEAR(end.centerM / start.centerM, 1.0, 0.02);
}

}  // namespace
