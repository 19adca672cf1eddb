#pragma once
// A reference problem with a known answer, shared by the validation tests (tests/gl/ValidationTest.cpp) and
// the benchmarks' speed/accuracy table: the longitudinal vibration of a free–free elastic bar, L = 0.72 m along
// x with a 0.12 m square section, E = 1e6 Pa, ρ = 400 kg/m³, started in its fundamental mode at 0.25 m/s
// (strain amplitude v0 / c = 0.5 %), without gravity.
//
// With ν = 0 a uniaxial displacement is an exact solution for any cross-section, the wave speed is c = √(E/ρ)
// and the period T = 2L / c (the classical free–free rod; e.g. Graff, Wave Motion in Elastic Solids). The
// solver's initial volumes V0 = m / ρ_grid (Stomakhin 2013 §6 step 2) are too large near a free surface, which
// stiffens a thin bar: its Rayleigh quotient with those volumes predicts T / √κ, κ = Σ V0 sin²(πX/L) /
// Σ (m/ρ) sin²(πX/L) (ValidationTest.cpp's ElasticBarVibratesAtAnalyticPeriod says how that was measured).
#include <string>
#include <vector>

#include "gl/Context.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"

namespace firn::bench {

constexpr double kBarLengthM = 0.72;
constexpr double kBarWidthM = 0.12;
constexpr double kBarYoungsModulusPa = 1e6;
constexpr double kBarDensityKgPerM3 = 400;
constexpr double kBarSpeedAmplitudeMPerS = 0.25;
constexpr int kBarMinimumSteps = 12;

// 2L / √(E/ρ): the period of the bar's fundamental with ν = 0 and exact volumes.
double barAnalyticPeriodS();

struct BarSetup {
  std::string model = "snow";  // "snow" (hardening 0, clamps it never reaches) or "fixed_corotated"
  double poissonRatio = 0;
  std::string kernel = "quadratic";
  std::string transfer = "apic";  // or "pic_flip", with flipRatio (0: pure PIC)
  double flipRatio = 0.95;
  std::string atomics = "fixed";
  std::string particleVolume = "grid_density";  // or "material_density": V0 = m / ρ, κ = 1
  int cellsAlongBar = 18;         // h = L / cellsAlongBar
  double particlesPerCell = 8;
  double dtFraction = 0.4;        // dt as a fraction of the elastic bound h / c (gpu/Materials.h)
  int periods = 1;                // how many periods to measure
  std::string integrator = "explicit";  // or "semi_implicit" (its defaults: β = 1, tolerance 1e-4)
  double implicitRatio = 1;             // semi-implicit: β
};

// Whether the snow model's plasticity clamps never acted: J_P ← J_P det F̂_E / det F_E stays 1 up to the float
// rounding of that quotient (about one ulp, 6e-8, per step; measured at most 3e-6 after 100 steps). Bound 1e-4.
bool stayedElastic(const ParticleSnapshot& particles);

// The bar as a scene: one box body per cell-thick slab, each at its centre's velocity v0 cos(πx/L) (bodies of
// one material merge on the grid), 5 cells of margin on every side (2 wall cells, the stencil, room for the
// ends' motion).
Scene barScene(const BarSetup& setup);

struct BarVibration {
  double periodS = 0;            // the 2N-th zero crossing of the modal displacement over N; 0 if not reached
  double kappa = 0;              // the Rayleigh quotient's volume factor κ
  bool elastic = false;          // whether J_P stayed 1 (the snow model's clamps never acted)
  // The modal displacement's peak in the last half period over that in the first; without a period (a step too
  // long to resolve one), its peak over the last half of the steps over that over the first half.
  double amplitudeRetained = 0;
  double meanSolverIterations = 0;  // semi-implicit: conjugate residual iterations per step
  double dtS = 0;
  std::size_t particles = 0;
  std::vector<double> stepWallMs;  // each step's wall time, dispatch to glFinish (the readbacks excluded)
  std::string transferShape;       // the P2G shape the run chose (sim/TransferShape.h)
  // The energy audit (sim/EnergyAudit.h) at the start and every 32nd of the steps, with its time (s): the bar has no
  // gravity and nothing enters, so its energy can only be dissipated, or made by an unstable step.
  std::vector<std::pair<double, EnergyBudget>> energy;
  // How fast its energy changed (the modified energy an explicit step keeps: EnergyBudget::stepTermJ), as a fraction
  // of its energy at the start per simulated second (< 0: dissipated).
  double energyDriftPerS = 0;
};

// The most steps measureBarVibration takes for `setup` at `dtS` (it stops earlier once it has its periods).
int barMaxSteps(const BarSetup& setup, double dtS);

// Steps the bar until its modal displacement q(t) = Σ m u_x φ / Σ m φ², φ = cos(π X / L), has crossed zero
// 2N times (N periods: q starts at 0), or for N + ½ analytic periods (and at least kBarMinimumSteps). Measuring
// q filters out the higher modes that the slabs' velocity steps excite. Throws SimulationError (exit 3) if the run
// goes unstable.
BarVibration measureBarVibration(const BarSetup& setup, const gl::ContextInfo& gl);

}  // namespace firn::bench
