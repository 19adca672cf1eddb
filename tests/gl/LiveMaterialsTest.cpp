// Materials changed while a scene runs (Simulation::setMaterials, the scene editor's live materials): a change the
// step can take applies at the next step, and one that needs the scene sampled or compiled again is refused with the
// key that says why.
#include <gtest/gtest.h>

#include <string>

#include "Error.h"
#include "GlTest.h"
#include "scene/Sampling.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"

namespace firn {
namespace {

// A ball of Stomakhin's snow falling for 20 steps of 1 ms. Its elastic bound h / c is 0.05 m / 22.35 m/s = 2.24 ms.
const char* const kBall = R"({
  "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
  "time": { "dt": 1e-3, "frame_rate": 50, "frames": 2 },
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "sphere", "center": [0.6, 0.3, 0.6], "radius": 0.15, "material": "snow",
                "velocity": [0, -2, 0] } ] })";

bool unstableWithin(Simulation& simulation, int steps) {
  for (int s = 0; s < steps; ++s) {
    simulation.step(1e-3);
    try {
      simulation.checkWatchdog();
    } catch (const SimulationError&) {
      return true;
    }
  }
  return false;
}

// The ball lands at 2 m/s. With E 400 times larger, c is 20 times faster and the bound 0.11 ms: the 1 ms step is 9
// times beyond it, and the landing goes unstable within the 40 steps after the change; without the change, the same
// 40 steps are stable. So the step took the new modulus at once.
TEST(LiveMaterials, AStifferModulusAppliesAtTheNextStep) {
  const Scene scene = parseScene(kBall, "ball.json");
  const std::vector<ParticleSeed> seeds = sampleBodies(scene);
  Simulation unchanged(scene, seeds, test::glContext().info());
  Simulation stiffened(scene, seeds, test::glContext().info());
  for (Simulation* simulation : {&unchanged, &stiffened}) {
    for (int s = 0; s < 5; ++s) simulation->step(1e-3);
    simulation->checkWatchdog();
  }
  std::vector<Material> materials = scene.materials;
  materials[0].youngsModulusPa *= 400;
  stiffened.setMaterials(materials);
  EXPECT_FALSE(unstableWithin(unchanged, 40));
  EXPECT_TRUE(unstableWithin(stiffened, 40));
  // A softer one is stable: the energy account, started again at the change, holds.
  Simulation softened(scene, seeds, test::glContext().info());
  for (int s = 0; s < 5; ++s) softened.step(1e-3);
  softened.checkWatchdog();
  materials[0].youngsModulusPa = scene.materials[0].youngsModulusPa / 2;
  softened.setMaterials(materials);
  EXPECT_FALSE(unstableWithin(softened, 40));
}

// A density is the particles' mass and a model the passes compiled: both wait for a new start, and say so.
TEST(LiveMaterials, ChangesThatNeedANewStartAreRefusedByKey) {
  const Scene scene = parseScene(kBall, "ball.json");
  Simulation simulation(scene, sampleBodies(scene), test::glContext().info());
  std::vector<Material> denser = scene.materials;
  denser[0].densityKgPerM3 *= 2;
  try {
    simulation.setMaterials(denser);
    FAIL() << "a density changed live";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("ball.json: materials.snow.density: "), std::string::npos) << error.what();
  }
  std::vector<Material> elastic = scene.materials;
  elastic[0].model = MaterialModel::FixedCorotated;
  EXPECT_THROW(simulation.setMaterials(elastic), InputError);
  // What is refused changes nothing: a softer snow still applies after.
  std::vector<Material> softer = scene.materials;
  softer[0].youngsModulusPa /= 2;
  EXPECT_NO_THROW(simulation.setMaterials(softer));
}

}  // namespace
}  // namespace firn
