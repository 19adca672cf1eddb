#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "Error.h"
#include "gpu/Materials.h"
#include "scene/Scene.h"
#include "sim/FixedPoint.h"

namespace {

// Stomakhin 2013's reference snow, E0 = 1.4e5 Pa, ν = 0.2: μ = E/(2(1+ν)) = 58,333.3 Pa and
// λ = Eν/((1+ν)(1−2ν)) = 38,888.9 Pa, computed by hand. Tolerance: double rounding, 1e-9 relative.
TEST(Materials, LameParametersOfReferenceSnow) {
  const firn::LameParameters lame = firn::lameParameters(1.4e5, 0.2);
  EXPECT_NEAR(lame.muPa, 58333.333333333, 1e-9 * 58333.3);
  EXPECT_NEAR(lame.lambdaPa, 38888.888888889, 1e-9 * 38888.9);
}

// ν = 0 decouples the axes (λ = 0, μ = E/2); as ν → 0.5, λ grows without bound (incompressibility).
TEST(Materials, LameParametersAtPoissonLimits) {
  EXPECT_EQ(firn::lameParameters(1e6, 0.0).lambdaPa, 0.0);
  EXPECT_DOUBLE_EQ(firn::lameParameters(1e6, 0.0).muPa, 5e5);
  EXPECT_GT(firn::lameParameters(1e6, 0.499).lambdaPa, 100 * firn::lameParameters(1e6, 0.499).muPa);
}

// Wave speed c = sqrt((λ + 2μ) e^{ξθc} / ρ); for the reference snow (λ + 2μ = 155,555.6 Pa, e^{0.25} = 1.2840,
// ρ = 400) c = 22.35 m/s, so h = 0.02 m gives dt < 8.95e-4 s. Tolerance 1e-3 relative: the hand arithmetic.
TEST(Materials, ElasticStableTimeStep) {
  firn::Material snow;
  EXPECT_NEAR(firn::waveSpeedMPerS(snow), 22.35, 22.35e-3);
  EXPECT_NEAR(firn::elasticStableDtS(snow, 0.02), 8.95e-4, 8.95e-7);
}

// 8 particles per cell: the bound 8 × 8 (compression) × 4 (cells per step) = 256 = 2^8 takes 8 bits, so 23 of
// the 31 magnitude bits are resolution; 64 per cell takes 11 bits and leaves 20.
TEST(FixedPoint, ScaleFollowsParticlesPerCell) {
  const firn::FixedPointScale eight = firn::deriveFixedPointScale(1e-3, 8, 0.02, 1e-4);
  EXPECT_EQ(eight.fractionBits, 23);
  EXPECT_DOUBLE_EQ(eight.maxNodeValue(), 256.0);
  EXPECT_DOUBLE_EQ(eight.momentumUnitKgMPerS, 1e-3 * 0.02 / 1e-4);
  EXPECT_EQ(firn::deriveFixedPointScale(1e-3, 64, 0.02, 1e-4).fractionBits, 20);
  // The bound must fit: maxNodeValue ≥ particles per cell × both margins.
  for (double ppc : {1.0, 3.0, 8.0, 27.0, 64.0, 125.0}) {
    const firn::FixedPointScale scale = firn::deriveFixedPointScale(1e-3, ppc, 0.02, 1e-4);
    EXPECT_GE(scale.maxNodeValue(),
              ppc * firn::kFixedPointCompressionMargin * firn::kFixedPointVelocityMarginCellsPerStep);
    EXPECT_LT(scale.maxNodeValue(),
              2 * ppc * firn::kFixedPointCompressionMargin * firn::kFixedPointVelocityMarginCellsPerStep);
  }
}

// k_H, the semi-implicit Hessian product's scale: the largest P2G node value (256 at 8 per cell) times (c Δt / h)²
// (at least 1) times 2^8 for hardening must fit below 2^62 in units of 2^−k_H, and k_H is the largest that fits:
// 256 · 1 · 256 = 2^16 gives 46 bits; at c Δt / h = 30, 2^16 · 900 < 2^26 gives 36; at 100, < 2^30 gives 32.
TEST(FixedPoint, SolverScaleLeavesRoomForTheStiffestWave) {
  const firn::FixedPointScale eight = firn::deriveFixedPointScale(1e-3, 8, 0.02, 1e-4);
  const double cellSizeM = 0.02, dtS = 1e-3;
  const auto bitsAtCourant = [&](double courant) {
    return firn::deriveSolverFractionBits(eight, courant * cellSizeM / dtS, cellSizeM, dtS);
  };
  EXPECT_EQ(bitsAtCourant(0.5), 46);
  EXPECT_EQ(bitsAtCourant(1), 46);
  EXPECT_EQ(bitsAtCourant(30), 36);
  EXPECT_EQ(bitsAtCourant(100), 32);
  for (double courant : {0.5, 2.0, 7.0, 30.0, 94.0, 300.0}) {
    const int bits = bitsAtCourant(courant);
    const double largest = eight.maxNodeValue() * std::max(1.0, courant * courant) * 256;
    EXPECT_LE(largest, std::ldexp(1.0, 62 - bits)) << "c dt / h = " << courant;
    EXPECT_GT(largest, std::ldexp(1.0, 61 - bits)) << "c dt / h = " << courant;  // no bit left unused
  }
}

TEST(FixedPoint, TooManyParticlesPerCellIsBadInput) {
  EXPECT_THROW(firn::deriveFixedPointScale(1e-3, 1e6, 0.02, 1e-4), firn::InputError);
}

}  // namespace
