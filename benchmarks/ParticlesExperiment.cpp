// particles.csv: time per step against particle count on the thesis's 200³ grid (Snow thesis 2015 §5.2, fig. 10),
// once per atomics, in two series: unscaled (one bunny, more particles per cell) and scaled (8 per cell, a bunny
// ∛2 larger per size, so the counts match). The summary gives the exponent of time against particles over each
// series' largest sizes.
#include <algorithm>
#include <cmath>
#include <utility>

#include "Experiments.h"

namespace firn::bench {

namespace {

// The thesis's scaled series keeps 8 particles per cell and grows the bunny (issue 7).
constexpr double kScaledParticlesPerCell = 8;
// The particle exponent is fitted over each series' largest sizes (issue 7: ≤ 1.15 there), where the fixed
// costs of a step (a dispatch, the grid box) no longer matter.
constexpr std::size_t kExponentFitSizes = 3;

// Least-squares slope of log(y) against log(x).
double logLogSlope(const std::vector<std::pair<double, double>>& points) {
  double meanX = 0, meanY = 0;
  for (const auto& [x, y] : points) {
    meanX += std::log(x);
    meanY += std::log(y);
  }
  meanX /= double(points.size());
  meanY /= double(points.size());
  double covariance = 0, variance = 0;
  for (const auto& [x, y] : points) {
    covariance += (std::log(x) - meanX) * (std::log(y) - meanY);
    variance += (std::log(x) - meanX) * (std::log(x) - meanX);
  }
  return variance > 0 ? covariance / variance : std::nan("");
}

}  // namespace

PlannedWork planParticles(const BenchRun& run) {
  PlannedWork work;
  const Sizes& sizes = run.sizes();
  for (const SumSeries& sums : run.sumSeries()) {
    for (const double perCell : sizes.unscaledParticlesPerCell) {
      const double particles = sizes.smallestParticles * perCell / kSmallestParticlesPerCell;
      work.add(particles, plannedSteps(sizes.timing), 1, 2);  // cubic, unscaled and scaled
      if (sums.atomics == "fixed") work.add(particles, plannedSteps(sizes.timing), kQuadraticStepCost);
    }
  }
  return work;
}

void measureParticles(BenchRun& run) {
  CsvTable table({"series", "kernel", "atomics", "transfer_shape", "particles", "grid_cells", "grid_dims",
                  "cell_size_m", "particles_per_cell", "bunny_scale", "active_nodes", "steps", "repeats", "ms_per_step",
                  "ms_min", "ms_max", "steps_per_s", "gpu_ms_per_step", "status", "renderer"});
  const Sizes& sizes = run.sizes();
  const BunnyScenes& bunnies = run.bunnies();
  const double smallestScale = bunnies.scaleFor(sizes.smallestParticles, kSmallestParticlesPerCell);
  // The thesis's cubic kernel in both series; fixed point also with the quadratic kernel at 8 per cell, the
  // configuration of issue 28's GPU target (a million particles within 0.5 ms per step).
  struct Series {
    std::string name;  // "unscaled", "scaled"
    std::string kernel;
    SumSeries sums;
    std::string label() const { return name + " " + kernel + " " + sums.label(); }
  };
  std::vector<Series> series;
  for (const SumSeries& sums : run.sumSeries()) {
    series.push_back({"unscaled", "cubic", sums});
    series.push_back({"scaled", "cubic", sums});
    if (sums.atomics == "fixed") series.push_back({"scaled", "quadratic", sums});
  }
  std::vector<std::size_t> seriesOf;  // each setup's
  std::vector<BunnySetup> setups;
  for (std::size_t s = 0; s < series.size(); ++s) {
    for (const double unscaledPerCell : sizes.unscaledParticlesPerCell) {
      BunnySetup setup;
      setup.atomics = series[s].sums.atomics;
      setup.kernel = series[s].kernel;
      setup.gridCells = sizes.particleGridCells;
      if (series[s].name == "unscaled") {
        setup.scale = smallestScale;
        setup.particlesPerCell = unscaledPerCell;
      } else {
        setup.scale = smallestScale * std::cbrt(unscaledPerCell / kScaledParticlesPerCell);
        setup.particlesPerCell = kScaledParticlesPerCell;
      }
      seriesOf.push_back(s);
      setups.push_back(setup);
    }
  }
  std::vector<Configuration> configurations;
  for (std::size_t i = 0; i < setups.size(); ++i) {
    const Series& of = series[seriesOf[i]];
    const std::string label = "particles, " + of.kernel + ", " + of.sums.atomics + " atomics, " +
                              of.sums.transferShape + ", " + of.name + ", " + fixed(setups[i].particlesPerCell, 0) +
                              " per cell, bunny scale " + fixed(setups[i].scale, 3);
    configurations.push_back({label, [&, i] { return bunnies.scene(setups[i]); }, of.sums.transferShape});
  }
  const std::vector<Timed> timed = run.timeConfigurations(configurations);
  std::string exponents;
  for (std::size_t s = 0; s < series.size(); ++s) {
    std::vector<std::pair<double, double>> points;
    for (std::size_t i = 0; i < setups.size(); ++i) {
      if (seriesOf[i] != s) continue;
      const glm::ivec3 cells(setups[i].gridCells);
      CsvTable::Row& row = table.addRow();
      row.setText("series", series[s].name)
          .setText("kernel", series[s].kernel)
          .setText("atomics", series[s].sums.atomics)
          .setCount("particles", std::int64_t(timed[i].particles))
          .setCount("grid_cells", nodeCount(cells))
          .setText("grid_dims", nodeDims(cells))
          .set("cell_size_m", bunnies.cellSizeM())
          .set("particles_per_cell", setups[i].particlesPerCell)
          .set("bunny_scale", setups[i].scale)
          .setText("renderer", run.renderer());
      setTiming(row, timed[i]);
      if (timed[i].status == "ok") points.emplace_back(double(timed[i].particles), timed[i].timing.medianMs);
    }
    if (points.size() >= 2) {
      const std::vector<std::pair<double, double>> largest(
          points.end() - std::ptrdiff_t(std::min(points.size(), kExponentFitSizes)), points.end());
      exponents += (exponents.empty() ? "" : ", ") + series[s].label() + " " + fixed(logLogSlope(largest), 3) + " (" +
                   grouped(std::uint64_t(largest.front().first)) + "–" +
                   grouped(std::uint64_t(largest.back().first)) + " particles)";
    }
  }
  run.write(table, "particles");
  if (!exponents.empty()) {
    run.addSummary("particles: exponent of ms per step against particles over the largest " +
                   std::to_string(kExponentFitSizes) + " sizes: " + exponents + "; issue bound 1.15");
  }
}

}  // namespace firn::bench
