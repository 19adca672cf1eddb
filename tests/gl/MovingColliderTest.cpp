// Colliders that move and turn by keyframes (docs/algorithm.md, Colliders), as the GPU's steps see them: snow on a
// raised box rises with it to the keyframes' heights, and a spinning paddle stirs a bed of snow.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <glm/gtc/constants.hpp>

#include "GlTest.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"

namespace {

using firn::Scene;
using firn::Simulation;

class MovingColliderTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { firn::test::glContext(); }
  static const firn::gl::ContextInfo& gl() { return firn::test::glContext().info(); }
};

float lowestParticleM(const firn::ParticleSnapshot& s) {
  float lowest = std::numeric_limits<float>::max();
  for (std::size_t i = 0; i < s.size(); ++i) lowest = std::min(lowest, s.positionMass[i].y);
  return lowest;
}

// A block of elastic solid (256 particles; snow's moduli without its plasticity) rests on a sticky box that
// keyframes hold still until 0.1 s and raise by 5 cm by 0.3 s, where the last keyframe leaves it (it starts and
// stops at 0.25 m/s in a step). At each keyframe and after the last, at rest (0.5 s), the block's lowest particle
// lies on the box's top where the keyframe puts it: not inside it by more than the 1e-4 m the other collider tests
// allow (SimulationTest.NothingPenetratesSphereOrBoxCollider), and not above it by more than half a particle spacing,
// 0.0125 m (8 particles a cell of 5 cm: 2.5 cm apart, the first sampled half a spacing inside the body; settling
// only brings them down). The hop the stop gives (v² / 2g = 3 mm) has landed by 0.5 s. Measured gaps on llvmpipe:
// 6.4, 5.8 and 3.8 mm.
// That the GPU's collider is at the keyframe to float rounding is ColliderMotion.TheGpuTableAdvancedToAKeyframeIsAtIt;
// here the steps see it there.
TEST_F(MovingColliderTest, SnowOnAKeyframedBoxIsAtTheKeyframesHeights) {
  const Scene scene = firn::parseScene(R"({
    "grid": { "origin": [0, 0, 0], "cells": [24, 24, 24], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 10, "frames": 5 },
    "materials": { "rubber": { "model": "fixed_corotated", "youngs_modulus": 1.4e5, "poisson_ratio": 0.2,
                               "density": 400 } },
    "bodies": [ { "shape": "box", "min": [0.5, 0.4, 0.5], "max": [0.7, 0.5, 0.7], "material": "rubber" } ],
    "colliders": [ { "type": "box", "min": [0.35, 0.2, 0.35], "max": [0.85, 0.4, 0.85], "boundary": "sticky",
                     "keyframes": [ { "time_s": 0.1 }, { "time_s": 0.3, "translate": [0, 0.05, 0] } ] } ]
  })", "keyframed box");
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  const double halfSpacingM = 0.0125;
  const double penetrationM = 1e-4;
  for (const auto& [timeS, topM] : {std::pair{0.1, 0.4}, std::pair{0.3, 0.45}, std::pair{0.5, 0.45}}) {
    simulation.advanceTo(timeS);
    const double gapM = lowestParticleM(simulation.snapshot()) - topM;
    std::printf("at %.1f s the lowest particle is %.6g m above the box\n", timeS, gapM);
    EXPECT_GT(gapM, -penetrationM) << "at " << timeS << " s";
    EXPECT_LT(gapM, halfSpacingM) << "at " << timeS << " s";
  }
  simulation.checkWatchdog();
}

