// Validation against numbers from outside the project: conservation laws the transfer schemes are known to
// keep or break (Jiang et al. 2015), and the analytic vibration period of an elastic bar. Each tolerance says
// where it comes from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "ElasticBar.h"
#include "GlTest.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"

namespace {

constexpr double pi = 3.14159265358979323846;

using firn::bench::barAnalyticPeriodS;
using firn::bench::BarVibration;
using firn::bench::kBarDensityKgPerM3;
using firn::bench::kBarLengthM;
using firn::bench::kBarWidthM;
using firn::bench::kBarYoungsModulusPa;
using firn::bench::stayedElastic;

// A number as JSON text, with every digit a double needs.
std::string jsonNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

// λ + 2μ = E (1 − ν) / ((1 + ν)(1 − 2ν)), the modulus of the dilatational (P) wave.
double pWaveModulus(double youngsModulusPa, double poissonRatio) {
  return youngsModulusPa * (1 - poissonRatio) / ((1 + poissonRatio) * (1 - 2 * poissonRatio));
}

// The kernel's second moment D = Σ_i w_ip (x_i − x_p)² per axis: h²/4 for the quadratic B-spline, h²/3 for
// the cubic one (APIC's D_p, Jiang et al. 2015).
double kernelSecondMoment(const std::string& kernel, double cellSizeM) {
  return cellSizeM * cellSizeM / (kernel == "cubic" ? 3.0 : 4.0);
}

// Angular momentum about the z axis through the centre of mass, L = Σ m ((x − c) × v)_z, and the moment of
// inertia I = Σ m |(x − c)_⊥|², from the particles alone.
struct Spin {
  double massKg = 0;
  double angularMomentum = 0;  // kg m²/s
  double inertia = 0;          // kg m²
};

Spin spinAboutZ(const firn::ParticleSnapshot& s) {
  Spin spin;
  glm::dvec3 centerM(0.0);
  for (std::size_t i = 0; i < s.size(); ++i) {
    spin.massKg += s.positionMass[i].w;
    centerM += double(s.positionMass[i].w) * glm::dvec3(s.positionMass[i]);
  }
  centerM /= spin.massKg;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double m = s.positionMass[i].w;
    const glm::dvec3 r = glm::dvec3(s.positionMass[i]) - centerM;
    const glm::dvec3 v(s.velocityVolume[i]);
    spin.angularMomentum += m * (r.x * v.y - r.y * v.x);
    spin.inertia += m * (r.x * r.x + r.y * r.y);
  }
  return spin;
}

class Validation : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { firn::test::glContext(); }
  static const firn::gl::ContextInfo& gl() { return firn::test::glContext().info(); }
};

