// The estimate before sampling (run/Budget.h; docs/scene-format.md, Sizes and limits): each body's particles
// against the GPU's buffers, with the semi-implicit solve's buffers counted where the scene has them. No GL: the
// driver's limits are given as a gl::ContextInfo.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "Error.h"
#include "gpu/GpuLayout.h"
#include "run/Budget.h"
#include "scene/Sampling.h"
#include "scene/Scene.h"
#include "sim/GpuState.h"
#include "support/TestFiles.h"

namespace firn {
namespace {

// A 0.5 m box at 8 particles per cell of 1 cm: a lattice of spacing 5 mm, 100³ = 1,000,000 particles.
Scene boxScene(const std::string& solver) {
  return parseScene(R"({
    "grid": { "cells": [64, 64, 64], "cell_size": 0.01 },
    "time": { "dt": 1e-5, "frame_rate": 50, "frames": 1 },
    "solver": )" + solver + R"(,
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "box", "min": [0.05, 0.05, 0.05], "max": [0.55, 0.55, 0.55], "material": "snow" } ] })",
                    "budget.json");
}

const std::string kExplicit = R"({ "integrator": "explicit" })";
const std::string kSemiImplicit = R"({ "integrator": "semi_implicit" })";

// A driver that allows 64 MiB per storage block and says nothing of its free memory. The host's memory (22 GiB
// available on the build machines, at 256 bytes a particle) binds far above a million particles.
gl::ContextInfo driver() {
  gl::ContextInfo info;
  info.renderer = "a test driver";
  info.maxStorageBlockBytes = 64LL << 20;
  return info;
}

