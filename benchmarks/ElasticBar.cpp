#include "ElasticBar.h"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <optional>

#include <nlohmann/json.hpp>

#include "gl/GL.h"
#include "gpu/Materials.h"
#include "sim/Simulation.h"

namespace firn::bench {

namespace {

constexpr double pi = 3.14159265358979323846;
constexpr int kMarginCells = 5;  // 2 wall cells, the stencil, and room for the ends' motion

}  // namespace

bool stayedElastic(const ParticleSnapshot& particles) {
  for (const float plasticJ : particles.plasticJ) {
    if (std::abs(plasticJ - 1.0f) > 1e-4f) return false;
  }
  return true;
}

double barAnalyticPeriodS() { return 2 * kBarLengthM / std::sqrt(kBarYoungsModulusPa / kBarDensityKgPerM3); }

Scene barScene(const BarSetup& setup) {
  using Json = nlohmann::json;
  const double cellSizeM = kBarLengthM / setup.cellsAlongBar;
  const int crossCells = int(std::lround(kBarWidthM / cellSizeM));
  const double startM = kMarginCells * cellSizeM;
  Json bodies = Json::array();
  for (int k = 0; k < setup.cellsAlongBar; ++k) {
    const double velocityMPerS = kBarSpeedAmplitudeMPerS * std::cos(pi * (k + 0.5) / setup.cellsAlongBar);
    bodies.push_back({{"shape", "box"}, {"material", "bar"},
                      {"min", {startM + k * cellSizeM, startM, startM}},
                      {"max", {startM + (k + 1) * cellSizeM, startM + kBarWidthM, startM + kBarWidthM}},
                      {"velocity", {velocityMPerS, 0, 0}}, {"particles_per_cell", setup.particlesPerCell}});
  }
  Material material;
  material.model = setup.model == "snow" ? MaterialModel::Snow : MaterialModel::FixedCorotated;
  material.youngsModulusPa = kBarYoungsModulusPa;
  material.poissonRatio = setup.poissonRatio;
  material.densityKgPerM3 = kBarDensityKgPerM3;
  material.hardening = 0;
  Json materialKeys = {{"model", setup.model}, {"youngs_modulus", kBarYoungsModulusPa},
                       {"poisson_ratio", setup.poissonRatio}, {"density", kBarDensityKgPerM3}};
  if (setup.model == "snow") {
    materialKeys.update({{"critical_compression", 0.9}, {"critical_stretch", 10}, {"hardening", 0}});
  }
  Json solver = {{"kernel", setup.kernel}, {"transfer", setup.transfer}, {"atomics", setup.atomics},
                 {"particle_volume", setup.particleVolume}, {"integrator", setup.integrator}};
  if (setup.transfer != "apic") solver["flip_ratio"] = setup.flipRatio;
  if (setup.integrator == "semi_implicit") solver["implicit_ratio"] = setup.implicitRatio;
  const int crossAxisCells = crossCells + 2 * kMarginCells;
  const double dtS = setup.dtFraction * elasticStableDtS(material, cellSizeM);
  const Json scene = {
      {"grid", {{"cells", {setup.cellsAlongBar + 2 * kMarginCells, crossAxisCells, crossAxisCells}},
                {"cell_size", cellSizeM}}},
      // The elastic bound h / c, c the dilatational speed √((λ + 2μ)/ρ). Symplectic Euler shortens the period
      // by (ω dt)²/24, ≤ 2e-4 at 0.4 of it (ω dt ≤ 0.4 π h / L).
      // A frame no shorter than the step (semi-implicit steps may be longer than 1/50 s).
      {"time", {{"dt", dtS}, {"frame_rate", std::min(50.0, 0.5 / dtS)}, {"frames", 1}}},
      {"gravity", {0, 0, 0}},
      {"solver", solver},
      {"materials", {{"bar", materialKeys}}},
      {"bodies", bodies}};
  return parseScene(scene.dump(), "vibrating bar");
}

int barMaxSteps(const BarSetup& setup, double dtS) {
  return std::max(kBarMinimumSteps, int((setup.periods + 0.5) * barAnalyticPeriodS() / dtS));
}

BarVibration measureBarVibration(const BarSetup& setup, const gl::ContextInfo& gl) {
  const Scene scene = barScene(setup);
  const double dtS = scene.time.dtS;
  const double startM = kMarginCells * scene.grid.cellSizeM;
  Simulation simulation(scene, sampleBodies(scene), gl);

  const ParticleSnapshot rest = simulation.snapshot();
  std::vector<double> modeShape(rest.size());
  double modalMass = 0, strainWeightedVolume = 0, strainWeightedTrueVolume = 0;
  for (std::size_t i = 0; i < rest.size(); ++i) {
    const double phase = pi * (rest.positionMass[i].x - startM) / kBarLengthM;
    const double m = rest.positionMass[i].w;
    const double strainWeight = std::sin(phase) * std::sin(phase);
    modeShape[i] = std::cos(phase);
    modalMass += m * modeShape[i] * modeShape[i];
    strainWeightedVolume += rest.velocityVolume[i].w * strainWeight;
    strainWeightedTrueVolume += m / kBarDensityKgPerM3 * strainWeight;
  }
  const auto modalDisplacement = [&](const ParticleSnapshot& s) {
    double sum = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      sum += s.positionMass[i].w * (s.positionMass[i].x - rest.positionMass[i].x) * modeShape[i];
    }
    return sum / modalMass;
  };