// A snowball (R = 5h, 4,190 particles) spinning freely at ω = 20 rad/s without gravity, for 100 steps of
// 3e-4 s, once with APIC and once with pure PIC (flip_ratio 0), with each kernel.
//
// APIC conserves angular momentum exactly in both transfers and in the grid update (Jiang et al. 2015, "The
// Affine Particle-In-Cell Method"; the Kirchhoff stress is symmetric, so the elastic forces exert no torque).
// The conserved total is L_p + Σ_p m_p ε : B_pᵀ, where part of the spin lives in the affine matrices, which
// the snapshot does not read back. For a rigid rotation B_p = [ω]× D (D the kernel's second moment), so that
// part is 2DMω with ω = L_p / I_p, and the total is L_p (1 + 2DM / I_p). It starts as L_p(0), C_p being 0.
// (The first step moves about 2DM / (I_p + 2DM) of L_p into the affine matrices: L_p drops to 0.9552 of L0
// with the quadratic kernel, 0.9414 with the cubic, against 0.9525 and 0.9376 for rigid motion; which is why
// L_p alone is not the measure.)
// The rigid estimate is exact only for rigid motion. The start excites elastic vibration (the surface nodes
// first get less than rigid velocity, and the body has no centrifugal prestress), during which the estimate
// swings by up to 2.1e-3 (measured, steps 5–45); by step 50 (1.6 wave crossing times 2R/c) it is below
// 1.9e-4 and averages out: measured every 5 steps over steps 50–100, the worst deviation of the estimated
// total from L0 is 1.9e-4 (quadratic) and 1.2e-4 (cubic), the mean 2e-6 and 9e-6. Bounds: worst 1e-3, mean
// 1e-4; a loss of PIC's kind would exceed both in one step.
//
// PIC forgets the affine part every step: the grid receives L_p (the weights reproduce linear functions) and
// spreads it over the grid's larger inertia I_p + 2DM, and G2P hands back only the rigid part. A rigidly
// spinning body therefore keeps I_p / (I_p + 2DM) of its spin per step: a loss of about 2D / (I_p / M)
// = 5D / R² for a sphere (I_p / M = 2R²/5), i.e. 1.25 (h/R)² (quadratic) or 1.67 (h/R)² (cubic) per step,
// whatever Δt. Measured over steps 1–41: 4.82 % per step against 4.75 % predicted (quadratic), 6.47 %
// against 6.24 % (cubic, whose wider stencil leaves the surface nodes' velocities less rigid); tolerance 10 %
// of the predicted rate. After the 100 steps PIC keeps < 1 % of L0 (measured 0.63 % and 0.08 %), over 100×
// APIC's loss (measured: APIC's estimated total ends at 1.00005 and 1.00004 of L0).
TEST_F(Validation, ApicKeepsAngularMomentumWherePicDampsIt) {
  const double cellSizeM = 0.05, radiusM = 0.25, omega = 20, dtS = 3e-4;
  // E = 1e6 Pa, ν = 0.2, ρ = 400: c = sqrt((λ + 2μ)/ρ) = 52.7 m/s, so h / c = 9.5e-4 s > dt. The centrifugal
  // strain ρ ω² R² / E ≈ 1 % stays far inside the clamps [1 − θc, 1 + θs] = [0.5, 2] (checked: J_P stays 1).
  const auto sceneFor = [&](const std::string& kernel, const std::string& transfer) {
    return firn::parseScene(R"({
      "grid": { "cells": [32, 32, 32], "cell_size": )" + jsonNumber(cellSizeM) + R"( },
      "time": { "dt": )" + jsonNumber(dtS) + R"(, "frame_rate": 50, "frames": 1 },
      "gravity": [0, 0, 0],
      "solver": { "kernel": ")" + kernel + R"(", "transfer": )" + transfer + R"( },
      "materials": { "snow": { "model": "snow", "youngs_modulus": 1e6, "poisson_ratio": 0.2, "density": 400,
                               "critical_compression": 0.5, "critical_stretch": 1, "hardening": 0 } },
      "bodies": [ { "shape": "sphere", "center": [0.8, 0.8, 0.8], "radius": )" + jsonNumber(radiusM) + R"(,
                    "material": "snow", "angular_velocity": [0, 0, )" + jsonNumber(omega) + R"(] } ] })",
                            "spinning snowball");
  };
  constexpr int steps = 100, settledStep = 50, sampleEvery = 5;
  constexpr int decayFrom = 1, decayTo = 41;
  for (const std::string kernel : {"quadratic", "cubic"}) {
    const double D = kernelSecondMoment(kernel, cellSizeM);

    const firn::Scene apicScene = sceneFor(kernel, R"("apic")");
    firn::Simulation apic(apicScene, firn::sampleBodies(apicScene), gl());
    const Spin start = spinAboutZ(apic.snapshot());
    // The sampler sets v = ω × (x − c) exactly, up to float32 velocities.
    ASSERT_NEAR(start.angularMomentum, omega * start.inertia, 1e-6 * omega * start.inertia);
    double worstApicDrift = 0, meanApicDrift = 0, apicKept = 0;
    int samples = 0;
    for (int step = 1; step <= steps; ++step) {
      apic.step(dtS);
      if (step < settledStep || step % sampleEvery != 0) continue;
      const Spin spin = spinAboutZ(apic.snapshot());
      apicKept = spin.angularMomentum * (1 + 2 * D * spin.massKg / spin.inertia) / start.angularMomentum;
      worstApicDrift = std::max(worstApicDrift, std::abs(apicKept - 1));
      meanApicDrift += apicKept - 1;
      ++samples;
    }
    meanApicDrift /= samples;
    apic.checkWatchdog();
    EXPECT_TRUE(stayedElastic(apic.snapshot())) << kernel << ": the clamps acted; the test needs a purely elastic body";
    EXPECT_LT(worstApicDrift, 1e-3) << kernel;
    EXPECT_LT(std::abs(meanApicDrift), 1e-4) << kernel;

    const firn::Scene picScene = sceneFor(kernel, R"("pic_flip", "flip_ratio": 0)");
    firn::Simulation pic(picScene, firn::sampleBodies(picScene), gl());
    double decayStart = 0, decayEnd = 0;
    for (int step = 1; step <= steps; ++step) {
      pic.step(dtS);
      if (step == decayFrom) decayStart = spinAboutZ(pic.snapshot()).angularMomentum;
      if (step == decayTo) decayEnd = spinAboutZ(pic.snapshot()).angularMomentum;
    }
    pic.checkWatchdog();
    const double picKept = spinAboutZ(pic.snapshot()).angularMomentum / start.angularMomentum;
    const double measuredLossPerStep = 1 - std::pow(decayEnd / decayStart, 1.0 / (decayTo - decayFrom));
    const double predictedLossPerStep = 2 * D * start.massKg / (start.inertia + 2 * D * start.massKg);
    EXPECT_NEAR(measuredLossPerStep, predictedLossPerStep, 0.1 * predictedLossPerStep) << kernel;
    EXPECT_LT(picKept, 0.01) << kernel;
    EXPECT_GT(1 - picKept, 100 * std::abs(1 - apicKept)) << kernel;
    std::printf("[ measured ] %s: APIC keeps %.6f of L0 (steps %d-%d: worst %.1e, mean %+.1e); PIC keeps %.5f, "
                "losing %.2f %% per step (predicted %.2f %%)\n",
                kernel.c_str(), apicKept, settledStep, steps, worstApicDrift, meanApicDrift, picKept,
                100 * measuredLossPerStep, 100 * predictedLossPerStep);
  }
}

