// The start both `firn run` and `firn view` make of a scene (run/SimulationSession.h): the particles sampled, what
// the pre-flight says, the simulation's room for particles added while running, a restart, and surface settings
// checked before anything is simulated.
#include <gtest/gtest.h>

#include <optional>
#include <sstream>
#include <string>

#include "Error.h"
#include "GlTest.h"
#include "render/Renderer.h"
#include "run/SimulationSession.h"
#include "scene/Sampling.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"
#include "surface/SurfaceReconstruction.h"

namespace firn {
namespace {

// A ball of 0.2 m radius at 8 particles per cell (cells 0.05 m): about 8 · (4π/3) 4³ = 2,145 particles.
const char* const kBallScene = R"({
  "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
  "time": { "dt": 1e-3, "frame_rate": 50, "frames": 2 },
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.2, "material": "snow" } ] })";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(SimulationSession, SamplesTheBodiesAndReportsTheStartUnderItsPrefix) {
  const Scene scene = parseScene(kBallScene, "ball.json");
  SessionOptions options;
  options.messagePrefix = "firn view";
  std::ostringstream log;
  SimulationSession session(scene, test::glContext().info(), options, log);
  // The bodies' particles, as sampling makes them outside a session.
  EXPECT_EQ(session.seeds().size(), sampleBodies(scene).size());
  EXPECT_EQ(session.simulation().particleCount(), session.seeds().size());
  const std::string particles = std::to_string(session.seeds().size()) + " particles, 24×24×24 cells, dt 0.001 s on ";
  EXPECT_TRUE(contains(log.str(), "firn view: ")) << log.str();
  EXPECT_TRUE(contains(log.str(), particles)) << log.str();
  EXPECT_TRUE(contains(log.str(), "firn view: stable time step: elastic bound")) << log.str();
  EXPECT_TRUE(contains(log.str(), "firn view: bodies[0]: 8 particles per cell")) << log.str();

  // With a last frame (a run's), the opening line gives the frames.
  options.messagePrefix = "firn";
  options.lastFrame = 2;
  std::ostringstream runLog;
  const SimulationSession run(scene, test::glContext().info(), options, runLog);
  EXPECT_TRUE(contains(runLog.str(), "dt 0.001 s, 2 frames on ")) << runLog.str();
  EXPECT_TRUE(contains(runLog.str(), "firn: bodies[0]: 8 particles per cell")) << runLog.str();
}

// The pictures draw the surface unless asked otherwise; surface settings that do not suit the particles (a kernel
// 24 reconstruction cells wide, twice the most) turn an unasked surface into particles with a note, and leave an
// asked mode as asked.
TEST(SimulationSession, PicturesDrawTheSurfaceUnlessItsSettingsDoNotSuit) {
  using render::RenderMode;
  const Scene scene = parseScene(kBallScene, "ball.json");
  std::ostringstream log;
  SimulationSession session(scene, test::glContext().info(), SessionOptions{}, log);
  EXPECT_EQ(session.pictureRenderMode(std::nullopt), RenderMode::Surface);
  EXPECT_EQ(session.pictureRenderMode(RenderMode::Particles), RenderMode::Particles);
  EXPECT_FALSE(contains(log.str(), "note: drawing the snow as particles")) << log.str();

  const std::string ball = kBallScene;
  const Scene wideKernel = parseScene(
      ball.substr(0, ball.rfind('}')) + R"(, "surface": { "resolution": 8, "smoothing": 6 } })", "wide.json");
  std::ostringstream wideLog;
  SimulationSession unsuited(wideKernel, test::glContext().info(), SessionOptions{}, wideLog);
  EXPECT_EQ(unsuited.pictureRenderMode(std::nullopt), RenderMode::Particles);
  EXPECT_TRUE(contains(wideLog.str(), "firn: note: drawing the snow as particles")) << wideLog.str();
  EXPECT_TRUE(contains(wideLog.str(), "surface.resolution")) << wideLog.str();
  EXPECT_EQ(unsuited.pictureRenderMode(RenderMode::Surface), RenderMode::Surface);
  EXPECT_THROW(unsuited.surface(), InputError) << "asked for, the surface stays an error";
}

TEST(SimulationSession, KeepsRoomForAddedParticlesAndRestartsFromTheBodies) {
  const Scene scene = parseScene(kBallScene, "ball.json");
  SessionOptions options;
  options.addedParticleCapacity = 100;
  std::ostringstream log;
  SimulationSession session(scene, test::glContext().info(), options, log);
  const std::size_t bodies = session.seeds().size();
  EXPECT_EQ(session.simulation().particleCapacity(), bodies + 100);
  std::vector<ParticleSeed> added(session.seeds().begin(), session.seeds().begin() + 100);
  for (ParticleSeed& particle : added) particle.bodyIndex = -1;
  session.simulation().addParticles(added);
  session.simulation().advanceTo(scene.time.dtS);
  EXPECT_EQ(session.simulation().particleCount(), bodies + 100);
  session.restart();
  EXPECT_EQ(session.simulation().particleCount(), bodies);
  EXPECT_EQ(session.simulation().stepCount(), 0u);
  EXPECT_EQ(session.simulation().timeS(), 0.0);
}

// 1,000 particles per cell are h / 10 apart: two spacings of kernel radius, h / 5, are narrower than a
// reconstruction cell at surface.resolution 1 (h).
TEST(SimulationSession, RefusesSurfaceSettingsThatDoNotSuitTheParticlesBeforeSimulating) {
  std::string json = kBallScene;
  json.replace(json.find("\"radius\": 0.2,"), 14, "\"radius\": 0.05, \"particles_per_cell\": 1000,");
  json.replace(json.find("\"materials\""), 0, "\"surface\": { \"resolution\": 1, \"smoothing\": 2 }, ");
  const Scene scene = parseScene(json, "fine.json");
  SessionOptions options;
  options.withSurface = true;
  std::ostringstream log;
  try {
    const SimulationSession session(scene, test::glContext().info(), options, log);
    FAIL() << "a kernel narrower than a reconstruction cell was accepted";
  } catch (const InputError& error) {
    EXPECT_TRUE(contains(error.what(), "surface.resolution: the smallest particles' kernel")) << error.what();
  }
  EXPECT_EQ(log.str(), "") << "nothing is reported before the checks pass";

  // Without a surface asked for at the start, the same scene runs, and asking for one later is refused alike.
  options.withSurface = false;
  SimulationSession session(scene, test::glContext().info(), options, log);
  EXPECT_THROW(session.surface(), InputError);
}

TEST(SimulationSession, MakesTheSurfaceOnceAndReportsIt) {
  const Scene scene = parseScene(kBallScene, "ball.json");
  SessionOptions options;
  options.withSurface = true;
  std::ostringstream log;
  SimulationSession session(scene, test::glContext().info(), options, log);
  EXPECT_FALSE(contains(log.str(), "surface: nodes")) << "made on first use, not before";
  surface::SurfaceReconstruction& surface = session.surface();
  EXPECT_EQ(&session.surface(), &surface);
  EXPECT_TRUE(contains(log.str(), "firn: surface: nodes 0.025 m apart (grid.cell_size / 2)")) << log.str();
}

}  // namespace
}  // namespace firn
