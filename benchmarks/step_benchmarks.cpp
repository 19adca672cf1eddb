// Google Benchmark timings of one simulation step, for quick A/B comparisons while working on a pass (the tables
// and plots are `firn bench`'s). Each benchmark steps a snowball of about the given particle count, with each
// kernel and each kind of atomics, and reports the wall time of a step from glFinish to glFinish (manual time)
// and, as counters, each pass's wall milliseconds when timed alone.
//   build/release/benchmarks/firn_step_benchmarks --benchmark_repetitions=5 --benchmark_report_aggregates_only
//   build/release/benchmarks/firn_step_benchmarks --benchmark_filter='Step/cubic/fixed/.*'
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "StepTiming.h"
#include "gl/Context.h"
#include "gl/GL.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"

namespace {

constexpr double kCellSizeM = 0.02;
constexpr double kParticlesPerCell = 8;
constexpr double pi = 3.14159265358979323846;

firn::gl::HeadlessContext& context() {
  static firn::gl::HeadlessContext headless;
  return headless;
}

// A snowball of about `particles` particles (8 per cell) thrown sideways, in a domain that holds it with room.
firn::Scene snowball(double particles, const std::string& kernel, const std::string& atomics) {
  const double volumeM3 = particles * std::pow(kCellSizeM, 3) / kParticlesPerCell;
  const double radiusM = std::cbrt(3 * volumeM3 / (4 * pi));
  const int cells = int(std::ceil(4 * radiusM / kCellSizeM)) + 8;
  const double centreM = 0.5 * cells * kCellSizeM;
  const nlohmann::json scene = {
      {"grid", {{"cells", {cells, cells, cells}}, {"cell_size", kCellSizeM}}},
      {"time", {{"dt", 1e-4}, {"frame_rate", 30}, {"frames", 1}}},
      {"solver", {{"kernel", kernel}, {"transfer", "pic_flip"}, {"atomics", atomics}}},
      {"materials", {{"snow", {{"preset", "stomakhin"}}}}},
      {"bodies",
       {{{"shape", "sphere"}, {"center", {centreM, centreM, centreM}}, {"radius", radiusM}, {"material", "snow"},
         {"velocity", {2, 0, 0}}, {"particles_per_cell", kParticlesPerCell}}}}};
  return firn::parseScene(scene.dump(), "benchmark snowball");
}

void Step(benchmark::State& state, const std::string& kernel, const std::string& atomics) {
  if (atomics == "float" && !context().info().hasFloatAtomics) {
    state.SkipWithError("no GL_NV_shader_atomic_float");
    return;
  }
  const firn::Scene scene = snowball(double(state.range(0)), kernel, atomics);
  firn::Simulation simulation(scene, firn::sampleBodies(scene), context().info());
  const double dtS = scene.time.dtS;
  for (int i = 0; i < 3; ++i) simulation.step(dtS);  // the first dispatch of each program compiles it
  for (auto _ : state) {
    glFinish();
    const auto start = std::chrono::steady_clock::now();
    simulation.step(dtS);
    glFinish();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  for (const firn::bench::PassTiming& pass : firn::bench::timePasses(simulation, {0, 3, 2})) {
    state.counters[pass.pass + "_ms"] = pass.wallMs;
  }
  state.counters["particles"] = double(simulation.particleCount());
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  for (const std::string kernel : {"quadratic", "cubic"}) {
    for (const std::string atomics : {"fixed", "float"}) {
      benchmark::RegisterBenchmark(("Step/" + kernel + "/" + atomics).c_str(), Step, kernel, atomics)
          ->Arg(16000)
          ->Arg(64000)
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond);
    }
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
