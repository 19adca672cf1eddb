// A second GL implementation: the same scenes run on Mesa's llvmpipe and on Zink (GL over Vulkan, on lavapipe)
// agree within tolerances derived from float rounding. Bitwise reproducibility holds within one driver, not across
// drivers: each compiler rounds float arithmetic its own way (docs/numerics.md, Bitwise determinism).
//
// Both run through Mesa's surfaceless EGL platform with the software path forced (LIBGL_ALWAYS_SOFTWARE=1);
// GALLIUM_DRIVER picks llvmpipe or zink behind it (docs/platform.md, A second driver: Zink).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "Cli.h"

namespace {

namespace fs = std::filesystem;
using firn::test::freshDirectory;
using firn::test::readTable;
using firn::test::Table;
using firn::test::Result;
using firn::test::runFirn;
using firn::test::writeScene;

const char* const kLlvmpipe = "LIBGL_ALWAYS_SOFTWARE=1 GALLIUM_DRIVER=llvmpipe";
const char* const kZink = "LIBGL_ALWAYS_SOFTWARE=1 GALLIUM_DRIVER=zink";

// A float's relative precision, 2⁻²³: how far two drivers may round a stored position apart each step.
constexpr double kFloatEpsilon = 1.1920928955078125e-7;
// How far two conforming compilers may take a step's velocities apart, relative to them: GLSL 4.30 (§4.7.1) lets
// pow(x, y) be exp2(y · log2(x)) with log2 within 2⁻²¹ absolute near 1, so water's pressure term J^−γ (γ = 7, the
// largest power a material model raises J to) may differ by 7 × 2⁻²¹ relative; the other models' exp, log and
// inversesqrt are allowed 2 or 3 ulp, less. Measured: a water and sand scene drifted 2.8e-7 of Σ m|v| per step
// (about 2.3 ε), the built-in snow scene 1e-9.
constexpr double kStepPrecision = 7 * 4.76837158203125e-7;

Table run(const std::string& arguments, const std::string& driver, const fs::path& out, const std::string& renderer) {
  const Result result = runFirn(arguments + " --no-ply --out " + out.string(), driver);
  EXPECT_EQ(result.exitCode, 0) << driver << "\n" << result.output;
  // The closing line names the renderer ("… ms per step on zink (llvmpipe …)").
  EXPECT_NE(result.output.find("per step on " + renderer), std::string::npos) << driver << "\n" << result.output;
  return readTable(out / "stats.csv");
}

// Runs `arguments` under both drivers and holds Zink's stats.csv to llvmpipe's:
// - particles, steps and mass exactly: they are counts, or sums of the same host-set masses in the same order;
// - momentum: each step, the two compilers may take a particle's velocity apart by kStepPrecision δ of it, and the
//   differences of successive steps add up: after S steps |Δp| ≤ S δ Σ m|v|, with Σ m|v| ≤ √(2 M K)
//   (Cauchy–Schwarz; M the mass, K the largest kinetic energy so far). A semi-implicit step also stops its solve
//   wherever the residual falls below the tolerance, a relative `solverTolerance` of the velocities on each side,
//   which adds 2 × solverTolerance per step;
// - centre of mass: the momentum's difference integrated over the time t (t |Δp| / M), and a position's own
//   rounding, ε of the domain's extent `extentM` per step.
void expectDriversAgree(const std::string& name, const std::string& arguments, double extentM,
                        double solverTolerance = 0) {
  const fs::path directory = freshDirectory("drivers_" + name);
  const Table llvmpipe = run(arguments, kLlvmpipe, directory / "llvmpipe", "llvmpipe");
  const Table zink = run(arguments, kZink, directory / "zink", "zink");
  ASSERT_EQ(llvmpipe.header, zink.header);
  ASSERT_EQ(llvmpipe.rows.size(), zink.rows.size());
  ASSERT_GE(llvmpipe.rows.size(), 2u);
  double steps = 0;
  double largestKineticJ = 0;
  double largestMomentumDifference = 0;
  double largestCenterDifferenceM = 0;
  for (std::size_t frame = 0; frame < llvmpipe.rows.size(); ++frame) {
    const std::string where = name + " frame " + std::to_string(frame);
    for (const char* exact : {"particles", "steps", "mass_kg"}) {
      EXPECT_EQ(llvmpipe.text(frame, exact), zink.text(frame, exact)) << where << " " << exact;
    }
    steps += llvmpipe.at(frame, "steps");
    largestKineticJ = std::max(largestKineticJ, llvmpipe.at(frame, "kinetic_energy_j"));
    const double massKg = llvmpipe.at(frame, "mass_kg");
    const double momentumTolerance =
        std::max(steps, 1.0) * (kStepPrecision + 2 * solverTolerance) * std::sqrt(2 * massKg * largestKineticJ);
    const double centerTolerance =
        llvmpipe.at(frame, "time_s") * momentumTolerance / massKg + std::max(steps, 1.0) * kFloatEpsilon * extentM;
    for (const char* axis : {"x", "y", "z"}) {
      const std::string momentum = std::string("momentum_") + axis;
      const std::string center = std::string("center_of_mass_") + axis;
      const double momentumDifference = std::abs(llvmpipe.at(frame, momentum) - zink.at(frame, momentum));
      const double centerDifference = std::abs(llvmpipe.at(frame, center) - zink.at(frame, center));
      EXPECT_LE(momentumDifference, momentumTolerance) << where << " " << momentum;
      EXPECT_LE(centerDifference, centerTolerance) << where << " " << center;
      largestMomentumDifference = std::max(largestMomentumDifference, momentumDifference / momentumTolerance);
      largestCenterDifferenceM = std::max(largestCenterDifferenceM, centerDifference / centerTolerance);
    }
  }
  // How close the drivers came, as a fraction of the tolerances (docs/platform.md records them).
  std::printf("%s: largest difference %.2g of the momentum tolerance, %.2g of the centre of mass's\n", name.c_str(),
              largestMomentumDifference, largestCenterDifferenceM);
  fs::remove_all(directory);
}

// The driver each run gets, before anything is compared: on a machine with a GPU, Firn takes the GPU whatever
// Mesa's variables say, and there is no llvmpipe-to-Zink comparison to make.
bool bothMesaDriversReachable() {
  const Result llvmpipe = runFirn("info", kLlvmpipe);
  const Result zink = runFirn("info", kZink);
  return llvmpipe.output.find("llvmpipe") != std::string::npos && zink.output.find("zink") != std::string::npos;
}

// The built-in scene (a snowball thrown at a wall: explicit, fixed-point sums, APIC, quadratic kernel, a collider)
// for its first 2 frames, 334 steps; its domain reaches 1.28 m from the origin.
TEST(Drivers, TheBuiltInSceneAgreesBetweenLlvmpipeAndZink) {
  if (!bothMesaDriversReachable()) GTEST_SKIP() << "Firn does not run on Mesa's llvmpipe and Zink here (a GPU?)";
  expectDriversAgree("builtin", "run --frames 2", 1.28);
}

// A snow ball thrown at the floor with semi-implicit steps, float atomics and PIC/FLIP, the options the built-in
// scene does not use; 40 steps. The solve's tolerance is the scene format's default, 1e-4. (The cubic kernel is the
// next scene's: with semi-implicit steps and float atomics it makes the solve non-finite at step 6, on both drivers.)
TEST(Drivers, ASemiImplicitFloatAtomicsSceneAgreesBetweenLlvmpipeAndZink) {
  if (!bothMesaDriversReachable()) GTEST_SKIP() << "Firn does not run on Mesa's llvmpipe and Zink here (a GPU?)";
  const fs::path directory = freshDirectory("drivers_semi_implicit_scene");
  const fs::path scene = writeScene(directory, "fall.json", R"({
  "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
  "time": { "dt": 1e-3, "frame_rate": 50, "frames": 2 },
  "solver": { "integrator": "semi_implicit", "atomics": "float", "kernel": "quadratic", "transfer": "pic_flip" },
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "sphere", "center": [0.6, 0.35, 0.6], "radius": 0.15, "material": "snow",
                "velocity": [0, -3, 0] } ] })");
  expectDriversAgree("semi_implicit", "run " + scene.string(), 1.2 * std::sqrt(3.0), 1e-4);
  fs::remove_all(directory);
}

