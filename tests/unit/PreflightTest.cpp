// The pre-flight check: the time step against the elastic and CFL bounds (warn, or stop when far beyond),
// and bodies that start inside colliders.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "Error.h"
#include "gpu/Materials.h"
#include "run/Preflight.h"
#include "scene/Scene.h"
#include "support/TestFiles.h"

namespace firn {
namespace {

Scene sceneWith(const std::string& dt, const std::string& body, const std::string& colliders = "[]") {
  return parseScene(R"({
    "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
    "time": { "dt": )" + dt + R"(, "frame_rate": 50, "frames": 1 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ )" + body + R"( ],
    "colliders": )" + colliders + "}",
                    "preflight.json");
}

const char* const kBall = R"({ "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.15, "material": "snow" })";

bool contains(const std::vector<std::string>& lines, const std::string& fragment) {
  for (const std::string& line : lines) {
    if (line.find(fragment) != std::string::npos) return true;
  }
  return false;
}

// The stomakhin preset's wave speed is 22.35 m/s (MaterialsTest), so h / c = 0.05 / 22.35 = 2.24e-3 s.
TEST(Preflight, StepWithinTheBoundsRunsQuietly) {
  const Scene scene = sceneWith("1e-3", kBall);
  const PreflightReport report = preflight(scene, sampleBodies(scene));
  EXPECT_NEAR(report.stableDtS, 0.05 / waveSpeedMPerS(scene.materials[0]), 1e-12);
  EXPECT_TRUE(report.warnings.empty());
  EXPECT_TRUE(contains(report.notes, "fixed point: "));
  EXPECT_TRUE(contains(report.notes, "bodies[0]: 8 particles per cell"));
}

// Each body's particles and mass, and where a sphere's or a box's particles hold more than its shape: the test tank's
// water, a box of 0.25 × 0.25 × 0.1 m at 4 particles per cell of 12.5 mm, is filled with whole lattice cells of
// s = 12.5 mm / ∛4 = 7.87 mm from the grid's origin, 32 × 32 × 13 of them (the box's 31.75 × 31.75 × 12.7 rounded to
// the cells whose centres lie inside), each holding 1000 s³ kg: 6.5 kg, 4.0% more than the box's 6.25 kg. The ball
// above (radius 6 cells of s = 2.5 cm) holds 919 cells of 400 s³ kg, 5.744 kg against its sphere's 5.655 kg; a box
// whose faces lie on the lattice's cell faces (0.2 × 0.1 × 0.2 m: 8 × 4 × 8 cells) holds exactly its own mass and says
// nothing more.
TEST(Preflight, NotesEachBodysParticlesAndMassAgainstItsShape) {
  const Scene tank = parseScene(R"({
    "grid": { "origin": [0, 0, 0], "cells": [24, 20, 24], "cell_size": 0.0125 },
    "time": { "dt": 2e-4, "frame_rate": 10, "frames": 1 },
    "materials": { "water": { "model": "water", "density": 1000, "bulk_modulus": 1e5, "gamma": 7 } },
    "bodies": [ { "shape": "box", "min": [0.025, 0.025, 0.025], "max": [0.275, 0.125, 0.275], "material": "water",
                  "particles_per_cell": 4 } ] })", "tank.json");
  const PreflightReport report = preflight(tank, sampleBodies(tank));
  EXPECT_TRUE(contains(report.notes, "bodies[0]: 4 particles per cell, 13,312 particles, 6.5 kg (+4.0% against its "
                                     "box's 6.25 kg: the particles fill it with whole lattice cells of 0.00787 m"));
  const Scene ball = sceneWith("1e-3", kBall);
  EXPECT_TRUE(contains(preflight(ball, sampleBodies(ball)).notes,
                       "bodies[0]: 8 particles per cell, 919 particles, 5.744 kg (+1.6% against its sphere's 5.655 kg"));
  const Scene box = sceneWith(
      "1e-3", R"({ "shape": "box", "min": [0.2, 0.2, 0.2], "max": [0.4, 0.3, 0.4], "material": "snow" })");
  const PreflightReport boxReport = preflight(box, sampleBodies(box));
  EXPECT_TRUE(contains(boxReport.notes, "bodies[0]: 8 particles per cell, 256 particles, 1.6 kg"));
  EXPECT_FALSE(contains(boxReport.notes, "against its box"));
}