  BarVibration result;
  result.kappa = strainWeightedVolume / strainWeightedTrueVolume;
  result.dtS = dtS;
  result.particles = rest.size();
  const std::optional<TransferShapeChoice>& shape = simulation.transferShapeChoice();
  if (shape) result.transferShape = transferShapeName(shape->shape);
  const int crossingsWanted = 2 * setup.periods;
  const int maxSteps = barMaxSteps(setup, dtS);
  int crossings = 0;
  double previousQ = 0, halfCyclePeak = 0, firstPeak = 0;
  std::vector<double> peaks;  // |q| per step
  const int auditEverySteps = std::max(1, maxSteps / 32);
  result.energy.emplace_back(0.0, simulation.energyBudget());
  for (int step = 1; step <= maxSteps && crossings < crossingsWanted; ++step) {
    glFinish();
    const auto start = std::chrono::steady_clock::now();
    simulation.step(dtS);
    glFinish();
    result.stepWallMs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    const double q = modalDisplacement(simulation.snapshot());
    if (step > 1 && (q > 0) != (previousQ > 0)) {
      ++crossings;
      if (crossings == 1) firstPeak = halfCyclePeak;
      if (crossings == crossingsWanted) {
        // Linear interpolation between the two steps: q is nearly straight at its zeros, where its curvature
        // vanishes.
        result.periodS = (step - 1 + previousQ / (previousQ - q)) * dtS / setup.periods;
        result.amplitudeRetained = halfCyclePeak / firstPeak;
      }
      halfCyclePeak = 0;
    }
    halfCyclePeak = std::max(halfCyclePeak, std::abs(q));
    peaks.push_back(std::abs(q));
    previousQ = q;
    if (step % auditEverySteps == 0) {
      simulation.checkWatchdog();
      result.energy.emplace_back(simulation.timeS(), simulation.energyBudget());
    }
  }
  simulation.checkWatchdog();
  result.energy.emplace_back(simulation.timeS(), simulation.energyBudget());
  // Of the modified energy the explicit step keeps, whose energy shown swings about it by the step's term.
  const auto modifiedJ = [](const EnergyBudget& budget) { return budget.totalJ() + budget.stepTermJ; };
  const double startJ = modifiedJ(result.energy.front().second);
  if (startJ > 0 && simulation.timeS() > 0) {
    result.energyDriftPerS = (modifiedJ(result.energy.back().second) - startJ) / (startJ * simulation.timeS());
  }
  if (result.periodS <= 0 && peaks.size() >= 2) {
    const auto middle = peaks.begin() + std::ptrdiff_t(peaks.size() / 2);
    const double firstHalf = *std::max_element(peaks.begin(), middle);
    result.amplitudeRetained = firstHalf > 0 ? *std::max_element(middle, peaks.end()) / firstHalf : 0;
  }
  const SolverSummary solves = simulation.takeSolverSummary();
  if (solves.solves > 0) result.meanSolverIterations = double(solves.iterations) / double(solves.solves);
  result.elastic = stayedElastic(simulation.snapshot());
  return result;
}

}  // namespace firn::bench