// Water and sand side by side, explicit steps with the cubic kernel, falling onto a slip floor: the other material
// models, 100 steps.
TEST(Drivers, AWaterAndSandSceneAgreesBetweenLlvmpipeAndZink) {
  if (!bothMesaDriversReachable()) GTEST_SKIP() << "Firn does not run on Mesa's llvmpipe and Zink here (a GPU?)";
  const fs::path directory = freshDirectory("drivers_water_sand_scene");
  const fs::path scene = writeScene(directory, "water_sand.json", R"({
  "grid": { "cells": [24, 16, 12], "cell_size": 0.02 },
  "time": { "dt": 2e-4, "frame_rate": 50, "frames": 1 },
  "solver": { "kernel": "cubic", "transfer": "apic", "atomics": "fixed" },
  "materials": {
    "water": { "model": "water", "density": 1000, "bulk_modulus": 1e5, "gamma": 7 },
    "sand": { "model": "drucker_prager", "youngs_modulus": 3.537e6, "poisson_ratio": 0.3, "density": 2200,
              "friction_angle_deg": 30 } },
  "bodies": [
    { "shape": "box", "min": [0.06, 0.08, 0.06], "max": [0.2, 0.22, 0.18], "material": "water", "particles_per_cell": 4 },
    { "shape": "box", "min": [0.28, 0.08, 0.06], "max": [0.42, 0.22, 0.18], "material": "sand", "particles_per_cell": 4 } ],
  "colliders": [ { "type": "plane", "point": [0, 0.06, 0], "normal": [0, 1, 0], "friction": 0, "boundary": "slip" } ] })");
  const double extentM = std::sqrt(0.48 * 0.48 + 0.32 * 0.32 + 0.24 * 0.24);
  expectDriversAgree("water_sand", "run " + scene.string(), extentM);
  fs::remove_all(directory);
}

}  // namespace