// The vibrating bar (benchmarks/ElasticBar.h, shared with `firn bench`'s speed/accuracy table), measured over
// one period with APIC, fixed-point atomics, 8 particles per cell and dt = 0.4 h / c.
// `model` is "snow" (with hardening 0 and clamps it never reaches) or "fixed_corotated".
BarVibration measureBarPeriod(const std::string& kernel, int cellsAlongBar, double poissonRatio, const std::string& model,
                              const firn::gl::ContextInfo& gl) {
  firn::bench::BarSetup setup;
  setup.model = model;
  setup.poissonRatio = poissonRatio;
  setup.kernel = kernel;
  setup.cellsAlongBar = cellsAlongBar;
  return firn::bench::measureBarVibration(setup, gl);
}

// The longitudinal vibration of a free–free bar, L = 0.72 m by 0.12 m by 0.12 m, started in its fundamental
// mode, at two resolutions (h = L/18, 1,296 particles; h = L/36, 10,368 particles) with each kernel.
// Snow with hardening ξ = 0 and clamps it never reaches ([0.1, 11]; checked: J_P stays 1) is Stomakhin 2013's
// fixed corotated energy, eq. 6, and nothing else. With ν = 0 (λ = 0) a uniaxial displacement u(x) is an exact
// solution for any cross-section: the lateral faces carry no traction, and the stress 2μ(F − R) = E (F − I) is
// even linear in the stretch. The wave speed is c = sqrt(E/ρ) and the period T = 2L / c (the classical
// free–free rod; e.g. Graff, Wave Motion in Elastic Solids). The period is measured as the second zero crossing
// of the modal displacement, which filters out the higher modes that the slabs' velocity steps excite.
//
// The initial volumes are the grid density's, V0 = m / max(ρ_grid, ρ) (docs/algorithm.md eq. 6a). Without the
// max, ρ_grid read ρ too low near a free surface, so the particles near one carried more volume, and that much
// more stress, than they have: the outermost layer at a face 1.6–1.8× its m/ρ, edge and corner particles up to
// 5×, and this bar's period came out 21–23 % (h = L/18) and 12–13 % (h = L/36) short of 2L/c. The fundamental's
// Rayleigh quotient with the volumes used, ω² = (π/L)² (E/ρ) κ with κ = Σ V0 sin²(πX/L) / Σ (m/ρ) sin²(πX/L)
// (the strain energy weighted by the mode's strain), predicts the period T / √κ, and that is what is checked;
// κ is now 1.0000 (h = L/18) and 0.9993–0.9998 (h = L/36), where the grid reads an interior particle denser than ρ.
//
// Tolerance, from a measured convergence: the remaining error (measured / (T/√κ) − 1) was +1.04 % / +0.47 %
// (quadratic, h = L/18 / L/36) and +0.80 % / +0.35 % (cubic) with the unbounded volumes, +0.73 % / +0.32 % and
// +0.62 % / +0.23 % now, shrinking about 0.45× as h halves. Its sign
// and size agree with the lumped-mass dispersion of degree-p B-spline elements with exact stiffness,
// ω_h² / ω² = sinc^{2(p+1)}(kh/2), i.e. a period longer by (p+1)(kh)²/24 = +0.38 % / +0.51 % at kh = π/18;
// the rest (particle quadrature at 2 particles per cell and axis, the κ model) is not separated here.
// Asserted: below 2 % at L/18 and 1 % at L/36 (about twice the measured errors), and shrinking by at least
// 0.6× when h halves.
TEST_F(Validation, ElasticBarVibratesAtAnalyticPeriod) {
  const double analyticPeriodS = barAnalyticPeriodS();
  for (const std::string kernel : {"quadratic", "cubic"}) {
    std::vector<double> errors;
    for (const int cellsAlongBar : {18, 36}) {
      const BarVibration bar = measureBarPeriod(kernel, cellsAlongBar, 0.0, "snow", gl());
      EXPECT_TRUE(bar.elastic) << kernel << ": the clamps were reached; the test needs a purely elastic body";
      ASSERT_GT(bar.periodS, 0) << kernel << " at h = L/" << cellsAlongBar << ": no full period";
      const double predictedS = analyticPeriodS / std::sqrt(bar.kappa);
      errors.push_back(bar.periodS / predictedS - 1);
      std::printf("[ measured ] %s, h = L/%d: T = %.6f s against 2L/c = %.6f s (%+.2f %%); kappa = %.4f, "
                  "against T/sqrt(kappa) = %.6f s (%+.2f %%)\n",
                  kernel.c_str(), cellsAlongBar, bar.periodS, analyticPeriodS,
                  100 * (bar.periodS / analyticPeriodS - 1), bar.kappa, predictedS, 100 * errors.back());
    }
    EXPECT_LT(std::abs(errors[0]), 0.02) << kernel << " at h = L/18";
    EXPECT_LT(std::abs(errors[1]), 0.01) << kernel << " at h = L/36";
    EXPECT_LT(std::abs(errors[1]), 0.6 * std::abs(errors[0])) << kernel << ": the error does not shrink with h";
  }
}

