// domain.csv: one snowball of 50,000 particles (8 per cell, quadratic kernel, APIC, fixed point) in domains from
// 64³ to 1024³ cells, the ball always at the same place near the domain's low corner, so that every domain holds
// the same particles and the same blocks of the grid: time per step and the grid's GPU memory (the pool of blocks,
// and the block map, 4 bytes per 64 nodes of the domain) per size. The summary gives what the largest domain
// costs over the smallest (issue 12: at most 1.2x, within llvmpipe's 128 MiB per buffer).
#include <string>
#include <utility>

#include "Experiments.h"

namespace firn::bench {

PlannedWork planDomain(const BenchRun& run) {
  PlannedWork work;
  const Sizes& sizes = run.sizes();
  work.add(sizes.domainSnowballParticles, plannedSteps(sizes.timing), kQuadraticStepCost,
           int(sizes.domainExperimentCells.size()));
  return work;
}

void measureDomain(BenchRun& run) {
  CsvTable table({"grid_cells", "grid_dims", "transfer_shape", "particles", "active_blocks", "active_nodes",
                  "pool_blocks", "pool_mib", "block_map_mib", "steps", "repeats", "ms_per_step", "ms_min", "ms_max",
                  "steps_per_s", "gpu_ms_per_step", "status", "renderer"});
  const std::vector<int>& domainCells = run.sizes().domainExperimentCells;
  const double particles = run.sizes().domainSnowballParticles;
  std::vector<Configuration> configurations;
  for (const int cells : domainCells) {
    configurations.push_back({"domain, " + std::to_string(cells) + "³ cells",
                              [cells, particles] { return snowballInDomain(cells, particles, "quadratic"); },
                              ""});  // P2G's shape as a run chooses it
  }
  const std::vector<Timed> timed = run.timeConfigurations(configurations);
  std::vector<std::pair<int, double>> timedSizes;
  for (std::size_t i = 0; i < domainCells.size(); ++i) {
    const glm::ivec3 cells(domainCells[i]);
    CsvTable::Row& row = table.addRow();
    row.setCount("grid_cells", nodeCount(cells))
        .setText("grid_dims", nodeDims(cells))
        .setCount("particles", std::int64_t(timed[i].particles))
        .setText("renderer", run.renderer());
    setTiming(row, timed[i]);
    if (timed[i].status != "ok") continue;
    const double mebibyte = 1024.0 * 1024.0;
    row.setCount("active_blocks", std::int64_t(timed[i].blocks.lastStep))
        .setCount("pool_blocks", std::int64_t(timed[i].blocks.capacity))
        .set("pool_mib", double(timed[i].blocks.poolBytes) / mebibyte)
        .set("block_map_mib", double(timed[i].blocks.mapBytes) / mebibyte);
    timedSizes.emplace_back(domainCells[i], timed[i].timing.medianMs);
  }
  run.write(table, "domain");
  if (timedSizes.size() >= 2) {
    run.addSummary("domain, one snowball of " + grouped(std::uint64_t(particles)) + " particles: " +
                   std::to_string(timedSizes.back().first) + "³ cells cost " +
                   fixed(timedSizes.back().second / timedSizes.front().second, 3) + "x what " +
                   std::to_string(timedSizes.front().first) + "³ cells cost; issue bound 1.2");
  }
}

}  // namespace firn::bench