TEST(Preflight, StepBeyondTheBoundWarnsAndFarBeyondStops) {
  const Scene beyond = sceneWith("4e-3", kBall);  // 1.8 times h / c
  const PreflightReport report = preflight(beyond, sampleBodies(beyond));
  EXPECT_TRUE(contains(report.warnings, "time.dt = 0.004 s exceeds the elastic bound h / c = 0.00224 s"))
      << (report.warnings.empty() ? "" : report.warnings[0]);

  const Scene farBeyond = sceneWith("1e-2", kBall);  // 4.5 times h / c
  try {
    preflight(farBeyond, sampleBodies(farBeyond));
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind("preflight.json: time.dt: 0.01 s is 4.47 times the elastic bound", 0), 0u) << message;
    EXPECT_NE(message.find("Set time.dt to at most 0.00224 s"), std::string::npos) << message;
  }
}

// A body thrown at 100 m/s crosses two cells per step at dt = 1e-3 s: the CFL bound h / |v| = 5e-4 s is the limit.
TEST(Preflight, FastBodyIsHeldToTheCflBound) {
  const Scene scene = sceneWith("1e-3", R"({ "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.15,
                                            "material": "snow", "velocity": [100, 0, 0] })");
  const PreflightReport report = preflight(scene, sampleBodies(scene));
  EXPECT_NEAR(report.stableDtS, 5e-4, 1e-9);
  EXPECT_TRUE(contains(report.warnings, "exceeds the CFL bound h / |v| = 0.0005 s"));
}

// A rigid sphere of radius 0.1 m thrown at 30 m/s and spinning at 400 rad/s: its surface moves at up to 30 + 400 · 0.1
// = 70 m/s, so h / |v| = 0.05 / 70 = 7.14e-4 s binds dt = 1e-3 s (a warning); spun at 4,000 rad/s instead, 430 m/s
// bind it to 1.16e-4 s, more than 4 times below dt, and the refusal names the key that spins it.
TEST(Preflight, FastRigidBodyIsHeldToTheCflBoundOfItsSurface) {
  const auto withBall = [](const std::string& angularVelocity) {
    Scene scene = sceneWith("1e-3", kBall);
    RigidBody ball;
    ball.shape = RigidShape::Sphere;
    ball.centerM = ball.centerOfMassM = {0.3, 0.9, 0.3};
    ball.radiusM = 0.1;
    ball.velocityMPerS = {30, 0, 0};
    ball.angularVelocityRadPerS = {0, 0, std::stod(angularVelocity)};
    scene.rigidBodies.push_back(ball);
    return scene;
  };
  const Scene spinning = withBall("400");
  const PreflightReport report = preflight(spinning, sampleBodies(spinning));
  EXPECT_NEAR(report.stableDtS, 0.05 / 70.0, 1e-12);
  EXPECT_TRUE(contains(report.warnings, "exceeds the CFL bound h / |v| = 0.000714 s of rigid_bodies[0] (its surface "
                                        "moves at 70 m/s at the start)"))
      << (report.warnings.empty() ? "" : report.warnings[0]);
  const Scene fast = withBall("4000");
  try {
    preflight(fast, sampleBodies(fast));
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("times the CFL bound h / |v| = 0.000116 s of rigid_bodies[0]"), std::string::npos) << message;
    EXPECT_NE(message.find("or slow rigid_bodies[0].angular_velocity"), std::string::npos) << message;
  }
}

