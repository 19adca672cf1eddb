// The block-sparse grid (shaders/common/blocks.glsl): blocks claimed where particles' stencils reach, at the
// domain's edges too, released behind moving bodies, a pool that grows when the particles outgrow it, and tiles
// that are never cut short. The P2G sums on it are checked against the particles' own totals, with the
// fixed-point tolerance of SimulationTest.ParticleToGridConservesMassAndMomentum.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "Error.h"
#include "GlTest.h"
#include "gpu/GpuFunctions.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"
#include "sim/TransferShape.h"

namespace {

using firn::Scene;
using firn::Simulation;

class BlockGrid : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { firn::test::glContext(); }
  static const firn::gl::ContextInfo& gl() { return firn::test::glContext().info(); }
};

Scene sceneFromJson(const std::string& json) { return firn::parseScene(json, "test scene"); }

// Reference snow without gravity (`gravity` [0, 0, 0]) in a domain of `cells` cells of 0.05 m.
std::string scene(int cells, const std::string& solver, const std::string& bodies, const std::string& gravity = "[0, 0, 0]") {
  const std::string n = std::to_string(cells);
  return R"({
    "grid": { "origin": [0, 0, 0], "cells": [)" + n + "," + n + "," + n + R"(], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 50, "frames": 10 },
    "gravity": )" + gravity + R"(,
    "solver": )" + solver + R"(,
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": )" + bodies + "}";
}

std::string box(const glm::dvec3& min, const glm::dvec3& max, const glm::dvec3& velocity, double particlesPerCell = 8) {
  std::ostringstream out;
  out << R"({ "shape": "box", "min": [)" << min.x << "," << min.y << "," << min.z << R"(], "max": [)" << max.x << ","
      << max.y << "," << max.z << R"(], "velocity": [)" << velocity.x << "," << velocity.y << "," << velocity.z
      << R"(], "material": "snow", "particles_per_cell": )" << particlesPerCell << " }";
  return out.str();
}

struct Totals {
  double massKg = 0;
  glm::dvec3 momentum{0.0};
};

Totals particleTotals(const firn::ParticleSnapshot& s) {
  Totals t;
  for (std::size_t i = 0; i < s.size(); ++i) {
    t.massKg += s.positionMass[i].w;
    t.momentum += double(s.positionMass[i].w) * glm::dvec3(s.velocityVolume[i]);
  }
  return t;
}

// The grid's P2G sums equal the particles' totals to the fixed-point rounding of every contribution (one unit 2^-k
// each, dithered) plus float32 rounding of the weights (1e-6 relative), as in SimulationTest: every particle was
// scattered, whole, once.
void expectGridHoldsEveryParticle(Simulation& simulation, const std::string& where) {
  const Totals particles = particleTotals(simulation.snapshot());
  const firn::GridTotals grid = simulation.transferToGrid();
  const double stencilNodes = simulation.scene().solver.kernel == firn::Kernel::Cubic ? 64 : 27;
  const double contributions = double(simulation.particleCount()) * stencilNodes;
  const auto& fp = simulation.fixedPoint();
  const double massTolerance = contributions * fp.resolution() * fp.referenceMassKg + 1e-6 * particles.massKg;
  const double momentumTolerance =
      contributions * fp.resolution() * fp.momentumUnitKgMPerS + 1e-6 * glm::length(particles.momentum) + 1e-12;
  EXPECT_NEAR(grid.massKg, particles.massKg, massTolerance) << where;
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(grid.momentumKgMPerS[axis], particles.momentum[axis], momentumTolerance) << where << " axis " << axis;
  }
}

// Blocks at the domain's edges and corners: a box of snow pressed into each of the eight corners of a 20-cell
// domain (whose 21 nodes per axis leave the last block one node wide) reaches the first and the last blocks on
// every axis. For 40 steps every particle is scattered whole, none passes the positions G2P clamps particles to
// (a cell from the domain's edge), and the watchdog sees nothing.
TEST_F(BlockGrid, CornersOfTheDomainGetBlocks) {
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 side(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
    const glm::dvec3 min = 0.11 + side * 0.66;             // inside 0.1 m (2 cells) of walls, the box 0.12 m
    const glm::dvec3 velocity = (side * 2.0 - 1.0) * 1.5;  // into the corner, 0.03 cells per step
    const Scene s = sceneFromJson(scene(20, R"({"kernel": "cubic", "transfer": "pic_flip"})",
                                        "[" + box(min, min + 0.12, velocity) + "]"));
    Simulation simulation(s, firn::sampleBodies(s), gl());
    for (int step = 0; step < 40; ++step) simulation.step(s.time.dtS);
    simulation.checkWatchdog();
    expectGridHoldsEveryParticle(simulation, "corner " + std::to_string(corner));
    const firn::ParticleSnapshot particles = simulation.snapshot();
    for (std::size_t i = 0; i < particles.size(); ++i) {
      const glm::dvec3 x(particles.positionMass[i]);
      ASSERT_TRUE(glm::all(glm::greaterThanEqual(x, glm::dvec3(0.05))) && glm::all(glm::lessThanEqual(x, glm::dvec3(0.95))))
          << "corner " << corner << ", particle " << i << " at " << x.x << ", " << x.y << ", " << x.z;
    }
  }
}

