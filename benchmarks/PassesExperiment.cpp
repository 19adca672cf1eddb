// passes.csv: each pass of a step timed alone (GL_TIME_ELAPSED and wall time to glFinish) on the reference
// bunny, once per series of sums (atomics and P2G shape), with its share of the step; once more for each
// fixed-point series stepped semi-implicitly at the thesis's 1e-3 s, whose solve's passes (the Hessian product
// above all) are where that integrator's time goes; and, at the GPU sizes, for each fixed-point series on a bunny of
// a million particles with the quadratic kernel, the GPU target's configuration. The summary gives each pass's share
// and their sum. Each pass also says the bytes it reads and writes per particle and per node, as its shader's
// declarations count them (Simulation::PassTraffic), and the step's total against the floor of one read and one write
// of each particle's state (docs/numerics.md, "The passes' declarations, barriers and bytes moved").
#include <filesystem>
#include <map>

#include "Error.h"
#include "Experiments.h"
#include "gpu/GpuLayout.h"
#include "sim/Simulation.h"

namespace firn::bench {

namespace {

// Adds what `other` moved to `total`.
void addTraffic(Simulation::PassTraffic& total, const Simulation::PassTraffic& other) {
  total.readBytesPerParticle += other.readBytesPerParticle;
  total.writtenBytesPerParticle += other.writtenBytesPerParticle;
  total.readBytesPerNode += other.readBytesPerNode;
  total.writtenBytesPerNode += other.writtenBytesPerNode;
}

// A step's traffic by pass (the names timePasses gives them), summed over each pass's dispatches.
std::map<std::string, Simulation::PassTraffic> trafficByPass(const std::vector<Simulation::PassTraffic>& step) {
  std::map<std::string, Simulation::PassTraffic> byPass;
  for (const Simulation::PassTraffic& dispatch : step) {
    addTraffic(byPass[std::filesystem::path(dispatch.pass).stem().string()], dispatch);
  }
  return byPass;
}

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
       "dispatches_per_step", "read_bytes_per_particle", "written_bytes_per_particle", "read_bytes_per_node",
       "written_bytes_per_node", "mb_per_step", "particles", "renderer"});
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
      const Simulation::StepTraffic stepTraffic = simulation.stepRecordingTraffic(scene.time.dtS);
      const std::map<std::string, Simulation::PassTraffic> traffic = trafficByPass(stepTraffic.dispatches);
      const double particleCount = double(simulation.particleCount());
      const double nodeCount = double(simulation.blockUsage().lastStep) * gpu::BLOCK_NODES;
      const auto megabytes = [&](const Simulation::PassTraffic& pass) {
        return (particleCount * double(pass.readBytesPerParticle + pass.writtenBytesPerParticle) +
                nodeCount * double(pass.readBytesPerNode + pass.writtenBytesPerNode)) / 1e6;
      };
      Simulation::PassTraffic step;
      for (const auto& [name, pass] : traffic) addTraffic(step, pass);
      double totalWallMs = 0, totalGpuMs = 0;
      for (const PassTiming& timing : timings) {
        totalWallMs += timing.wallMs;
        totalGpuMs += timing.gpuMs;
      }
      std::string shares;
      for (const PassTiming& timing : timings) {
        const auto moved = traffic.find(timing.pass);
        const Simulation::PassTraffic pass = moved != traffic.end() ? moved->second : Simulation::PassTraffic{};
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
            .setCount("read_bytes_per_particle", std::int64_t(pass.readBytesPerParticle))
            .setCount("written_bytes_per_particle", std::int64_t(pass.writtenBytesPerParticle))
            .setCount("read_bytes_per_node", std::int64_t(pass.readBytesPerNode))
            .setCount("written_bytes_per_node", std::int64_t(pass.writtenBytesPerNode))
            .set("mb_per_step", megabytes(pass))
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
      const std::size_t floor = 2 * simulation.particleStateBytes();
      run.addSummary("bytes moved per step (" + grouped(seeds.size()) + " particles, " + kernel + ", " + atomics +
                     ", " + integrator + "): " + std::to_string(step.readBytesPerParticle) + " B read and " +
                     std::to_string(step.writtenBytesPerParticle) + " B written per particle, " +
                     fixed(double(step.readBytesPerParticle + step.writtenBytesPerParticle) / double(floor), 1) +
                     "x the floor of " + std::to_string(floor) + " B (its state read once and written once); " +
                     fixed(megabytes(step), 1) + " MB in all with the " + grouped(std::size_t(nodeCount)) +
                     " nodes' " + std::to_string(step.readBytesPerNode + step.writtenBytesPerNode) + " B each; " +
                     std::to_string(stepTraffic.barriers) + " barriers between its " +
                     std::to_string(stepTraffic.dispatches.size()) + " dispatches");
    } catch (const SimulationError& error) {
      run.progress("passes, " + integrator + ": unstable: " + error.what());
    } catch (const InputError& error) {
      run.progress("passes, " + integrator + ": skipped: " + error.what());
    }
  }
  run.write(table, "passes");
}

}  // namespace firn::bench
