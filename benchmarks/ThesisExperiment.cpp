// thesis.csv: the bunny of the implementation of Snow thesis 2015 (its point cloud, --thesis-cloud) stepped by
// Firn, once per atomics with the thesis's cubic kernel, once more with the quadratic one (fixed point), and once
// semi-implicitly at the thesis's own step of 1e-3 s (4.2 times the elastic bound of the 200 kg/m³ the cloud stands
// for, hardened; cubic, fixed point), against
// that implementation's 546 ms per step on it (measured, issue 7): Firn's time per step and per simulated second,
// and how many times faster each is. The timed steps are the bunny's first, in free fall: the solve's cheapest.
#include <string>
#include <vector>

#include "Experiments.h"

namespace firn::bench {

namespace {

// The thesis implementation's median time per physics step on its own bunny, at its step (issue 7).
constexpr double kThesisMsPerStep = 546;

}  // namespace

PlannedWork planThesis(const BenchRun& run) {
  PlannedWork work;
  // The cloud read once: its particles, and its materials at the semi-implicit rows' step.
  Scene scene = thesisCloudScene(run.options().thesisCloud, run.options().thesisDtS, "fixed");
  const double particles = double(sampleBodies(scene).size());
  const double steps = plannedSteps(run.sizes().timing);
  scene.time.dtS = kThesisDtS;
  const double semiImplicitCost = semiImplicitStepCost(scene);
  work.add(particles, steps, 1, int(run.sumSeries().size()));  // cubic, explicit, each series of sums
  work.add(particles, steps, kQuadraticStepCost, 2);             // quadratic in tiles and in blocks
  work.add(particles, steps, semiImplicitCost, 2);               // semi-implicit in tiles and in blocks
  return work;
}

void measureThesis(BenchRun& run) {
  CsvTable table({"kernel", "atomics", "transfer_shape", "integrator", "particles", "grid_dims", "dt_s", "steps", "repeats",
                  "ms_per_step", "ms_min", "ms_max", "ms_per_simulated_second", "mean_iterations",
                  "thesis_ms_per_step", "thesis_dt_s", "speedup_per_step", "speedup_per_simulated_second", "status",
                  "renderer"});
  const BenchOptions& options = run.options();
  struct ThesisCase {
    std::string kernel, atomics, integrator;
    double dtS = 0;
    std::string transferShape;
  };
  std::vector<ThesisCase> cases;
  for (const SumSeries& series : run.sumSeries()) {
    cases.push_back({"cubic", series.atomics, "explicit", options.thesisDtS, series.transferShape});
  }
  for (const std::string shape : {"tiles", "blocks"}) {
    cases.push_back({"quadratic", "fixed", "explicit", options.thesisDtS, shape});
    cases.push_back({"cubic", "fixed", "semi_implicit", kThesisDtS, shape});
  }
  std::vector<Configuration> configurations;
  for (const ThesisCase& c : cases) {
    configurations.push_back({"thesis bunny, " + c.kernel + ", " + c.atomics + " atomics, " + c.transferShape + ", " +
                                  c.integrator + ", dt " + formatNumber(c.dtS) + " s",
                              [&options, c] {
                                return thesisCloudScene(options.thesisCloud, c.dtS, c.atomics, c.kernel, c.integrator);
                              },
                              c.transferShape});
  }
  const std::vector<Timed> timed = run.timeConfigurations(configurations);
  for (std::size_t i = 0; i < timed.size(); ++i) {
    CsvTable::Row& row = table.addRow();
    const ThesisCase& c = cases[i];
    row.setText("kernel", c.kernel)
        .setText("atomics", c.atomics)
        .setText("transfer_shape", timed[i].transferShape)
        .setText("integrator", c.integrator)
        .setCount("particles", std::int64_t(timed[i].particles))
        .setText("grid_dims", nodeDims(glm::ivec3(kThesisGridCells)))
        .set("dt_s", c.dtS)
        .set("thesis_ms_per_step", kThesisMsPerStep)
        .set("thesis_dt_s", kThesisDtS)
        .setText("status", timed[i].status)
        .setText("renderer", run.renderer());
    if (timed[i].status != "ok") continue;
    const double msPerStep = timed[i].timing.medianMs;
    const double msPerSimulatedSecond = msPerStep / c.dtS;
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
    std::string iterations;
    if (timed[i].solves.solves > 0) {
      const double meanIterations = double(timed[i].solves.iterations) / double(timed[i].solves.solves);
      row.set("mean_iterations", meanIterations);
      iterations = " (" + fixed(meanIterations, 1) + " iterations per step)";
    }
    run.addSummary("thesis bunny (" + grouped(timed[i].particles) + " particles, " + c.kernel + ", " + c.atomics +
                   " atomics, P2G by " + timed[i].transferShape + ", " + c.integrator + ", dt " +
                   formatNumber(c.dtS) + " s): " + fixed(msPerStep, 1) + " ms per step" + iterations + ", " + fixed(speedupPerStep, 2) +
                   "x faster than the thesis's 546 ms per step; per simulated second " +
                   fixed(speedupPerSimulatedSecond, 2) + "x (the thesis steps 1e-3 s)");
  }
  run.write(table, "thesis");
}

}  // namespace firn::bench
