// The P2G sums on the GPU against the same contributions added in double on the CPU (benchmarks/P2GReference.h),
// for fixed-point and float sums: each must stay within what its number format can lose.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "GlTest.h"
#include "P2GReference.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"

namespace {

// Float rounding: ε = 2^-23 (one ulp of 1), u = 2^-24 (round to nearest: half of it).
constexpr double kEpsilon = 1.0 / (1 << 23);
constexpr double kUnitRoundoff = kEpsilon / 2;
// How far one contribution the shader computes may be from the CPU's float copy of that computation, which uses
// the same operations in the same order. llvmpipe evaluates them as the CPU does (measured: no node's error
// exceeds what its quantization alone allows), and 4 ulp of the contribution are allowed for a driver's. The
// shaders divide by nothing here (the host's reciprocals, gpu_contract.h) and fuse no multiply and add (precise,
// common/bspline.glsl), so a GPU's stencil positions and weights are the CPU's too: on an NVIDIA H100, whose
// division moved the positions by ulps of the cell index before, fringe nodes went 29-73x over this bound.
constexpr double kContributionMismatch = 4 * kEpsilon;

// A snowball of 2,100 particles on 0.05 m cells, falling at 3 m/s and spinning, so that momenta vary in size and
// sign across the grid.
firn::Scene snowball(const std::string& kernel, const std::string& transfer, const std::string& atomics) {
  return firn::parseScene(R"({
    "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
    "time": { "dt": 1e-4, "frame_rate": 30, "frames": 1 },
    "solver": { "kernel": ")" + kernel + R"(", "transfer": ")" + transfer + R"(", "atomics": ")" + atomics + R"(" },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.2, "material": "snow",
                  "velocity": [0.5, -3, 1], "angular_velocity": [0, 4, 2] } ] })",
                          "spinning snowball");
}

struct Comparison {
  std::vector<firn::bench::NodeSumError> nodes;
  firn::FixedPointScale scale;
};

Comparison compareOnGpu(const firn::Scene& scene) {
  firn::Simulation simulation(scene, firn::sampleBodies(scene), firn::test::glContext().info());
  const firn::bench::ReferenceGrid reference =
      firn::bench::referenceParticleToGrid(scene, simulation.fixedPoint(), simulation.snapshot());
  return {firn::bench::compareWithReference(simulation.readGridAfterTransfer(), reference, scene,
                                            simulation.fixedPoint()),
          simulation.fixedPoint()};
}

const char* const kKernelTransfers[][2] = {{"cubic", "pic_flip"}, {"quadratic", "apic"}};

// Fixed point stores each contribution c (in units of m_ref, or of m_ref·h/Δt) as floor(c·2^k + u) with a
// dither u in [0, 1): off by less than one quantum 2^-k. Forming c·2^k + u in float rounds by at most u·|c|·2^k,
// and the shader's c may differ from the CPU's copy by kContributionMismatch |c|. The integer sums add nothing
// more. So a node reached by n contributions is within n·2^-k + (u + 4ε) Σ|c| of the double sum (√3 n·2^-k for
// the momentum vector, whose three components round independently). Measured: the worst nodes use up to 0.94 of
// it; they are stencil fringes that one or two particles reach with weights far below a quantum, which the dither
// rounds to 0 or to one quantum. Full nodes use a small part of it: their errors cancel like a random walk.
TEST(P2GAtomics, FixedPointSumsMatchDoubleWithinResolution) {
  for (const auto& [kernel, transfer] : kKernelTransfers) {
    const Comparison comparison = compareOnGpu(snowball(kernel, transfer, "fixed"));
    const double quantum = comparison.scale.resolution();
    ASSERT_FALSE(comparison.nodes.empty());
    double worstMass = 0, worstMomentum = 0;
    for (const firn::bench::NodeSumError& node : comparison.nodes) {
      const double n = node.reference.contributions;
      const double massBound = n * quantum + (kUnitRoundoff + kContributionMismatch) * node.reference.massUnits;
      const double momentumBound =
          std::sqrt(3.0) * n * quantum + (kUnitRoundoff + kContributionMismatch) * node.reference.momentumScaleUnits;
      worstMass = std::max(worstMass, node.massErrorUnits / massBound);
      worstMomentum = std::max(worstMomentum, node.momentumErrorUnits / momentumBound);
    }
    std::printf("[ measured ] %s, %s, k = %d: worst node error / bound: mass %.3f, momentum %.3f (%zu nodes)\n", kernel,
                transfer, comparison.scale.fractionBits, worstMass, worstMomentum, comparison.nodes.size());
    EXPECT_LE(worstMass, 1.0) << kernel << ", " << transfer;
    EXPECT_LE(worstMomentum, 1.0) << kernel << ", " << transfer;
  }
}

// Float atomics add n contributions in whatever order the GPU's invocations arrive (a row's in the order of its
// particles, then the rows' sums at the node); each addition rounds to
// within u of the running sum, so the sum is within (n − 1)·u·Σ|c| of the exact one (Higham, Accuracy and
// Stability of Numerical Algorithms, §4.2), plus kContributionMismatch·Σ|c| for the contributions themselves.
// That worst case aligns every rounding. They are independent and of either sign, each uniform within half an ulp
// of the running sum (a standard deviation of at most u·Σ|c|/√3), so the typical error is u·Σ|c|·√(n/3) at most:
// 5e-7 of a full node's sum with the quadratic kernel (n ≈ 8·27), 8e-7 with the cubic (n ≈ 8·64). Asserted: the
// RMS relative error over the nodes holding a particle's mass or more (SumErrorSummary) below 1e-6.
// Measured: 2e-7 to 3e-7.
TEST(P2GAtomics, FloatSumsMatchDoubleWithinRounding) {
  for (const std::string atomics : {"float"}) {
    // Float atomics need GL_NV_shader_atomic_float.
    if (atomics == "float" && !firn::test::glContext().info().hasFloatAtomics) continue;
    for (const auto& [kernel, transfer] : kKernelTransfers) {
      const Comparison comparison = compareOnGpu(snowball(kernel, transfer, atomics));
      ASSERT_FALSE(comparison.nodes.empty());
      double worstMass = 0, worstMomentum = 0;
      for (const firn::bench::NodeSumError& node : comparison.nodes) {
        const double relativeBound = (node.reference.contributions - 1) * kUnitRoundoff + kContributionMismatch;
        worstMass = std::max(worstMass, node.massErrorUnits / (relativeBound * node.reference.massUnits));
        worstMomentum =
            std::max(worstMomentum, node.momentumErrorUnits / (relativeBound * node.reference.momentumScaleUnits));
      }
      const firn::bench::SumErrorSummary summary = firn::bench::summarizeErrors(comparison.nodes);
      std::printf("[ measured ] %s atomics, %s, %s: worst node error / bound: mass %.3f, momentum %.3f; RMS relative "
                  "error: mass %.2e, momentum %.2e\n",
                  atomics.c_str(), kernel, transfer, worstMass, worstMomentum, summary.massRmsRelative,
                  summary.momentumRmsRelative);
      EXPECT_LE(worstMass, 1.0) << atomics << ", " << kernel << ", " << transfer;
      EXPECT_LE(worstMomentum, 1.0) << atomics << ", " << kernel << ", " << transfer;
      EXPECT_LT(summary.massRmsRelative, 1e-6) << atomics << ", " << kernel << ", " << transfer;
      EXPECT_LT(summary.momentumRmsRelative, 1e-6) << atomics << ", " << kernel << ", " << transfer;
    }
  }
}

}  // namespace
