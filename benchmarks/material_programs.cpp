// What "a scene pays only for what it uses" is worth: a snow-only and a water-only scene stepped with programs
// built for their own material (the default) and with programs that carry every model and F for every
// particle, as one general build would. Both configurations are timed in the same run, interleaved, and the
// median of the repeats is kept (the machines are shared and noisy; read the ratio). Writes a CSV to stdout.
// Usage: firn_material_programs [steps per repeat] [repeats]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "gl/Context.h"
#include "gl/GL.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"

namespace {

double millisecondsPerStep(firn::Simulation& simulation, int steps) {
  glFinish();
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) simulation.step(simulation.scene().time.dtS);
  glFinish();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / steps;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// Water at rest in a tank, about as many particles as the built-in snowball.
firn::Scene waterScene() {
  return firn::parseScene(R"({
    "name": "water-tank",
    "grid": { "cells": [64, 48, 48], "cell_size": 0.02 },
    "time": { "dt": 2e-4, "frame_rate": 30, "frames": 1 },
    "solver": { "kernel": "quadratic", "transfer": "apic" },
    "materials": { "water": { "model": "water", "density": 1000, "bulk_modulus": 1e5, "gamma": 7 } },
    "bodies": [ { "shape": "box", "min": [0.3, 0.06, 0.3], "max": [0.6, 0.26, 0.6], "material": "water" } ],
    "colliders": [ { "type": "plane", "point": [0, 0.06, 0], "normal": [0, 1, 0], "boundary": "slip" } ] })",
                          "water tank");
}

}  // namespace

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 200;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 5;
  firn::gl::HeadlessContext context;
  std::printf("scene,particles,programs,ms_per_step,ratio_to_scene_models,renderer\n");
  for (const firn::Scene& scene : {firn::defaultScene(), waterScene()}) {
    const std::vector<firn::ParticleSeed> seeds = firn::sampleBodies(scene);
    firn::Simulation own(scene, seeds, context.info());
    firn::SimulationOptions everyModel;
    everyModel.programs = firn::MaterialPrograms::EveryModel;
    firn::Simulation every(scene, seeds, context.info(), everyModel);
    millisecondsPerStep(own, steps / 4);  // warm-up: the first dispatch of each program compiles it
    millisecondsPerStep(every, steps / 4);
    std::vector<double> ownMs, everyMs;
    for (int repeat = 0; repeat < repeats; ++repeat) {
      ownMs.push_back(millisecondsPerStep(own, steps));
      everyMs.push_back(millisecondsPerStep(every, steps));
    }
    own.checkWatchdog();
    every.checkWatchdog();
    const double ownMedian = median(ownMs), everyMedian = median(everyMs);
    for (const auto& [name, ms] : {std::pair{"scene models", ownMedian}, std::pair{"every model", everyMedian}}) {
      std::printf("%s,%zu,%s,%.3f,%.3f,%s\n", scene.name.c_str(), seeds.size(), name, ms, ms / ownMedian,
                  context.info().renderer.c_str());
    }
  }
  return 0;
}
