// stiff.csv: snow too stiff for the explicit step's elastic bound, stepped explicitly at 0.5 h / c and
// semi-implicitly at 1e-3 s (issue 13). A snowball of h = 0.02 m cells thrown at the floor, E = 1e8 Pa (with the
// `stomakhin` preset's ρ = 400 kg/m³, ν = 0.2 and its hardening at J_P = 1 − θc, h / c = 3.3e-5 s: 1e-3 s is 30
// times the bound) and, at the default sizes, E = 1e9 Pa (h / c = 1.1e-5 s, 94 times), each run for the same
// simulated time explicitly and then semi-implicitly with the solver's defaults and with a looser tolerance (1e-3)
// and the most iterations allowed (1000). Per row: the cost of a simulated second and its ratio to the explicit
// run's, the solver's iterations and residuals, and how far the particles end from where the explicit run puts them
// (what the long step costs in accuracy). The first step, whose dispatches compile the programs, is left out of the
// time. A solve the watchdog rejects (exit 3 in
// `firn run`) is the row's status.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "Error.h"
#include "Experiments.h"
#include "gl/GL.h"
#include "gpu/Materials.h"
#include "sim/Simulation.h"

namespace firn::bench {

namespace {

constexpr double kCellSizeM = 0.02;
constexpr int kGridCells = 32;
constexpr double kSemiImplicitDtS = 1e-3;    // the thesis's step, and the issue's
constexpr double kExplicitBoundFraction = 0.5;  // of h / c, as in the tradeoff table's baseline
constexpr int kWatchdogIntervalSteps = 16;

struct StiffCase {
  std::string name;
  double youngsModulusPa = 0;
  std::string integrator;
  std::optional<double> tolerance;  // the solver's own default when unset
  std::optional<int> maxIterations;
};

Scene snowball(const StiffCase& stiff, double dtS) {
  nlohmann::json solver = {{"integrator", stiff.integrator}};
  if (stiff.tolerance) solver["tolerance"] = *stiff.tolerance;
  if (stiff.maxIterations) solver["max_iterations"] = *stiff.maxIterations;
  // A ball of 4 cells' radius, its lowest particles two cells above the floor's walls, falling at 2 m/s: it lands
  // within 0.02 s and spends the rest of the run in contact, where the solve works hardest.
  const nlohmann::json scene = {
      {"name", "stiff snowball"},
      {"grid", {{"cells", {kGridCells, kGridCells, kGridCells}}, {"cell_size", kCellSizeM}}},
      {"time", {{"dt", dtS}, {"frame_rate", 30}, {"frames", 1}}},
      {"solver", solver},
      {"materials", {{"snow", {{"preset", "stomakhin"}, {"youngs_modulus", stiff.youngsModulusPa}}}}},
      {"bodies",
       {{{"shape", "sphere"}, {"center", {0.32, 0.16, 0.32}}, {"radius", 0.08}, {"material", "snow"},
         {"velocity", {0, -2, 0}}}}}};
  return parseScene(scene.dump(), "stiff.csv's snowball");
}

struct StiffRun {
  std::string status = "ok";
  std::string failure;  // the watchdog's message
  std::size_t particles = 0;
  int steps = 0;
  double timedMs = 0;  // the steps after the first (whose dispatches compile the programs), dispatch to glFinish
  SolverSummary solves;
  ParticleSnapshot end;
  std::string transferShape;  // the P2G shape the run chose (sim/TransferShape.h)
};

// The quick sizes leave out 1e9 Pa: its explicit run's 3,800 steps would take a third of their 3 minutes.
std::vector<double> stiffnesses(BenchSize size) {
  if (size != BenchSize::Default) return {1e8};
  return {1e8, 1e9};
}

std::vector<StiffCase> stiffCases(double youngsModulusPa) {
  const std::string e = formatNumber(youngsModulusPa);
  return {{"explicit_E_" + e, youngsModulusPa, "explicit", {}, {}},
          {"semi_implicit_E_" + e, youngsModulusPa, "semi_implicit", {}, {}},
          {"semi_implicit_loose_E_" + e, youngsModulusPa, "semi_implicit", 1e-3, 1000}};
}

double elasticBoundS(const StiffCase& stiff) {
  return elasticStableDtS(snowball(stiff, kSemiImplicitDtS).materials.front(), kCellSizeM);
}

// The steps of `simulatedS`: explicitly the fewest whose equal steps keep within 0.5 h / c, semi-implicitly the
// thesis's 1e-3 s.
int stiffSteps(const StiffCase& stiff, double simulatedS) {
  const double longestDtS =
      stiff.integrator == "explicit" ? kExplicitBoundFraction * elasticBoundS(stiff) : kSemiImplicitDtS;
  return int(std::ceil(simulatedS / longestDtS - 1e-9));
}

StiffRun runStiff(const Scene& scene, int steps, const gl::ContextInfo& gl) {
  StiffRun run;
  // A pool of every block of the domain: the steps are taken one by one, without the frames that grow a pool.
  const glm::ivec3 domainBlocks = (scene.grid.cells + 1 + gpu::BLOCK_WIDTH - 1) / gpu::BLOCK_WIDTH;
  SimulationOptions options;
  options.blockCapacity = std::size_t(domainBlocks.x) * std::size_t(domainBlocks.y) * std::size_t(domainBlocks.z);
  Simulation simulation(scene, sampleBodies(scene), gl, options);
  run.particles = simulation.particleCount();
  run.transferShape = chosenTransferShape(simulation);
  try {
    auto start = std::chrono::steady_clock::now();
    for (int step = 1; step <= steps; ++step) {
      simulation.step(scene.time.dtS);
      run.steps = step;
      if (step % kWatchdogIntervalSteps == 0 || step == steps) simulation.checkWatchdog();
      if (step == 1) {
        glFinish();
        start = std::chrono::steady_clock::now();
      }
    }
    glFinish();
    run.timedMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  } catch (const SimulationError& error) {
    run.status = "unstable";
    run.failure = error.what();
  }
  run.solves = simulation.takeSolverSummary();
  if (run.status == "ok") run.end = simulation.snapshot();
  return run;
}

// The root mean square of the distance between each particle's end position in two runs of the same seeds.
double rmsDistanceM(const ParticleSnapshot& a, const ParticleSnapshot& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const glm::dvec3 d = glm::dvec3(a.positionMass[i]) - glm::dvec3(b.positionMass[i]);
    sum += glm::dot(d, d);
  }
  return std::sqrt(sum / double(a.size()));
}

double centreOfMassHeightM(const ParticleSnapshot& particles) {
  double mass = 0, moment = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    mass += particles.positionMass[i].w;
    moment += double(particles.positionMass[i].w) * particles.positionMass[i].y;
  }
  return moment / mass;
}

}  // namespace