// The same bar with "particle_volume": "material_density": V0 = m / ρ exactly, so κ = 1 and the period is
// checked against 2L/c itself. What remains is the discretization error that ElasticBarVibratesAtAnalyticPeriod
// measured against T/√κ (the period longer by about 1 % at h = L/18 and 0.5 % at L/36, shrinking as h²), so
// the same bounds: below 2 % at L/18, 1 % at L/36, and shrinking by at least 0.6× as h halves (measured:
// +0.73 % / +0.32 % quadratic, +0.62 % / +0.23 % cubic). With Stomakhin's grid-density volumes unbounded by ρ the
// same bar was 12–23 % short of 2L/c.
TEST_F(Validation, ElasticBarWithMaterialVolumesVibratesAtTwoLengthsOverWaveSpeed) {
  const double analyticPeriodS = barAnalyticPeriodS();
  for (const std::string kernel : {"quadratic", "cubic"}) {
    std::vector<double> errors;
    for (const int cellsAlongBar : {18, 36}) {
      firn::bench::BarSetup setup;
      setup.kernel = kernel;
      setup.cellsAlongBar = cellsAlongBar;
      setup.particleVolume = "material_density";
      const BarVibration bar = firn::bench::measureBarVibration(setup, gl());
      ASSERT_GT(bar.periodS, 0) << kernel << " at h = L/" << cellsAlongBar << ": no full period";
      EXPECT_NEAR(bar.kappa, 1.0, 1e-5) << "V0 = m / rho exactly";
      errors.push_back(bar.periodS / analyticPeriodS - 1);
      std::printf("[ measured ] %s, h = L/%d, V0 = m/rho: T = %.6f s against 2L/c = %.6f s (%+.2f %%)\n",
                  kernel.c_str(), cellsAlongBar, bar.periodS, analyticPeriodS, 100 * errors.back());
    }
    EXPECT_LT(std::abs(errors[0]), 0.02) << kernel << " at h = L/18";
    EXPECT_LT(std::abs(errors[1]), 0.01) << kernel << " at h = L/36";
    EXPECT_LT(std::abs(errors[1]), 0.6 * std::abs(errors[0])) << kernel << ": the error does not shrink with h";
  }
}