// Particles crossing block boundaries every step: a rigid box moving at 0.9 cells per step, no gravity, no stress
// (it moves as one, so F stays I), crosses a block (4 cells) every 4–5 steps, 18 blocks in 80 steps. Its particles
// keep their velocity, so each ends at x0 + v t to float32 accumulation, every step's grid holds them all, and the
// blocks behind it are released: the pool's last step uses no more blocks than at the start.
// The accumulation has two parts. The position rounds each step, half an ulp at up to 4 m (2⁻²² m): 1.9e-5 m over
// 80 steps. The velocity G2P gives back is off by a few of its ulps (45 m/s: 2⁻¹⁸ m/s) each step: the node's
// momentum over its mass, a division GLSL allows 2.5 ulp, and the weights' sum, 1 to within an ulp or two; 4 ulp
// are allowed. A step's velocity error is carried by every later step, so after N steps the position has moved
// Δt Σₙ n · 4 ulp = 4.9e-5 m. (llvmpipe, whose division is exact, stays within the first part; an NVIDIA H100
// measured 4.16e-5 m, over it.)
TEST_F(BlockGrid, MovingBodyCrossesBlocksWhole) {
  const double speedMPerS = 0.9 * 0.05 / 1e-3;
  const Scene s = sceneFromJson(scene(96, R"({"kernel": "quadratic", "transfer": "apic"})",
                                      "[" + box(glm::dvec3(0.2, 0.5, 0.5), glm::dvec3(0.5, 0.8, 0.8),
                                                glm::dvec3(speedMPerS, 0, 0)) + "]"));
  constexpr int kSteps = 80;
  const double positionUlpM = std::ldexp(1.0, -21), velocityUlpMPerS = std::ldexp(1.0, -18);  // at 4 m, at 45 m/s
  const double tolerance = kSteps * positionUlpM / 2 + 1e-3 * (kSteps * (kSteps + 1) / 2) * 4 * velocityUlpMPerS;
  Simulation simulation(s, firn::sampleBodies(s), gl());
  const firn::ParticleSnapshot start = simulation.snapshot();
  simulation.step(s.time.dtS);
  const std::size_t blocksAtStart = simulation.blockUsage().lastStep;
  for (int step = 1; step < kSteps; ++step) {
    simulation.step(s.time.dtS);
    if (step % 20 == 0) expectGridHoldsEveryParticle(simulation, "step " + std::to_string(step));
  }
  simulation.checkWatchdog();
  EXPECT_LE(simulation.blockUsage().lastStep, blocksAtStart);
  const firn::ParticleSnapshot end = simulation.snapshot();
  double worst = 0;
  for (std::size_t i = 0; i < end.size(); ++i) {
    const glm::dvec3 expected = glm::dvec3(start.positionMass[i]) + glm::dvec3(speedMPerS * kSteps * 1e-3, 0, 0);
    worst = std::max(worst, glm::length(glm::dvec3(end.positionMass[i]) - expected));
  }
  std::printf("[ measured ] farthest particle from x0 + v t: %.3g m (tolerance %.3g m)\n", worst, tolerance);
  EXPECT_LT(worst, tolerance) << "the farthest particle from x0 + v t";
}

