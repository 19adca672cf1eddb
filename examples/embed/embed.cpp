// Firn as a library: a block of snow in free fall, simulated headless and checked against g t²/2.
// Exit status: 0 the fall is right, 1 it is not, or Firn's own (2 bad input, 3 unstable, 4 no OpenGL 4.3).
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "Error.h"
#include "gl/Context.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"

namespace {

// A 0.3 m cube of snow (1,728 particles) at rest in a 0.8 m box of air, 0.25 m above the walls.
const char* const kScene = R"({
  "grid": { "origin": [0, 0, 0], "cells": [16, 16, 16], "cell_size": 0.05 },
  "time": { "dt": 1e-3, "frame_rate": 50, "frames": 5 },
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "box", "min": [0.25, 0.35, 0.25], "max": [0.55, 0.65, 0.55], "material": "snow" } ]
})";

glm::dvec3 centerOfMass(const firn::ParticleSnapshot& snapshot) {
  glm::dvec3 sum(0.0);
  double mass = 0;
  for (std::size_t i = 0; i < snapshot.size(); ++i) {
    sum += double(snapshot.positionMass[i].w) * glm::dvec3(snapshot.positionMass[i]);
    mass += snapshot.positionMass[i].w;
  }
  return sum / mass;
}

}  // namespace

int main() try {
  firn::gl::HeadlessContext context;  // EGL, no window: a GPU, or Mesa's llvmpipe
  std::printf("OpenGL: %s (%s)\n", context.info().renderer.c_str(), context.info().platform.c_str());

  const firn::Scene scene = firn::parseScene(kScene, "embed.cpp");
  firn::Simulation simulation(scene, firn::sampleBodies(scene), context.info());
  const glm::dvec3 start = centerOfMass(simulation.snapshot());
  std::printf("%zu particles, centre of mass at y = %.5f m\n", simulation.particleCount(), start.y);

  // Each frame is 1/50 s of steps no longer than dt; the watchdog throws SimulationError if anything blew up.
  for (int frame = 1; frame <= scene.time.frames; ++frame) {
    const double t = frame / scene.time.frameRateHz;
    const int steps = simulation.advanceTo(t);
    simulation.checkWatchdog();
    std::printf("t = %.2f s (%d steps): y = %.5f m\n", t, steps, centerOfMass(simulation.snapshot()).y);
  }

  // Free fall moves the block rigidly, so its centre of mass drops ½ g t², plus ½ g Δt t: symplectic Euler
  // updates the velocity before the position. Allowed: that lag, and 1e-4 m for float32 rounding.
  const double t = simulation.timeS(), g = glm::length(scene.gravityMPerS2), dt = scene.time.dtS;
  const double drop = start.y - centerOfMass(simulation.snapshot()).y;
  const double expected = 0.5 * g * t * t;
  const double tolerance = 0.5 * g * dt * t + 1e-4;
  std::printf("fell %.5f m in %.2f s; g t²/2 = %.5f m ± %.5f m\n", drop, t, expected, tolerance);
  if (!(std::abs(drop - expected) <= tolerance)) {
    std::fprintf(stderr, "embed: wrong fall (%.5f m, expected %.5f ± %.5f m)\n", drop, expected, tolerance);
    return 1;
  }
  std::printf("ok\n");
  return 0;
} catch (const firn::Error& error) {
  std::fprintf(stderr, "embed: %s\n", error.what());
  return static_cast<int>(error.code());
} catch (const std::exception& error) {
  std::fprintf(stderr, "embed: %s\n", error.what());
  return 1;
}