PlannedWork planStiff(const BenchRun& run) {
  PlannedWork work;
  for (const double youngsModulusPa : stiffnesses(run.options().size)) {
    for (const StiffCase& stiff : stiffCases(youngsModulusPa)) {
      const Scene scene = snowball(stiff, kSemiImplicitDtS);  // the cubic kernel, the solver's default
      work.add(double(sampleBodies(scene).size()), stiffSteps(stiff, run.sizes().stiffSimulatedS),
               stiff.integrator == "explicit" ? 1 : semiImplicitStepCost(scene));
    }
  }
  return work;
}

void measureStiff(BenchRun& run) {
  CsvTable table({"configuration", "youngs_modulus_pa", "integrator", "dt_s", "dt_over_elastic_bound", "tolerance",
                  "max_iterations", "particles", "simulated_s", "steps", "ms_per_step", "ms_per_simulated_second",
                  "cost_over_explicit", "mean_iterations", "most_iterations", "largest_residual",
                  "centre_of_mass_height_m", "rms_distance_from_explicit_m", "transfer_shape", "status", "renderer"});
  const double simulatedS = run.sizes().stiffSimulatedS;
  for (const double youngsModulusPa : stiffnesses(run.options().size)) {
    const std::string e = formatNumber(youngsModulusPa);
    std::optional<StiffRun> reference;
    double referenceMsPerSimulatedSecond = 0;
    for (const StiffCase& stiff : stiffCases(youngsModulusPa)) {
      const bool isExplicit = stiff.integrator == "explicit";
      const double boundS = elasticBoundS(stiff);
      const int steps = stiffSteps(stiff, simulatedS);
      const double dtS = simulatedS / steps;
      const StiffRun result = runStiff(snowball(stiff, dtS), steps, run.gl());
      CsvTable::Row& row = table.addRow();
      row.setText("configuration", stiff.name)
          .set("youngs_modulus_pa", youngsModulusPa)
          .setText("integrator", stiff.integrator)
          .set("dt_s", dtS)
          .set("dt_over_elastic_bound", dtS / boundS)
          .setCount("particles", std::int64_t(result.particles))
          .set("simulated_s", simulatedS)
          .setCount("steps", result.steps)
          .setText("transfer_shape", result.transferShape)
          .setText("status", result.status)
          .setText("renderer", run.renderer());
      const double meanIterations =
          double(result.solves.iterations) / double(std::max<std::uint64_t>(1, result.solves.solves));
      const std::string label = "stiff snowball, E = " + e + " Pa, " + stiff.name + " at dt " + formatNumber(dtS) +
                                " s (" + fixed(dtS / boundS, 1) + " h / c)";
      if (!isExplicit) {
        const SolverSpec defaults;
        row.set("tolerance", stiff.tolerance.value_or(defaults.tolerance))
            .setCount("max_iterations", stiff.maxIterations.value_or(defaults.maxIterations));
        if (result.solves.solves > 0) {
          row.set("mean_iterations", meanIterations)
              .setCount("most_iterations", result.solves.mostIterations)
              .set("largest_residual", result.solves.largestResidual);
        }
      }
      if (result.status != "ok") {
        const std::string stopped = "the watchdog stopped it at its look after step " + std::to_string(result.steps) +
                                    " of " + std::to_string(steps) + ": " + result.failure;
        run.progress(label + ": " + stopped);
        run.addSummary(label + ": " + stopped);
        continue;
      }
      const double msPerStep = result.timedMs / std::max(1, steps - 1);
      const double msPerSimulatedSecond = msPerStep / dtS;
      row.set("ms_per_step", msPerStep)
          .set("ms_per_simulated_second", msPerSimulatedSecond)
          .set("centre_of_mass_height_m", centreOfMassHeightM(result.end));
      std::string comparison;
      if (isExplicit) {
        reference = result;
        referenceMsPerSimulatedSecond = msPerSimulatedSecond;
      } else if (reference) {
        const double costRatio = msPerSimulatedSecond / referenceMsPerSimulatedSecond;
        const double distanceM = rmsDistanceM(result.end, reference->end);
        row.set("cost_over_explicit", costRatio).set("rms_distance_from_explicit_m", distanceM);
        comparison = ", " + fixed(costRatio, 2) + "x the explicit run's cost per simulated second, particles " +
                     fixed(distanceM / kCellSizeM, 3) + " cells (rms) from the explicit run's";
        run.addSummary(label + ": " + fixed(meanIterations, 1) + " iterations per step" + comparison);
      }
      run.progress(label + ": " + grouped(result.particles) + " particles, " + std::to_string(steps) + " steps, " +
                   fixed(msPerStep, 2) + " ms per step" + comparison);
    }
  }
  run.write(table, "stiff");
}

}  // namespace firn::bench