// A body spanning many blocks beside a single lonely particle far from it (as heavy as the body's, so the fixed
// point's resolution is the same for both, and with its material's volume: a volume from the grid's density would
// be that of the whole stencil, and a particle alone would stress itself): both fall freely, the particle on its
// own few blocks, and both follow x0 + g t²/2 + g Δt t/2 (symplectic Euler: the velocity is updated first) to
// float32 accumulation over the steps (5e-5 m, as in SimulationTest.FreeFallFollowsBallisticTrajectory).
TEST_F(BlockGrid, LonelyParticleFallsLikeTheBody) {
  const std::string bodies = "[" + box(glm::dvec3(0.3, 1.2, 0.3), glm::dvec3(0.9, 1.5, 0.9), glm::dvec3(0.0)) +
                             R"(, { "shape": "points", "path": "lonely.xyz", "material": "snow", "particle_mass": 6.25e-3 }])";
  const std::string path = ::testing::TempDir() + "lonely.xyz";
  {
    std::FILE* file = std::fopen(path.c_str(), "w");
    ASSERT_NE(file, nullptr);
    std::fputs("2.6,1.5,2.6\n", file);
    std::fclose(file);
  }
  const Scene s = firn::parseScene(
      scene(64, R"({"kernel": "cubic", "transfer": "pic_flip", "particle_volume": "material_density"})", bodies,
            "[0, -9.81, 0]"),
                                   ::testing::TempDir() + "scene.json");
  Simulation simulation(s, firn::sampleBodies(s), gl());
  const firn::ParticleSnapshot start = simulation.snapshot();
  const int steps = 100;
  for (int step = 0; step < steps; ++step) simulation.step(s.time.dtS);
  simulation.checkWatchdog();
  const double t = steps * s.time.dtS;
  const double drop = 0.5 * 9.81 * t * t + 0.5 * 9.81 * s.time.dtS * t;
  const firn::ParticleSnapshot end = simulation.snapshot();
  ASSERT_EQ(end.size(), start.size());
  const std::size_t lonely = end.size() - 1;  // the points body comes last
  EXPECT_NEAR(start.positionMass[lonely].y - end.positionMass[lonely].y, drop, 5e-5);
  EXPECT_NEAR(start.positionMass[0].y - end.positionMass[0].y, drop, 5e-5);
  expectGridHoldsEveryParticle(simulation, "body and lonely particle");
}

// Particles that reach more blocks than the pool holds: 2,000 particles, one in each of 2,000 blocks, in a pool
// made with room for 16. The first step leaves the blocks past the pool out; advanceFrame sees it, grows the pool
// and redoes the frame from its start, so every particle is scattered and the log says so. A step run on its own
// is reported by the watchdog instead, with the counts. Particles added while running grow the pool at once.
// A small box of snow in a 160-cell domain (blocks of 4 cells, 0.2 m), volumes from the material's density (no P2G
// before the first step), and 2,000 light particles, one in each block of a 20 × 10 × 10 lattice away from the box.
Scene boxInALargeDomain() {
  const std::string solver = R"({"kernel": "quadratic", "transfer": "apic", "particle_volume": "material_density"})";
  return sceneFromJson(scene(160, solver, "[" + box(glm::dvec3(0.3), glm::dvec3(0.4), glm::dvec3(0.0)) + "]"));
}
std::vector<firn::ParticleSeed> oneParticleInEachOf2000Blocks() {
  std::vector<firn::ParticleSeed> scattered;
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 x(0.55f + 0.2f * float(i % 20), 0.55f + 0.2f * float((i / 20) % 10), 0.55f + 0.2f * float(i / 200));
    scattered.push_back({x, glm::vec3(0.0f), 1e-5f, 0, -1});
  }
  return scattered;
}

TEST_F(BlockGrid, PoolGrowsWhenParticlesOutgrowIt) {
  const Scene s = boxInALargeDomain();
  const std::vector<firn::ParticleSeed> scattered = oneParticleInEachOf2000Blocks();
  std::vector<firn::ParticleSeed> seeds = firn::sampleBodies(s);
  seeds.insert(seeds.end(), scattered.begin(), scattered.end());
  for (const bool whole : {true, false}) {
    firn::SimulationOptions options;
    options.blockCapacity = 16;
    Simulation simulation(s, seeds, gl(), options);
    if (whole) {
      std::ostringstream log;
      simulation.advanceFrame(1.0 / s.time.frameRateHz, log);
      EXPECT_NE(log.str().find("more than its pool held; redoing it"), std::string::npos) << log.str();
      EXPECT_GE(simulation.blockUsage().capacity, 2000u);
      expectGridHoldsEveryParticle(simulation, "after the pool grew");
    } else {
      simulation.step(s.time.dtS);
      try {
        simulation.checkWatchdog();
        ADD_FAILURE() << "the watchdog reported nothing";
      } catch (const firn::SimulationError& error) {
        EXPECT_NE(std::string(error.what()).find("more than the 16 its pool held"), std::string::npos) << error.what();
      }
    }
  }
  firn::SimulationOptions options;
  options.particleCapacity = 4000;
  Simulation simulation(s, firn::sampleBodies(s), gl(), options);
  ASSERT_LT(simulation.blockUsage().capacity, 2000u);
  simulation.addParticles(scattered);
  EXPECT_GE(simulation.blockUsage().capacity, 2000u);
  simulation.step(s.time.dtS);
  simulation.checkWatchdog();
  expectGridHoldsEveryParticle(simulation, "after addParticles");
}

