#include "BenchRun.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <tuple>
#include <utility>

#include "Error.h"
#include "gpu/Materials.h"
#include "sim/Simulation.h"
#include "sim/TransferShape.h"

namespace firn::bench {

Sizes sizesFor(BenchSize size) {
  Sizes sizes;
  switch (size) {
    case BenchSize::Default:
      // Up to 6 million particles; 128 per cell leaves 19 bits of fixed-point resolution.
      sizes.unscaledParticlesPerCell = {4, 8, 16, 32, 64, 128};
      sizes.gridExperimentCells = {50, 64, 80, 100, 128, 160, 200};
      sizes.domainExperimentCells = {64, 128, 256, 512, 1024};
      sizes.timing = {5, 5, 20};
      sizes.barPeriods = 3;
      sizes.surfaceParticles = {47063, 188252, 753008, 3012032};
      sizes.stiffSimulatedS = 0.1;
      sizes.passesTargetParticles = 1e6;  // the GPU target: a million quadratic particles within 0.5 ms a step
      break;
    case BenchSize::Quick:
      // The default's tables with fewer and smaller points, in under 3 minutes on llvmpipe (2 cores): bunnies of
      // 6,000 to 24,000 particles (at these sizes a step's own cost, its dispatches and barriers, is still a large
      // part of its time: the particle exponent and the grid's ratio read lower than at the default sizes).
      sizes.smallestParticles = 6000;
      sizes.unscaledParticlesPerCell = {4, 8, 16};
      sizes.gridExperimentCells = {50, 100, 200};
      sizes.domainExperimentCells = {64, 256, 1024};
      sizes.domainSnowballParticles = 12000;
      sizes.timing = {1, 3, 2};
      sizes.barPeriods = 1;
      sizes.surfaceParticles = {6000, 12000, 24000};
      sizes.surfaceResolutions = {1, 2, 3};
      sizes.stiffSimulatedS = 0.01;  // the ball still in the air (it lands at 0.02 s): the solve's cost, no contact
      break;
    case BenchSize::Tiny:
      sizes.particleGridCells = 40;
      sizes.smallestParticles = 1500;
      sizes.unscaledParticlesPerCell = {4, 8};
      sizes.gridExperimentCells = {24, 40};
      sizes.domainExperimentCells = {32, 64};
      sizes.domainSnowballParticles = 1500;
      sizes.timing = {1, 3, 1};
      sizes.barPeriods = 1;
      sizes.surfaceParticles = {1500, 3000};
      sizes.surfaceResolutions = {1, 2};
      sizes.stiffSimulatedS = 3e-3;  // three semi-implicit steps, the ball still in the air
      break;
  }
  return sizes;
}

void PlannedWork::add(double particles, double stepCount, double stepCost, int simulations) {
  builds += simulations;
  builtParticles += simulations * particles;
  steps += simulations * stepCount * stepCost;
  particleSteps += simulations * particles * stepCount * stepCost;
}

double semiImplicitStepCost(const Scene& scene) {
  double boundS = std::numeric_limits<double>::infinity();
  for (const Material& material : scene.materials) {
    boundS = std::min(boundS, elasticStableDtS(material, scene.grid.cellSizeM));
  }
  const double iterations = std::min(150.0, 6 * std::pow(scene.time.dtS / boundS, 0.75));
  return 2 + 0.6 * iterations;
}

double plannedSteps(const TimingPlan& plan) { return plan.warmupSteps + double(plan.repeats) * plan.stepsPerRepeat; }

std::string grouped(std::uint64_t count) {
  std::string digits = std::to_string(count);
  for (int i = int(digits.size()) - 3; i > 0; i -= 3) digits.insert(std::size_t(i), ",");
  return digits;
}

std::string fixed(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

std::string nodeDims(const glm::ivec3& cells) {
  return std::to_string(cells.x + 1) + "x" + std::to_string(cells.y + 1) + "x" + std::to_string(cells.z + 1);
}

std::int64_t nodeCount(const glm::ivec3& cells) {
  return std::int64_t(cells.x + 1) * std::int64_t(cells.y + 1) * std::int64_t(cells.z + 1);
}

std::string chosenTransferShape(const Simulation& simulation) {
  const std::optional<TransferShapeChoice>& choice = simulation.transferShapeChoice();
  return choice ? transferShapeName(choice->shape) : std::string();
}

std::vector<SumSeries> BenchRun::sumSeries() const {
  std::vector<SumSeries> series;
  for (const std::string& atomics : atomics_) {
    series.push_back({atomics, "tiles"});
    if (atomics == "fixed") series.push_back({atomics, "blocks"});
  }
  return series;
}

void setTiming(CsvTable::Row& row, const Timed& timed) {
  row.setText("status", timed.status).setText("transfer_shape", timed.transferShape);
  if (timed.status != "ok") return;
  row.setCount("active_nodes", timed.activeNodes)
      .setCount("steps", timed.timing.stepsPerRepeat)
      .setCount("repeats", timed.timing.repeats)
      .set("ms_per_step", timed.timing.medianMs)
      .set("ms_min", timed.timing.minMs)
      .set("ms_max", timed.timing.maxMs)
      .set("steps_per_s", 1e3 / timed.timing.medianMs)
      .set("gpu_ms_per_step", timed.timing.gpuMedianMs);
}

BenchRun::BenchRun(const BenchOptions& options, std::ostream& log)
    : options_(options),
      log_(log),
      sizes_(sizesFor(options.size)),
      // Loaded before the GL context: missing assets are reported at once.
      bunnies_(wantsBunny() ? std::optional<BunnyScenes>(std::in_place, options.assetsDir) : std::nullopt) {
  if (options.stepsPerRepeat > 0) sizes_.timing.stepsPerRepeat = options.stepsPerRepeat;
  if (options.repeats > 0) sizes_.timing.repeats = options.repeats;
  atomics_ = options.atomics;
  if (atomics_.empty()) {
    atomics_ = {"fixed"};
    if (gl().hasFloatAtomics) atomics_.push_back("float");
  }
}

bool BenchRun::wanted(const std::string& table) const {
  return options_.tables.empty() ||
         std::find(options_.tables.begin(), options_.tables.end(), table) != options_.tables.end();
}

bool BenchRun::wantsBunny() const {
  return wanted("particles") || wanted("grid") || wanted("passes") || wanted("p2g_atomics") || wanted("surface");
}

BunnySetup BenchRun::referenceBunny() const {
  BunnySetup setup;
  setup.gridCells = sizes_.particleGridCells;
  setup.scale = bunnies().scaleFor(sizes_.smallestParticles, kSmallestParticlesPerCell);
  setup.particlesPerCell = kSmallestParticlesPerCell;
  return setup;
}

std::string BenchRun::inputErrorStatus(const std::string& atomics) const {
  return atomics == "float" && !gl().hasFloatAtomics ? "unsupported" : "skipped";
}

namespace {

// The line through (x[0], y[0]) and (x[1], y[1]) as {intercept, slope}, both held non-negative (a first build that
// also paid a one-time cost, or noise, could make either negative).
std::pair<double, double> nonNegativeLine(const double x[2], const double y[2]) {
  const double slope = x[1] > x[0] ? std::max(0.0, (y[1] - y[0]) / (x[1] - x[0])) : 0.0;
  return {std::max(0.0, y[0] - slope * x[0]), slope};
}

}  // namespace

StepCosts BenchRun::calibrate() {
  using Clock = std::chrono::steady_clock;
  // The larger simulation's extra time is its particles'; the rest is a step's own (its dispatches, barriers and
  // readbacks: most of a small step on llvmpipe).
  const double particles[2] = {sizes_.smallestParticles / 8, sizes_.smallestParticles};
  std::vector<std::unique_ptr<Simulation>> simulations;
  std::vector<Simulation*> stepped;
  double counts[2] = {0, 0}, buildS[2] = {0, 0};
  for (int i = 0; i < 2; ++i) {
    const auto start = Clock::now();
    Scene scene;
    if (bunnies_) {
      BunnySetup setup = referenceBunny();
      setup.scale = bunnies_->scaleFor(particles[i], setup.particlesPerCell);
      scene = bunnies_->scene(setup);
    } else {
      scene = snowballInDomain(64, particles[i], "cubic");
    }
    const std::vector<ParticleSeed> seeds = sampleBodies(scene);
    counts[i] = double(seeds.size());
    // P2G's shape as a run chooses it, the fastest here (a table that forces a slower one takes longer: on llvmpipe
    // blocks take 1.8x the tiles' time, on a GPU tiles take longer).
    simulations.push_back(std::make_unique<Simulation>(scene, seeds, gl()));
    buildS[i] = std::chrono::duration<double>(Clock::now() - start).count();
    stepped.push_back(simulations.back().get());
  }
  const std::vector<InterleavedTiming> timed = timeInterleaved(stepped, {1, 3, 2});
  for (const InterleavedTiming& timing : timed) {
    if (!timing.unstable.empty()) throw SimulationError("firn bench's calibration went unstable: " + timing.unstable);
  }
  StepCosts costs;
  std::tie(costs.buildS, costs.buildParticleS) = nonNegativeLine(counts, buildS);
  const double stepS[2] = {timed[0].timing.medianMs * 1e-3, timed[1].timing.medianMs * 1e-3};
  std::tie(costs.stepS, costs.particleStepS) = nonNegativeLine(counts, stepS);
  progress("calibration: a build " + fixed(costs.buildS, 2) + " s + " + fixed(costs.buildParticleS * 1e6, 1) +
           " µs per particle, a step " + fixed(costs.stepS * 1e3, 2) + " ms + " + fixed(costs.particleStepS * 1e9, 0) +
           " ns per particle (" + (bunnies_ ? "bunnies" : "snowballs") + " of " + grouped(std::uint64_t(counts[0])) +
           " and " + grouped(std::uint64_t(counts[1])) + " particles)");
  return costs;
}

void BenchRun::progress(const std::string& line) { log_ << "firn bench: " << line << "\n" << std::flush; }

void BenchRun::write(const CsvTable& table, const std::string& name) {
  table.write(options_.outputDir / (name + ".csv"));
  progress("wrote " + (options_.outputDir / (name + ".csv")).string());
}

std::vector<Timed> BenchRun::timeConfigurations(const std::vector<Configuration>& configurations) {
  return timeConfigurations(configurations, sizes_.timing);
}

std::vector<Timed> BenchRun::timeConfigurations(const std::vector<Configuration>& configurations,
                                                const TimingPlan& timing) {
  std::vector<Timed> results(configurations.size());
  std::vector<std::unique_ptr<Simulation>> simulations;
  std::vector<Simulation*> built;
  std::vector<std::size_t> builtIndex;
  for (std::size_t i = 0; i < configurations.size(); ++i) {
    try {
      const Scene scene = configurations[i].makeScene();
      const std::vector<ParticleSeed> seeds = sampleBodies(scene);
      results[i].particles = seeds.size();
      results[i].transferShape = configurations[i].transferShape;
      SimulationOptions options;
      options.transferShapes = configurations[i].transferShape;
      simulations.push_back(std::make_unique<Simulation>(scene, seeds, gl(), options));
      const std::string chosen = chosenTransferShape(*simulations.back());
      if (!chosen.empty()) results[i].transferShape = chosen;
      built.push_back(simulations.back().get());
      builtIndex.push_back(i);
      progress(configurations[i].label + ": " + grouped(seeds.size()) + " particles, " + nodeDims(scene.grid.cells) +
               " nodes");
    } catch (const InputError& error) {
      results[i].status = "skipped";
      progress(configurations[i].label + ": skipped: " + error.what());
    }
  }
  progress("timing " + std::to_string(built.size()) + " configurations interleaved: " +
           std::to_string(timing.warmupSteps) + " warm-up steps each, then " +
           std::to_string(timing.repeats) + " rounds of " + std::to_string(timing.stepsPerRepeat) +
           " steps of each");
  const std::vector<InterleavedTiming> timings = timeInterleaved(built, timing);
  for (std::size_t k = 0; k < built.size(); ++k) {
    Timed& result = results[builtIndex[k]];
    const std::string& label = configurations[builtIndex[k]].label;
    if (!timings[k].unstable.empty()) {
      result.status = "unstable";
      progress(label + ": unstable: " + timings[k].unstable);
      continue;
    }
    result.timing = timings[k].timing;
    result.blocks = built[k]->blockUsage();
    result.solves = built[k]->takeSolverSummary();
    result.activeNodes = static_cast<std::int64_t>(result.blocks.lastStep) * gpu::BLOCK_NODES;
    progress(label + ": " + fixed(result.timing.medianMs, 2) + " ms per step (runs " + fixed(result.timing.minMs, 2) +
             "–" + fixed(result.timing.maxMs, 2) + ")");
  }
  return results;
}

}  // namespace firn::bench
