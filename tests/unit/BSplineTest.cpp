// The B-spline weights the shaders use, checked on the CPU: this file includes shaders/common/bspline.glsl
// itself, so what is tested is the one copy of the weight code.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/common.hpp>

namespace firn::bspline {
using glm::abs;
using glm::sign;
#include "common/bspline.glsl"
}  // namespace firn::bspline

namespace {

using namespace firn::bspline;

struct Kernel {
  const char* name;
  float (*weight)(float);
  float (*slope)(float);
  float supportCells;
};

const Kernel kKernels[] = {{"quadratic", quadraticBSpline, quadraticBSplineSlope, 1.5f},
                           {"cubic", cubicBSpline, cubicBSplineSlope, 2.0f}};

// Σ_i f(x − i) over the nodes around x.
double sumOverNodes(float (*f)(float), float x) {
  double sum = 0;
  for (int node = 5; node <= 15; ++node) sum += f(x - float(node));
  return sum;
}

// Σ_i N(x − i) = 1 for every x: mass and momentum transfers neither create nor destroy anything; and
// Σ_i N'(x − i) = 0, its derivative, so internal forces sum to zero.
// Tolerance: a handful of float32 roundings of O(1) terms, 4 × 2⁻²³ ≈ 5e-7.
TEST(BSpline, PartitionOfUnityAndZeroSlopeSum) {
  for (const Kernel& kernel : kKernels) {
    for (int sample = 0; sample <= 1000; ++sample) {
      const float x = 10.0f + float(sample) / 1000.0f;
      EXPECT_NEAR(sumOverNodes(kernel.weight, x), 1.0, 5e-7) << kernel.name << " at x = " << x;
      EXPECT_NEAR(sumOverNodes(kernel.slope, x), 0.0, 5e-7) << kernel.name << " at x = " << x;
    }
  }
}

// Σ_i (i − x) N(x − i) = 0: B-splines reproduce linear functions, which APIC's affine transfer relies on.
TEST(BSpline, FirstMomentVanishes) {
  for (const Kernel& kernel : kKernels) {
    for (int sample = 0; sample <= 100; ++sample) {
      const float x = 10.0f + float(sample) / 100.0f;
      double moment = 0;
      for (int node = 5; node <= 15; ++node) moment += (node - double(x)) * kernel.weight(x - float(node));
      EXPECT_NEAR(moment, 0.0, 2e-6) << kernel.name << " at x = " << x;
    }
  }
}

// The analytic slope matches a central difference of the weight. Step 1e-3: the difference's truncation
// error is (δ²/6)·|N'''| ≤ 1e-6·(1/6)·3 and its rounding error 2⁻²⁴/δ ≈ 6e-5; tolerance 2e-4 covers both.
// Points within 2δ of the knots, where N'' jumps, are skipped.
TEST(BSpline, SlopeMatchesFiniteDifference) {
  const float delta = 1e-3f;
  for (const Kernel& kernel : kKernels) {
    for (int sample = -400; sample <= 400; ++sample) {
      const float d = float(sample) / 200.0f * kernel.supportCells / 2.0f * 1.1f;
      const float toKnot = std::abs(std::fmod(std::abs(d) + 0.25f, 0.5f) - 0.25f);
      if (toKnot < 2 * delta) continue;
      const double difference = (double(kernel.weight(d + delta)) - kernel.weight(d - delta)) / (2.0 * delta);
      EXPECT_NEAR(kernel.slope(d), difference, 2e-4) << kernel.name << " at d = " << d;
    }
  }
}

// Compact support: no weight beyond 1.5 (quadratic) or 2 (cubic) cells, which sizes the 27/64-node stencil.
TEST(BSpline, VanishesOutsideSupport) {
  for (const Kernel& kernel : kKernels) {
    EXPECT_EQ(kernel.weight(kernel.supportCells), 0.0f) << kernel.name;
    EXPECT_EQ(kernel.weight(-kernel.supportCells - 0.1f), 0.0f) << kernel.name;
    EXPECT_EQ(kernel.slope(kernel.supportCells + 0.1f), 0.0f) << kernel.name;
    EXPECT_GT(kernel.weight(kernel.supportCells - 0.01f), 0.0f) << kernel.name;
  }
  // Peak values: 3/4 and 2/3 (Jiang et al. 2016, eq. 123–124).
  EXPECT_FLOAT_EQ(quadraticBSpline(0.0f), 0.75f);
  EXPECT_FLOAT_EQ(cubicBSpline(0.0f), 2.0f / 3.0f);
}

}  // namespace