std::string refusal(const Scene& scene, const gl::ContextInfo& gl, double reservedParticles = 0) {
  try {
    checkParticleBudget(scene, gl, reservedParticles);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(Budget, BoxesAreEstimatedAnalytically) {
  // The lattice puts exactly 100 points along each 0.5 m edge (faces half a spacing from the lattice's planes); the
  // estimate is the volume over s³, exact here but for the rounding of the box's corners (1e-6 relative).
  EXPECT_NEAR(estimateBodies(boxScene(kExplicit)).front().particles, 1e6, 1.0);
}

TEST(Budget, SemiImplicitScenesCountTheSolversBuffers) {
  // The layouts as GpuState allocates them: the solve adds a SolverParticle (144 bytes) per particle, which is also
  // the largest particle buffer, and a SolverNode (192 bytes) and a SolverPreconditioner (32) per node of the pool;
  // the SolverNodes are the largest pool buffer.
  const GpuStateLayout explicitLayout = GpuStateLayout::forScene(boxScene(kExplicit), 0, 0, true);
  const GpuStateLayout semiLayout = GpuStateLayout::forScene(boxScene(kSemiImplicit), 0, 0, true);
  EXPECT_EQ(explicitLayout.largestParticleBufferBytesPerParticle(), 48u);
  EXPECT_EQ(semiLayout.largestParticleBufferBytesPerParticle(), 144u);
  EXPECT_EQ(semiLayout.particleBytesPerParticle() - explicitLayout.particleBytesPerParticle(), 144u);
  EXPECT_EQ(semiLayout.poolBytesPerBlock() - explicitLayout.poolBytesPerBlock(), 64u * 224u + 16u);
  EXPECT_EQ(GpuStateLayout::maxPoolBlocks(64LL << 20, false), (64u << 20) / (64u * 16u));
  EXPECT_EQ(GpuStateLayout::maxPoolBlocks(64LL << 20, true), (64u << 20) / (64u * 192u));

  // 64 MiB per buffer hold 1,398,101 particles at 48 bytes, 466,033 at 144: the explicit scene fits, the
  // semi-implicit one is refused with its estimate, the limit and what to change.
  const ParticleBudget explicitBudget = checkParticleBudget(boxScene(kExplicit), driver(), 0);
  EXPECT_EQ(explicitBudget.maxParticles, 1398101u);
  const std::string message = refusal(boxScene(kSemiImplicit), driver());
  EXPECT_NE(message.find("budget.json: bodies: about 1,000,000 particles"), std::string::npos) << message;
  EXPECT_NE(message.find("need more than the 466,033 that fit the 64 MiB a test driver allows per particle buffer "
                         "(144 bytes per particle)"),
            std::string::npos)
      << message;
  // 8 × 466,033 / 1,000,000 = 3.73, less the 3% kept for the estimate's error, rounded down: 3.61.
  EXPECT_NE(message.find("particles_per_cell 3.61 on bodies[0] would fit"), std::string::npos) << message;
}

TEST(Budget, GpuMemoryTheDriverReportsBindsWithTheSolversBuffers) {
  // A driver with large buffers and 320 MiB free: the particles' bytes in all bind, 152 explicit (positions,
  // velocities, plastic state, F, τ, sort keys) and 296 semi-implicit, after the grid's start. That start is a pool
  // of four times the 15³ blocks of 4³ nodes the box reaches with the stencil, 13,500 blocks: 2.6 KiB each explicit
  // (two node buffers, PIC/FLIP's impulse among them, bins, tile order, slot), 34.11 MiB, and 14,352 bytes more
  // semi-implicit (64 SolverNodes and SolverPreconditioners, and a vec4), 218.9 MiB.
  gl::ContextInfo gl = driver();
  gl.maxStorageBlockBytes = 1LL << 30;
  gl.availableMemoryBytes = 320LL << 20;
  const ParticleBudget explicitBudget = checkParticleBudget(boxScene(kExplicit), gl, 0);
  EXPECT_NE(explicitBudget.limit.find("of GPU memory a test driver has free (152 bytes per particle in all, after "
                                      "34.11 MiB for the grid)"),
            std::string::npos)
      << explicitBudget.limit;
  // (320 − 34.11) MiB / 152 B = 1,972,214; the message's 34.11 MiB is rounded to 0.005 MiB, 35 particles' worth.
  EXPECT_NEAR(double(explicitBudget.maxParticles), 1972214, 35);
  // (320 − 218.89) MiB / 296 B = 358,191: the million are refused.
  const std::string message = refusal(boxScene(kSemiImplicit), gl);
  EXPECT_NE(message.find("the 358,1"), std::string::npos) << message;
  EXPECT_NE(message.find("(296 bytes per particle in all, after 218.9 MiB for the grid)"), std::string::npos)
      << message;
}

TEST(Budget, RoomForTheViewersSnowballsCounts) {
  // 398,101 particles of room are left beside the box: 400,000 more do not fit.
  const std::string message = refusal(boxScene(kExplicit), driver(), 400000);
  EXPECT_NE(message.find("and room for 400,000 more (the viewer's snowballs)"), std::string::npos) << message;
  EXPECT_EQ(refusal(boxScene(kExplicit), driver(), 390000), "");
}

TEST(Budget, SamplingStopsAtTheLimitWhenTheEstimateIsShort) {
  // Held to 1,000 particles, the million-particle box stops at once, naming the scene file, the body and the reason.
  SamplingLimits limits;
  limits.maxParticles = 1000;
  limits.reason = "a test limit";
  try {
    sampleBodies(boxScene(kExplicit), limits);
    FAIL() << "sampling went past the limit";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("budget.json: bodies[0]"), std::string::npos) << message;
    EXPECT_NE(message.find("a test limit"), std::string::npos) << message;
  }
}

// The box of snow beside a rigid cube of 0.503 m (a mesh, at `resolution` samples per 1 cm cell), in `folder`.
Scene sceneWithMeshBody(const std::filesystem::path& folder, const std::string& resolution) {
  std::ofstream(folder / "cube.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                        "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\n"
                                        "f 4 1 5\nf 4 5 8\nf 3 4 8\nf 3 8 7\n";
  return parseScene(R"({
    "grid": { "cells": [64, 64, 64], "cell_size": 0.01 },
    "time": { "dt": 1e-5, "frame_rate": 50, "frames": 1 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "box", "min": [0.05, 0.05, 0.05], "max": [0.15, 0.15, 0.15], "material": "snow" } ],
    "rigid_bodies": [ { "shape": "mesh", "path": "cube.obj", "scale": 0.503, "translate": [0.06, 0.06, 0.06],
                        "density": 500, "resolution": )" + resolution + " } ] }",
                    folder / "budget.json");
}

TEST(Budget, DistanceFieldsTakeTheirMemoryFirst) {
  const std::filesystem::path folder = test::freshDirectory("budget_fields");
  gl::ContextInfo gl = driver();
  gl.maxStorageBlockBytes = 1LL << 30;
  gl.availableMemoryBytes = 320LL << 20;
  // At resolution 8 the field's spacing is 1.25 mm over 0.503 m and 3 cells each side: ⌈0.563 / 0.00125⌉ + 1 = 452
  // samples per axis, 92.3 million samples of two floats (φ and the nearest triangle), 704.5 MiB with the 12
  // triangles' 132 bytes each: more than the GPU has free. (The sizes stay clear of whole
  // steps, where the count would hang on the rounding of the division.)
  const std::string message = refusal(sceneWithMeshBody(folder, "8"), gl);
  EXPECT_EQ(message.rfind((folder / "budget.json").string() + ": rigid_bodies[0].resolution: the distance field of "
                                                              "cube.obj, 452 × 452 × 452 samples 0.00125 m apart (704.5 MiB",
                          0),
            0u)
      << message;
  EXPECT_NE(message.find("lower its resolution"), std::string::npos) << message;
  // At resolution 2, 5 mm: 114³ samples, 11.3 MiB, which the GPU's limit counts beside the grid.
  const ParticleBudget budget = checkParticleBudget(sceneWithMeshBody(folder, "2"), gl, 0);
  EXPECT_NE(budget.limit.find(", 11.3 MiB for the distance fields)"), std::string::npos) << budget.limit;
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace firn
