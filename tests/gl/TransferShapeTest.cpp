// The transfers' two shapes (sim/TransferShape.h), P2G's and the semi-implicit Hessian product's: tiles and blocks add
// the same quantized contributions, and integer sums do not depend on the order, so every shape must write the same
// bytes; a run picks the fastest by timing them.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "Error.h"
#include "GlTest.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"
#include "sim/TransferShape.h"

namespace {

using firn::Scene;
using firn::Simulation;
using firn::TransferShape;

Scene assetScene(const std::string& name) {
  return firn::loadScene(std::string(FIRN_SOURCE_DIR) + "/assets/scenes/" + name);
}

// What a run in one shape leaves: the grid of its first transfer (nondimensional integer sums, exact in double) and
// the particles after `steps` steps.
struct ShapeRun {
  std::vector<firn::GridNodeSums> grid;
  firn::ParticleSnapshot particles;
};

// A simulation given `shapes` (SimulationOptions::transferShapes; "": every shape).
firn::SimulationOptions inShapes(const std::string& shapes) {
  firn::SimulationOptions options;
  options.transferShapes = shapes;
  return options;
}

ShapeRun runInShape(const Scene& scene, const std::string& shape, int steps) {
  Simulation simulation(scene, firn::sampleBodies(scene), firn::test::glContext().info(), inShapes(shape));
  EXPECT_EQ(firn::transferShapeName(simulation.transferShapeChoice()->shape), shape);
  ShapeRun run;
  run.grid = simulation.readGridAfterTransfer();
  for (int step = 0; step < steps; ++step) simulation.step(scene.time.dtS);
  simulation.checkWatchdog();
  run.particles = simulation.snapshot();
  return run;
}

// Every shape took time, and `chosen` the least of it.
void expectKeptTheFastest(const std::vector<std::pair<TransferShape, double>>& timed, const TransferShape& chosen) {
  double chosenMs = -1;
  for (const auto& [shape, ms] : timed) {
    EXPECT_GT(ms, 0.0) << firn::transferShapeName(shape);
    if (shape == chosen) chosenMs = ms;
  }
  for (const auto& [shape, ms] : timed) EXPECT_LE(chosenMs, ms) << firn::transferShapeName(shape);
}

bool sameGrid(const std::vector<firn::GridNodeSums>& a, const std::vector<firn::GridNodeSums>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].node != b[i].node || a[i].massKg != b[i].massKg || a[i].momentumKgMPerS != b[i].momentumKgMPerS) {
      return false;
    }
  }
  return true;
}

// Every shape against tiles, on scenes that between them take each kernel with each transfer, every material model,
// each collider kind, rigid bodies, emitters, the adaptive steps' momentum unit and the semi-implicit solve (its
// Hessian product in the same shape): the first transfer's node sums and the particles after 12 steps, to the bit
// (integer sums either agree or they do not). Each shape reads its own sort (the bins scanned by a work group per
// block for blocks, an invocation per block for tiles), so a wrong offset in either would scatter wrong particles.
TEST(TransferShape, EveryShapeWritesTheSameBytesAsTiles) {
  std::vector<std::pair<std::string, Scene>> scenes;
  for (const char* name : {"snowball_wall.json", "bunny_small.json", "mixed_materials.json", "sand_column.json",
                           "water_dam_break.json", "elastic_bodies.json", "plough.json", "paddle_drum.json",
                           "boulder_bank.json", "snow_stream.json"}) {
    scenes.emplace_back(name, assetScene(name));
  }
  Scene semiImplicit = assetScene("snowball_wall.json");
  semiImplicit.solver.integrator = firn::Integrator::SemiImplicit;
  semiImplicit.time.dtS = 1e-3;
  scenes.emplace_back("snowball_wall.json, semi-implicit", semiImplicit);
  Scene adaptive = assetScene("snowball_wall.json");
  adaptive.time.adaptive = true;
  scenes.emplace_back("snowball_wall.json, adaptive", adaptive);
  Scene cubicFlip = assetScene("bunny_small.json");
  cubicFlip.solver.kernel = firn::Kernel::Cubic;
  cubicFlip.solver.transfer = firn::Transfer::PicFlip;
  scenes.emplace_back("bunny_small.json, cubic PIC/FLIP", cubicFlip);
  Scene cubicApic = assetScene("mixed_materials.json");
  cubicApic.solver.kernel = firn::Kernel::Cubic;
  scenes.emplace_back("mixed_materials.json, cubic APIC", cubicApic);

  for (const auto& [name, scene] : scenes) {
    const std::vector<TransferShape> shapes = firn::transferShapes(scene);
    ASSERT_EQ(shapes.size(), 4u) << name << ": fixed-point scenes take tiles and three block sizes";
    const ShapeRun tiles = runInShape(scene, "tiles", 12);
    ASSERT_FALSE(tiles.grid.empty()) << name;
    for (std::size_t i = 1; i < shapes.size(); ++i) {
      const std::string shape = firn::transferShapeName(shapes[i]);
      const ShapeRun other = runInShape(scene, shape, 12);
      EXPECT_TRUE(sameGrid(tiles.grid, other.grid)) << name << ": the first transfer's node sums by " << shape;
      EXPECT_TRUE(firn::test::sameBytes(tiles.particles, other.particles))
          << name << ": particles after 12 steps by " << shape;
    }
  }
}