TEST(Preflight, BodyStartingInsideAColliderIsReported) {
  const Scene scene = sceneWith("1e-3", kBall,
                                R"([ { "type": "plane", "point": [0, 0.6, 0], "normal": [0, 1, 0] },
                                     { "type": "sphere", "center": [0.2, 0.2, 0.2], "radius": 0.05 } ])");
  const std::vector<ParticleSeed> particles = sampleBodies(scene);
  const PreflightReport report = preflight(scene, particles);
  // The plane through the ball's centre has about half the ball's particles below it; the sphere none.
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("start inside colliders[0] (a plane)"), std::string::npos) << report.warnings[0];
  const std::size_t inside = std::stoul(report.warnings[0].substr(report.warnings[0].find(": ") + 2));
  EXPECT_NEAR(double(inside), 0.5 * double(particles.size()), 0.05 * double(particles.size()));
}

// A collider at 1e6 m/s crosses 2e4 cells per step of 1e-3 s (h = 0.05 m): its CFL bound h / |v| = 5e-8 s, not the
// bodies' (at rest), is what the refusal names, with the key to change.
TEST(Preflight, FastColliderIsNamedWhenItBindsTheStep) {
  const Scene scene = sceneWith("1e-3", kBall, R"([ { "type": "box", "min": [0.2, 0.2, 0.2], "max": [0.3, 0.3, 0.3],
                                                      "velocity": [1e6, 0, 0] } ])");
  try {
    preflight(scene, sampleBodies(scene));
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("time.dt: 0.001 s is 2e+04 times the CFL bound h / |v| = 5e-08 s of colliders[0] (a box "
                           "moving at 1e+06 m/s"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("or slow colliders[0].velocity"), std::string::npos) << message;
  }
}

// A box turning a quarter turn in 1e-6 s about its centre: ω = (π/2) / 1e-6 s = 1.571e6 rad/s, and its corners,
// sqrt(0.05² · 3) = 0.0866 m from the pivot, move at |ω| r = 1.36e5 m/s; the bound h / |v| = 3.676e-7 s names the
// collider and its keyframes.
TEST(Preflight, TurningColliderIsBoundByItsSurfacesSpeed) {
  const Scene scene = sceneWith("1e-3", kBall, R"([ { "type": "box", "min": [0.2, 0.2, 0.2], "max": [0.3, 0.3, 0.3],
      "keyframes": [ { "time_s": 0 }, { "time_s": 1e-6, "rotate_deg": [0, 90, 0] } ] } ])");
  try {
    preflight(scene, sampleBodies(scene));
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("CFL bound h / |v| = 3.68e-07 s of colliders[0] (a box moving at 1.36e+05 m/s"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("or slow colliders[0].keyframes"), std::string::npos) << message;
  }
}

// Gravity of 1e30 m/s² over the interior's 1 m (20 cells of 0.05 m) reaches √(2e30) = 1.41e15 m/s: the bound
// h / √(2 |g| L) = 3.54e-17 s names gravity, for fixed steps and for adaptive ones (whose steps would number 1e15
// a frame).
TEST(Preflight, HugeGravityIsNamed) {
  Scene scene = sceneWith("1e-3", kBall);
  scene.gravityMPerS2 = {0, -1e30, 0};
  const std::vector<ParticleSeed> particles = sampleBodies(scene);
  try {
    preflight(scene, particles);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("times the CFL bound h / √(2 |g| L) = 3.54e-17 s of gravity (|g| = 1e+30 "
                                             "m/s²"),
              std::string::npos)
        << error.what();
  }
  scene.time.adaptive = true;
  try {
    preflight(scene, particles);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()).rfind("preflight.json: gravity: the CFL bound h / √(2 |g| L) = 3.54e-17 s", 0), 0u)
        << error.what();
  }
  // Earth's gravity over the same metre: 4.43 m/s, a bound of 0.0113 s, far above dt.
  scene.gravityMPerS2 = {0, -9.81, 0};
  EXPECT_NO_THROW(preflight(scene, particles));
}