// A step sorted for blocks runs its passes over them (release_blocks, bin_scan_block, p2g_block, update_grid) in as
// many work groups as the blocks the host last counted, each group striding over the rest (common/blocks.glsl,
// workGroupCount). Counted at the box's few blocks, then 2,000 particles more, each in a block of its own: every group
// takes hundreds of blocks in turn, and the grid still holds every particle whole, in both block sizes and in the
// tiles, which take their dispatches from the block table (a block left out, or left uncleared, would be a whole
// particle's mass, 1e-5 kg, off: with the groups not striding, 0.02 kg was missing).
TEST_F(BlockGrid, BlocksPastTheHostsCountAreTransferredWhole) {
  const Scene s = boxInALargeDomain();
  for (const char* shape : {"tiles", "blocks-64", "blocks-256"}) {
    firn::SimulationOptions options;
    options.particleCapacity = 4000;
    options.transferShapes = shape;
    Simulation simulation(s, firn::sampleBodies(s), gl(), options);
    simulation.step(s.time.dtS);
    const std::size_t counted = simulation.blockUsage().lastStep;  // the count the dispatches take from here on
    ASSERT_GT(counted, 0u) << shape;
    ASSERT_LT(counted, 30u) << shape;
    simulation.addParticles(oneParticleInEachOf2000Blocks());
    for (int step = 0; step < 2; ++step) simulation.step(s.time.dtS);
    simulation.checkWatchdog();
    expectGridHoldsEveryParticle(simulation, shape);
    EXPECT_GT(simulation.blockUsage().lastStep, 2000u) << shape;
  }
}

// A tile of base nodes as full as a transfer takes on llvmpipe (maxTileParticles: its loop limit) is scattered
// whole; one fuller stops the run with what to change, rather than dropping particles. Cubic kernel (the most loop
// iterations per particle): a box of 4 × 1 × 1 cells whose particles' base nodes fill one tile.
TEST_F(BlockGrid, FullestTileIsScatteredWholeAndFullerIsReported) {
  const unsigned limit = firn::gpu::maxTileParticles(4);
  for (const double fill : {0.98, 1.2}) {
    // Cells 9–12 along x: cubic base nodes 8–11, the third tile of a block row; y and z one cell.
    const double particlesPerCell = fill * limit / 4.0;
    const Scene s = sceneFromJson(scene(32, R"({"kernel": "cubic", "transfer": "pic_flip"})",
                                        "[" + box(glm::dvec3(0.45, 0.45, 0.45), glm::dvec3(0.65, 0.5, 0.5),
                                                  glm::dvec3(0.0), particlesPerCell) + "]"));
    firn::SimulationOptions tiles;
    tiles.transferShapes = "tiles";  // the limit is the tiles' (P2G by blocks has none)
    Simulation simulation(s, firn::sampleBodies(s), gl(), tiles);
    if (fill < 1) {
      ASSERT_LE(simulation.particleCount(), limit);
      ASSERT_GT(simulation.particleCount(), 0.8 * limit);
      expectGridHoldsEveryParticle(simulation, "a full tile");
      simulation.checkWatchdog();
    } else {
      ASSERT_GT(simulation.particleCount(), limit);
      simulation.step(s.time.dtS);
      try {
        simulation.checkWatchdog();
        ADD_FAILURE() << "the watchdog reported nothing";
      } catch (const firn::SimulationError& error) {
        EXPECT_NE(std::string(error.what()).find("held more than " + std::to_string(limit) + " particles"),
                  std::string::npos)
            << error.what();
        EXPECT_NE(std::string(error.what()).find("Lower particles_per_cell"), std::string::npos) << error.what();
      }
    }
  }
}

// A domain far larger than its snow: the same small box in a 48³ and a 512³ domain claims the same blocks and
// gives the same particles to the last bit after 20 steps (the grid is sums over blocks, wherever they are).
TEST_F(BlockGrid, LargeDomainRunsLikeASmallOne) {
  std::vector<firn::ParticleSnapshot> results;
  std::vector<std::size_t> blocks;
  for (const int cells : {48, 512}) {
    const Scene s = sceneFromJson(scene(cells, R"({"kernel": "quadratic", "transfer": "apic"})",
                                        "[" + box(glm::dvec3(0.6), glm::dvec3(0.9), glm::dvec3(0.3, -0.2, 0.1)) + "]",
                                        "[0, -9.81, 0]"));
    Simulation simulation(s, firn::sampleBodies(s), gl());
    for (int step = 0; step < 20; ++step) simulation.step(s.time.dtS);
    simulation.checkWatchdog();
    results.push_back(simulation.snapshot());
    blocks.push_back(simulation.blockUsage().lastStep);
  }
  EXPECT_EQ(blocks[0], blocks[1]);
  ASSERT_EQ(results[0].size(), results[1].size());
  for (std::size_t i = 0; i < results[0].size(); ++i) {
    ASSERT_EQ(results[0].positionMass[i], results[1].positionMass[i]) << "particle " << i;
    ASSERT_EQ(results[0].velocityVolume[i], results[1].velocityVolume[i]) << "particle " << i;
  }
}

}  // namespace