// Unforced, a run times every shape on its first particles and keeps the fastest it measured; "blocks" times the
// block sizes only.
TEST(TransferShape, ARunKeepsTheFastestShapeItTimed) {
  const Scene scene = firn::defaultScene();
  Simulation simulation(scene, firn::sampleBodies(scene), firn::test::glContext().info());
  const std::optional<firn::TransferShapeChoice>& choice = simulation.transferShapeChoice();
  ASSERT_TRUE(choice.has_value());
  EXPECT_FALSE(choice->forced);
  ASSERT_EQ(choice->msPerTransfer.size(), 4u);
  expectKeptTheFastest(choice->msPerTransfer, choice->shape);
  EXPECT_NE(choice->describe().find("faster than"), std::string::npos) << choice->describe();

  // "blocks" times the block sizes alone (the benchmarks' blocks rows).
  Simulation blocksOnly(scene, firn::sampleBodies(scene), firn::test::glContext().info(), inShapes("blocks"));
  const std::optional<firn::TransferShapeChoice>& blocksChoice = blocksOnly.transferShapeChoice();
  ASSERT_TRUE(blocksChoice.has_value());
  EXPECT_TRUE(blocksChoice->forced);
  ASSERT_EQ(blocksChoice->msPerTransfer.size(), 3u);
  for (const auto& [shape, ms] : blocksChoice->msPerTransfer) EXPECT_EQ(shape.kind, TransferShape::Kind::Blocks);
  EXPECT_EQ(blocksChoice->shape.kind, TransferShape::Kind::Blocks);
}

// A semi-implicit run times its Hessian product in every shape too, on its own, keeps the fastest, and says so; its
// particles after a few steps are the bytes of a run forced to tiles (the shapes agree, whichever were kept).
TEST(TransferShape, ASemiImplicitRunTimesItsProductToo) {
  Scene scene = assetScene("snowball_wall.json");
  scene.solver.integrator = firn::Integrator::SemiImplicit;
  scene.time.dtS = 1e-3;
  Simulation simulation(scene, firn::sampleBodies(scene), firn::test::glContext().info());
  const std::optional<firn::TransferShapeChoice>& choice = simulation.transferShapeChoice();
  ASSERT_TRUE(choice.has_value());
  ASSERT_EQ(choice->msPerProduct.size(), 4u);
  expectKeptTheFastest(choice->msPerProduct, choice->productShape);
  EXPECT_NE(choice->describe().find("; Hessian product by " + firn::transferShapeName(choice->productShape)),
            std::string::npos)
      << choice->describe();
  for (int step = 0; step < 6; ++step) simulation.step(scene.time.dtS);
  simulation.checkWatchdog();
  EXPECT_TRUE(firn::test::sameBytes(simulation.snapshot(), runInShape(scene, "tiles", 6).particles))
      << choice->describe();
}

// A scene whose particles all come from an emitter has none to time at first: it times the shapes at its first step
// with particles, and again each time they have grown fourfold, since the faster shape can change with the count.
// Float sums depend on their order, so a float scene keeps the tiles and blocks are refused for it.
TEST(TransferShape, EmittersTimeTheShapesAsTheirParticlesGrowAndFloatSumsKeepTiles) {
  const Scene stream = firn::parseScene(R"({
    "grid": { "cells": [30, 40, 30], "cell_size": 0.02 },
    "time": { "dt": 2e-4, "frame_rate": 30, "frames": 9 },
    "materials": { "slush": { "preset": "slushy" } },
    "bodies": [ { "shape": "box", "min": [0.25, 0.2, 0.25], "max": [0.35, 0.7, 0.35], "material": "slush",
                  "velocity": [0, -2, 0], "start_frame": 1, "duration_frames": 8 } ] })",
                                        "a column released over frames 1 to 9");
  Simulation simulation(stream, firn::sampleBodies(stream), firn::test::glContext().info());
  ASSERT_EQ(simulation.particleCount(), 0u) << "the column is released from frame 1 on, none at the start";
  EXPECT_FALSE(simulation.transferShapeChoice().has_value());
  int step = 0;
  for (; step < 500 && !simulation.transferShapeChoice(); ++step) simulation.step(stream.time.dtS);
  ASSERT_TRUE(simulation.transferShapeChoice().has_value());
  const std::size_t firstTimedOn = simulation.transferShapeChoice()->particles;
  EXPECT_EQ(simulation.transferShapeChoice()->msPerTransfer.size(), 4u);
  EXPECT_GT(firstTimedOn, 0u);
  for (; step < 1500 && simulation.particleCount() < 4 * firstTimedOn; ++step) simulation.step(stream.time.dtS);
  ASSERT_GE(simulation.particleCount(), 4 * firstTimedOn) << "the column grows fourfold within its frames";
  simulation.step(stream.time.dtS);
  EXPECT_GE(simulation.transferShapeChoice()->particles, 4 * firstTimedOn) << "timed again after the growth";

  Scene floatSums = firn::defaultScene();
  floatSums.solver.atomics = firn::Atomics::Float;
  ASSERT_EQ(firn::transferShapes(floatSums).size(), 1u);
  EXPECT_EQ(firn::transferShapes(floatSums)[0].kind, TransferShape::Kind::Tiles);
  try {
    (void)firn::transferShapeCandidates(floatSums, "blocks-128");
    FAIL() << "blocks were accepted for float sums";
  } catch (const firn::InputError& error) {
    EXPECT_NE(std::string(error.what()).find("transfer shape blocks-128: blocks sum in fixed point only"),
              std::string::npos)
        << error.what();
  }
}

TEST(TransferShape, AnUnknownShapeIsBadInputListingTheShapes) {
  try {
    (void)firn::transferShapeCandidates(firn::defaultScene(), "warps");
    FAIL() << "\"warps\" was accepted";
  } catch (const firn::InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("transfer shape: expected one of"), std::string::npos) << message;
    EXPECT_NE(message.find("blocks-256"), std::string::npos) << message;
    EXPECT_NE(message.find("\"warps\""), std::string::npos) << message;
  }
}

}  // namespace