// The same bar made of the fixed corotated material (Blažević 2022 §4.2.2) rather than of snow without plasticity,
// at h = L/18 with each kernel. The two are one energy (Stomakhin 2013 eq. 6 with ξ = 0 and no clamping) and
// differ only in float rounding (snow rebuilds F_E = U Σ Vᵀ from its SVD, fixed corotated keeps F̂): measured
// periods differ by 4e-6 (quadratic) and 3.6e-5 (cubic) of T; tolerance 4e-4, about 10× that. The fixed
// corotated bar also meets ElasticBarVibratesAtAnalyticPeriod's tolerance at this resolution (2 % from T / √κ).
TEST_F(Validation, FixedCorotatedBarVibratesLikeSnowWithoutPlasticity) {
  const double analyticPeriodS = barAnalyticPeriodS();
  for (const std::string kernel : {"quadratic", "cubic"}) {
    const BarVibration snow = measureBarPeriod(kernel, 18, 0.0, "snow", gl());
    const BarVibration fixedCorotated = measureBarPeriod(kernel, 18, 0.0, "fixed_corotated", gl());
    ASSERT_GT(fixedCorotated.periodS, 0) << kernel << ": no full period";
    std::printf("[ measured ] %s, h = L/18: fixed corotated T = %.7f s, snow without plasticity %.7f s\n",
                kernel.c_str(), fixedCorotated.periodS, snow.periodS);
    EXPECT_NEAR(fixedCorotated.periodS, snow.periodS, 4e-4 * snow.periodS) << kernel;
    EXPECT_LT(std::abs(fixedCorotated.periodS / (analyticPeriodS / std::sqrt(fixedCorotated.kappa)) - 1), 0.02)
        << kernel;
  }
}

// A thin bar with ν = 0.3 vibrates at the bar speed sqrt(E/ρ), not at the dilatational speed sqrt((λ+2μ)/ρ),
// 16 % faster at ν = 0.3: its lateral faces are free, so it thins as it stretches. Lateral inertia lengthens
// the period by ν²π² r² / (2L²) (Rayleigh–Love; r² = w²/6, the square section's polar radius of gyration
// squared): +0.2 % at L/w = 6. Quadratic kernel, h = L/18, with the volume factor κ of
// ElasticBarVibratesAtAnalyticPeriod, whose tolerance at that resolution (2 %) applies. Measured: T √κ is
// +1.18 % from the corrected bar period (+1.39 % from 2L/c; the ν = 0 bar measured +1.04 %) and +17.6 % from
// the dilatational one.
TEST_F(Validation, ThinBarVibratesAtBarSpeed) {
  const double poissonRatio = 0.3;
  const BarVibration bar = measureBarPeriod("quadratic", 18, poissonRatio, "snow", gl());
  EXPECT_TRUE(bar.elastic);
  ASSERT_GT(bar.periodS, 0) << "no full period";
  const double radiusOfGyrationSquared = kBarWidthM * kBarWidthM / 6;
  const double rayleighLove =
      1 + poissonRatio * poissonRatio * pi * pi * radiusOfGyrationSquared / (2 * kBarLengthM * kBarLengthM);
  const double barPeriodS = barAnalyticPeriodS() * rayleighLove;
  const double dilatationalPeriodS =
      2 * kBarLengthM / std::sqrt(pWaveModulus(kBarYoungsModulusPa, poissonRatio) / kBarDensityKgPerM3);
  // The period the bar would have with its true volumes (κ as in ElasticBarVibratesAtAnalyticPeriod).
  const double volumeCorrectedPeriodS = bar.periodS * std::sqrt(bar.kappa);
  const double error = volumeCorrectedPeriodS / barPeriodS - 1;
  std::printf("[ measured ] nu = 0.3: T sqrt(kappa) = %.6f s against the bar's %.6f s (%+.2f %%) and the "
              "dilatational %.6f s (%+.2f %%)\n",
              volumeCorrectedPeriodS, barPeriodS, 100 * error, dilatationalPeriodS,
              100 * (volumeCorrectedPeriodS / dilatationalPeriodS - 1));
  EXPECT_LT(std::abs(error), 0.02);
}

}  // namespace
