// passes.csv: each pass of a step timed alone (GL_TIME_ELAPSED and wall time to glFinish) on the reference
// bunny, once per series of sums (atomics and P2G shape), with its share of the step; once more for each
// fixed-point series stepped semi-implicitly at the thesis's 1e-3 s, whose solve's passes (the Hessian product
// above all) are where that integrator's time goes; and, at the GPU sizes, for each fixed-point series on a bunny of
// a million particles with the quadratic kernel, the GPU target's configuration. The summary gives each pass's share
// and their sum.
#include "Error.h"
#include "Experiments.h"
#include "sim/Simulation.h"

namespace firn::bench {

namespace {

struct PassSeries {
  SumSeries sums;
  std::string integrator;
  std::string kernel;
  double particles = 0;  // at 8 per cell; 0: the reference bunny
};

std::vector<PassSeries> passSeries(const BenchRun& run) {
  std::vector<PassSeries> series;
  for (const SumSeries& sums : run.sumSeries()) series.push_back({sums, "explicit", "cubic"});
  for (const SumSeries& sums : run.sumSeries()) {
    if (sums.atomics == "fixed") series.push_back({sums, "semi_implicit", "cubic"});  // the solver sums fixed point
  }
  const double targetParticles = run.sizes().passesTargetParticles;
  for (const SumSeries& sums : run.sumSeries()) {
    if (sums.atomics == "fixed" && targetParticles > 0) series.push_back({sums, "explicit", "quadratic", targetParticles});
  }
  return series;
}

BunnySetup passBunny(const BenchRun& run, const PassSeries& series) {
  BunnySetup setup = run.referenceBunny();
  setup.atomics = series.sums.atomics;
  setup.kernel = series.kernel;
  if (series.particles > 0) {
    setup.particlesPerCell = 8;
    setup.scale = run.bunnies().scaleFor(series.particles, setup.particlesPerCell);
  }
  if (series.integrator == "semi_implicit") {
    setup.integrator = series.integrator;
    setup.dtS = kThesisDtS;
  }
  return setup;
}

}  // namespace

PlannedWork planPasses(const BenchRun& run) {
  PlannedWork work;
  for (const PassSeries& series : passSeries(run)) {
    const Scene scene = run.bunnies().scene(passBunny(run, series));
    const double cost = (series.kernel == "cubic" ? 1 : kQuadraticStepCost) *
                        (series.integrator == "explicit" ? 1 : semiImplicitStepCost(scene));
    work.add(series.particles > 0 ? series.particles : run.sizes().smallestParticles,
             plannedSteps(run.sizes().timing), cost);
  }
  return work;
}

void measurePasses(BenchRun& run) {
  CsvTable table(
      {"atomics", "transfer_shape", "integrator", "kernel", "pass", "gpu_ms", "wall_ms", "share_of_step",
       "dispatches_per_step", "particles", "renderer"});
  for (const auto& [sums, integrator, kernel, particles] : passSeries(run)) {
    const std::string& atomics = sums.atomics;
    try {
      const Scene scene = run.bunnies().scene(passBunny(run, {sums, integrator, kernel, particles}));
      const std::vector<ParticleSeed> seeds = sampleBodies(scene);
      SimulationOptions options;
      options.transferShapes = sums.transferShape;
      Simulation simulation(scene, seeds, run.gl(), options);
      const std::string shape = chosenTransferShape(simulation);
      const std::vector<PassTiming> timings = timePasses(simulation, run.sizes().timing);
      double totalWallMs = 0, totalGpuMs = 0;
      for (const PassTiming& timing : timings) {
        totalWallMs += timing.wallMs;
        totalGpuMs += timing.gpuMs;
      }
      std::string shares;
      for (const PassTiming& timing : timings) {
        table.addRow()
            .setText("atomics", atomics)
            .setText("transfer_shape", shape)
            .setText("integrator", integrator)
            .setText("kernel", kernel)
            .setText("pass", timing.pass)
            .set("gpu_ms", timing.gpuMs)
            .set("wall_ms", timing.wallMs)
            .set("share_of_step", timing.wallMs / totalWallMs)
            .set("dispatches_per_step", timing.dispatchesPerStep)
            .setCount("particles", std::int64_t(seeds.size()))
            .setText("renderer", run.renderer());
        shares += (shares.empty() ? "" : ", ") + timing.pass + " " + fixed(100 * timing.wallMs / totalWallMs, 1) +
                  "% (" + fixed(timing.wallMs, 2) + " ms)";
      }
      run.progress("passes: " + shares);
      run.addSummary("passes (" + grouped(seeds.size()) + " particles, " + kernel + ", PIC/FLIP, " + atomics +
                     " atomics, P2G by " + shape + ", " + integrator + (integrator == "explicit" ? "" : ", dt " + formatNumber(kThesisDtS) + " s") +
                     "), wall time per step, each pass timed alone: " + shares + "; sum " +
                     fixed(totalWallMs, 2) + " ms wall, " + fixed(totalGpuMs, 2) + " ms GL_TIME_ELAPSED");
    } catch (const SimulationError& error) {
      run.progress("passes, " + integrator + ": unstable: " + error.what());
    } catch (const InputError& error) {
      run.progress("passes, " + integrator + ": skipped: " + error.what());
    }
  }
  run.write(table, "passes");
}

}  // namespace firn::bench
