// grid.csv: time per step against grid size with the same particles (Snow thesis 2015 §5.2, fig. 11), once per
// series of sums (atomics and P2G shape): the reference bunny sits in the domain's low corner, so every domain
// holds exactly the same particles. The summary gives what the largest grid costs over the smallest (issue 7: at
// most 1.5x).
#include <utility>

#include "Experiments.h"

namespace firn::bench {

PlannedWork planGrid(const BenchRun& run) {
  PlannedWork work;
  const Sizes& sizes = run.sizes();
  work.add(sizes.smallestParticles, plannedSteps(sizes.timing), 1,
           int(run.sumSeries().size() * sizes.gridExperimentCells.size()));
  return work;
}

void measureGrid(BenchRun& run) {
  CsvTable table({"atomics", "transfer_shape", "grid_cells", "grid_dims", "particles", "active_nodes", "steps",
                  "repeats", "ms_per_step", "ms_min", "ms_max", "steps_per_s", "gpu_ms_per_step", "status", "renderer"});
  const std::vector<SumSeries> sumSeries = run.sumSeries();
  const std::vector<int>& gridCells = run.sizes().gridExperimentCells;
  const BunnyScenes& bunnies = run.bunnies();
  std::vector<Configuration> configurations;
  for (const SumSeries& sums : sumSeries) {
    BunnySetup setup = run.referenceBunny();
    setup.centred = false;
    setup.atomics = sums.atomics;
    for (const int cells : gridCells) {
      configurations.push_back({"grid, " + sums.atomics + " atomics, " + sums.transferShape + ", " +
                                    std::to_string(cells) + "³ cells",
                                [setup, cells, &bunnies]() mutable {
                                  setup.gridCells = cells;
                                  return bunnies.scene(setup);
                                },
                                sums.transferShape});
    }
  }
  const std::vector<Timed> timed = run.timeConfigurations(configurations);
  std::string ratios;
  for (std::size_t series = 0; series < sumSeries.size(); ++series) {
    std::vector<std::pair<std::int64_t, double>> timedSizes;
    for (std::size_t size = 0; size < gridCells.size(); ++size) {
      const std::size_t i = series * gridCells.size() + size;
      const glm::ivec3 cells(gridCells[size]);
      CsvTable::Row& row = table.addRow();
      row.setText("atomics", sumSeries[series].atomics)
          .setCount("grid_cells", nodeCount(cells))
          .setText("grid_dims", nodeDims(cells))
          .setCount("particles", std::int64_t(timed[i].particles))
          .setText("renderer", run.renderer());
      setTiming(row, timed[i]);
      if (timed[i].status == "ok") timedSizes.emplace_back(nodeCount(cells), timed[i].timing.medianMs);
    }
    if (timedSizes.size() >= 2) {
      ratios += (ratios.empty() ? "" : "; ") + sumSeries[series].label() + ": " +
                grouped(std::uint64_t(timedSizes.back().first)) + " nodes cost " +
                fixed(timedSizes.back().second / timedSizes.front().second, 3) + "x what " +
                grouped(std::uint64_t(timedSizes.front().first)) + " nodes cost";
    }
  }
  run.write(table, "grid");
  if (!ratios.empty()) run.addSummary("grid, the same particles: " + ratios + "; issue bound 1.5");
}

}  // namespace firn::bench
