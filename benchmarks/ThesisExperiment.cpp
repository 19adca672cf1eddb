// thesis.csv: the bunny of the implementation of Snow thesis 2015 (its point cloud, --thesis-cloud) stepped by
// Firn, once per atomics with the thesis's cubic kernel and once more with the quadratic one (fixed point), against
// that implementation's 546 ms per step on it (measured, issue 7): Firn's time per step and per simulated second,
// and how many times faster each is.
#include <utility>

#include "Experiments.h"

namespace firn::bench {

namespace {

// The thesis implementation's median time per physics step on its own bunny, at its step (issue 7).
constexpr double kThesisMsPerStep = 546;
constexpr double kThesisDtS = 1e-3;

}  // namespace

void measureThesis(BenchRun& run) {
  CsvTable table({"kernel", "atomics", "particles", "grid_dims", "dt_s", "steps", "repeats", "ms_per_step", "ms_min",
                  "ms_max", "ms_per_simulated_second", "thesis_ms_per_step", "thesis_dt_s", "speedup_per_step",
                  "speedup_per_simulated_second", "status", "renderer"});
  const BenchOptions& options = run.options();
  const std::vector<std::string>& atomicsSeries = run.atomicsSeries();
  std::vector<std::pair<std::string, std::string>> cases;  // kernel, atomics
  for (const std::string& atomics : atomicsSeries) cases.emplace_back("cubic", atomics);
  cases.emplace_back("quadratic", "fixed");
  std::vector<Configuration> configurations;
  for (const auto& [kernel, atomics] : cases) {
    configurations.push_back({"thesis bunny, " + kernel + ", " + atomics + " atomics, dt " +
                                  formatNumber(options.thesisDtS) + " s",
                              [&options, kernel = kernel, atomics = atomics] {
                                return thesisCloudScene(options.thesisCloud, options.thesisDtS, atomics, kernel);
                              }});
  }
  const std::vector<Timed> timed = run.timeConfigurations(configurations);
  for (std::size_t i = 0; i < timed.size(); ++i) {
    CsvTable::Row& row = table.addRow();
    row.setText("kernel", cases[i].first)
        .setText("atomics", cases[i].second)
        .setCount("particles", std::int64_t(timed[i].particles))
        .setText("grid_dims", nodeDims(glm::ivec3(kThesisGridCells)))
        .set("dt_s", options.thesisDtS)
        .set("thesis_ms_per_step", kThesisMsPerStep)
        .set("thesis_dt_s", kThesisDtS)
        .setText("status", timed[i].status)
        .setText("renderer", run.renderer());
    if (timed[i].status != "ok") continue;
    const double msPerStep = timed[i].timing.medianMs;
    const double msPerSimulatedSecond = msPerStep / options.thesisDtS;
    // How many times faster Firn is: the thesis's cost over Firn's.
    const double speedupPerStep = kThesisMsPerStep / msPerStep;
    const double speedupPerSimulatedSecond = (kThesisMsPerStep / kThesisDtS) / msPerSimulatedSecond;
    row.setCount("steps", timed[i].timing.stepsPerRepeat)
        .setCount("repeats", timed[i].timing.repeats)
        .set("ms_per_step", msPerStep)
        .set("ms_min", timed[i].timing.minMs)
        .set("ms_max", timed[i].timing.maxMs)
        .set("ms_per_simulated_second", msPerSimulatedSecond)
        .set("speedup_per_step", speedupPerStep)
        .set("speedup_per_simulated_second", speedupPerSimulatedSecond);
    run.addSummary("thesis bunny (" + grouped(timed[i].particles) + " particles, " + cases[i].first + ", " +
                   cases[i].second + " atomics, dt " + formatNumber(options.thesisDtS) + " s): " + fixed(msPerStep, 1) +
                   " ms per step, " + fixed(speedupPerStep, 2) +
                   "x faster than the thesis's 546 ms per step; per simulated second " +
                   fixed(speedupPerSimulatedSecond, 2) + "x (the thesis steps 1e-3 s)");
  }
  run.write(table, "thesis");
}

}  // namespace firn::bench