// A paddle (a 30 × 20 × 6 cm sticky box) turning about the vertical axis through its centre at 2π rad/s, keyframed
// every quarter turn, stands in a 40 × 10 × 40 cm bed of snow (2,000 particles) on a ground plane with friction.
// The snow starts at rest, with no angular momentum about the axis; after 0.3 s (300 steps, 0.3 turns) the paddle
// has dragged it round. L_y is compared with L_rigid = ω Σ m r², the whole bed turning rigidly with the paddle: the
// cohesive bed follows the paddle's faces while the ground's friction holds it back, and measured L_y / L_rigid is
// 0.129 on llvmpipe. The threshold, 0.05, is a clear rise above the start's exact 0 (a sticky paddle whose surface
// moved at v alone, not v + ω × r, would hold the snow it touches still), with room for the bed's plastic response
// to vary.
TEST_F(MovingColliderTest, SpinningPaddleRaisesTheSnowsAngularMomentumAboutItsAxis) {
  const Scene scene = firn::parseScene(R"({
    "grid": { "origin": [0, 0, 0], "cells": [24, 16, 24], "cell_size": 0.04 },
    "time": { "dt": 1e-3, "frame_rate": 10, "frames": 3 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "box", "min": [0.28, 0.12, 0.28], "max": [0.68, 0.22, 0.68], "material": "snow" } ],
    "colliders": [
      { "type": "plane", "point": [0, 0.12, 0], "normal": [0, 1, 0], "friction": 0.3 },
      { "type": "box", "min": [0.33, 0.1, 0.45], "max": [0.63, 0.3, 0.51], "boundary": "sticky",
        "keyframes": [ { "time_s": 0 }, { "time_s": 0.25, "rotate_deg": [0, 90, 0] },
                       { "time_s": 0.5, "rotate_deg": [0, 180, 0] } ] } ]
  })", "spinning paddle");
  const glm::dvec3 axisPointM(0.48, 0.2, 0.48);
  const double omegaRadPerS = glm::two_pi<double>();
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  const auto angularMomentum = [&](const firn::ParticleSnapshot& s, double* rigidKgM2PerS) {
    double angularKgM2PerS = 0;
    *rigidKgM2PerS = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      const double massKg = s.positionMass[i].w;
      const glm::dvec3 r = glm::dvec3(s.positionMass[i]) - axisPointM;
      angularKgM2PerS += massKg * glm::cross(r, glm::dvec3(s.velocityVolume[i])).y;
      *rigidKgM2PerS += massKg * omegaRadPerS * (r.x * r.x + r.z * r.z);
    }
    return angularKgM2PerS;
  };
  double rigidKgM2PerS = 0;
  EXPECT_EQ(angularMomentum(simulation.snapshot(), &rigidKgM2PerS), 0.0);
  simulation.advanceTo(0.3);
  simulation.checkWatchdog();
  const double stirredKgM2PerS = angularMomentum(simulation.snapshot(), &rigidKgM2PerS);
  std::printf("L_y = %.6g kg m^2/s, L_rigid = %.6g, ratio %.4f\n", stirredKgM2PerS, rigidKgM2PerS,
              stirredKgM2PerS / rigidKgM2PerS);
  EXPECT_GT(stirredKgM2PerS, 0.05 * rigidKgM2PerS);
}

// A run resumed from a checkpoint taken mid-segment of a keyframed collider's motion ends bit for bit where the
// uninterrupted run does: the collider's pose is a function of the time alone (each step writes the table of the
// segment holding it), so a checkpoint needs nothing of it.
TEST_F(MovingColliderTest, ResumedRunWithAKeyframedColliderIsBitIdentical) {
  const Scene scene = firn::parseScene(R"({
    "grid": { "origin": [0, 0, 0], "cells": [16, 16, 16], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 50, "frames": 4 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "box", "min": [0.3, 0.2, 0.3], "max": [0.5, 0.3, 0.5], "material": "snow" } ],
    "colliders": [ { "type": "box", "min": [0.25, 0.1, 0.38], "max": [0.55, 0.25, 0.42], "boundary": "sticky",
                     "keyframes": [ { "time_s": 0 }, { "time_s": 0.05, "translate": [0, 0.02, 0],
                                                       "rotate_deg": [0, 60, 0] } ] } ]
  })", "resumed paddle");
  const std::vector<firn::ParticleSeed> seeds = firn::sampleBodies(scene);
  Simulation uninterrupted(scene, seeds, gl());
  uninterrupted.advanceTo(0.08);
  Simulation first(scene, seeds, gl());
  first.advanceTo(0.02);
  const firn::Checkpoint checkpoint = first.checkpoint(1);
  Simulation resumed(scene, seeds, gl());
  resumed.resume(checkpoint, "in memory");
  resumed.advanceTo(0.08);
  const firn::ParticleSnapshot expected = uninterrupted.snapshot(), actual = resumed.snapshot();
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    ASSERT_EQ(actual.positionMass[i], expected.positionMass[i]) << "particle " << i;
    ASSERT_EQ(actual.velocityVolume[i], expected.velocityVolume[i]) << "particle " << i;
  }
}

}  // namespace