// At x = 1000 m floats are 2⁻¹⁴ m = 6.1e-5 m apart, 0.00122 of a 0.05 m cell: above the warning's thousandth (not
// the refusal's hundredth). A step of 1e-3 s moves a particle only if it is faster than 6.1e-5 / 2 / 1e-3 m/s.
TEST(Preflight, DomainFarFromTheOriginWarnsWithTheSpeedThatStandsStill) {
  Scene scene = sceneWith("1e-3", kBall);
  scene.grid.originM.x = 1000;
  EXPECT_DOUBLE_EQ(scene.grid.positionResolutionM(), std::ldexp(1.0, -14));
  // The grid moves, the ball does not: its particles lie outside it, which pre-flight does not look at.
  const PreflightReport report = preflight(scene, sampleBodies(sceneWith("1e-3", kBall)));
  EXPECT_TRUE(contains(report.warnings, "grid.origin: positions out at the domain's far corner are 32-bit floats "
                                        "6.1e-05 m apart, 0.00122 of a cell"));
  EXPECT_TRUE(contains(report.warnings, "a particle slower than 0.0305 m/s"));
  // At the origin the same grid's far corner, 1.2 m, has floats 1.2e-7 m apart: no warning.
  const Scene atOrigin = sceneWith("1e-3", kBall);
  EXPECT_TRUE(preflight(atOrigin, sampleBodies(atOrigin)).warnings.empty());
}

// Every scene Firn ships passes its own pre-flight check without a warning.
TEST(Preflight, ShippedScenesAreWithinTheirBounds) {
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(FIRN_SOURCE_DIR) / "assets/scenes")) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const Scene scene = loadScene(entry.path());
    const PreflightReport report = preflight(scene, sampleBodies(scene));
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
  }
}

// Each rigid body's mass, volume and inertia, and each distance field's lattice and size, are notes.
TEST(Preflight, RigidBodiesAndDistanceFieldsAreNoted) {
  const std::filesystem::path folder = test::freshDirectory("preflight_rigid_bodies");
  std::ofstream(folder / "cube.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                        "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\n"
                                        "f 4 1 5\nf 4 5 8\nf 3 4 8\nf 3 8 7\n";
  const Scene scene = parseScene(R"({
    "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 50, "frames": 1 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ )" + std::string(kBall) + R"( ],
    "rigid_bodies": [
      { "shape": "box", "center": [0.3, 0.3, 0.3], "size": [0.1, 0.2, 0.3], "mass": 6 },
      { "shape": "mesh", "path": "cube.obj", "scale": 0.21, "translate": [0.8, 0.2, 0.8], "density": 1000 } ] })",
                                 folder / "preflight.json");
  const PreflightReport report = preflight(scene, sampleBodies(scene));
  // m/12 diag(b² + c², a² + c², a² + b²) = 0.5 diag(0.13, 0.1, 0.05) kg m².
  EXPECT_TRUE(contains(report.notes, "rigid_bodies[0]: 6 kg, 0.006 m³, centre of mass (0.3, 0.3, 0.3) m, inertia "
                                     "about it diag(0.065, 0.05, 0.025) kg m²"));
  EXPECT_TRUE(contains(report.notes, "rigid_bodies[1]: 9.261 kg, 0.009261 m³, centre of mass (0.905, 0.305, 0.905) m, inertia "
                                     "about it diag(0.0681, 0.0681, 0.0681) kg m²"));
  // Spacing 0.025 m over 0.21 m and 0.15 m each side: ⌈0.51 / 0.025⌉ + 1 = 22 samples per axis of two floats, and 12
  // triangles of 33: 86,768 bytes.
  EXPECT_TRUE(contains(report.notes, "rigid_bodies[1]: distance field of cube.obj, 22 × 22 × 22 samples 0.025 m apart "
                                     "(0.0868 MB as 32-bit floats)"));
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace firn
