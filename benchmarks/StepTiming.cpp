#include "StepTiming.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <utility>

#include "Error.h"
#include "gl/GL.h"
#include "gl/Query.h"

namespace firn::bench {

double median(std::vector<double> values) {
  if (values.empty()) throw std::logic_error("median of no values");
  std::sort(values.begin(), values.end());
  const std::size_t middle = values.size() / 2;
  return values.size() % 2 == 1 ? values[middle] : 0.5 * (values[middle - 1] + values[middle]);
}

namespace {

void warmUp(Simulation& simulation, const TimingPlan& plan) {
  const double dtS = simulation.scene().time.dtS;
  for (int i = 0; i < plan.warmupSteps; ++i) simulation.step(dtS);
}

// One timed run: wall and GL_TIME_ELAPSED milliseconds per step.
std::pair<double, double> timeRun(Simulation& simulation, const TimingPlan& plan, gl::TimerQuery& timer) {
  const double dtS = simulation.scene().time.dtS;
  glFinish();
  const auto start = std::chrono::steady_clock::now();
  timer.begin();
  for (int i = 0; i < plan.stepsPerRepeat; ++i) simulation.step(dtS);
  timer.end();
  glFinish();
  const double wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return {wallMs / plan.stepsPerRepeat, double(timer.elapsedNanoseconds()) * 1e-6 / plan.stepsPerRepeat};
}

StepTiming summarize(const std::vector<double>& wallMs, const std::vector<double>& gpuMs, const TimingPlan& plan) {
  StepTiming timing;
  timing.stepsPerRepeat = plan.stepsPerRepeat;
  timing.repeats = plan.repeats;
  timing.medianMs = median(wallMs);
  timing.minMs = *std::min_element(wallMs.begin(), wallMs.end());
  timing.maxMs = *std::max_element(wallMs.begin(), wallMs.end());
  timing.gpuMedianMs = median(gpuMs);
  return timing;
}

}  // namespace

StepTiming timeSteps(Simulation& simulation, const TimingPlan& plan) {
  const InterleavedTiming timed = timeInterleaved({&simulation}, plan).front();
  if (!timed.unstable.empty()) throw SimulationError(timed.unstable);
  return timed.timing;
}

std::vector<InterleavedTiming> timeInterleaved(const std::vector<Simulation*>& simulations, const TimingPlan& plan) {
  for (Simulation* simulation : simulations) warmUp(*simulation, plan);
  std::vector<std::vector<double>> wallMs(simulations.size()), gpuMs(simulations.size());
  gl::TimerQuery timer;
  for (int repeat = 0; repeat < plan.repeats; ++repeat) {
    for (std::size_t i = 0; i < simulations.size(); ++i) {
      const auto [wall, gpu] = timeRun(*simulations[i], plan, timer);
      wallMs[i].push_back(wall);
      gpuMs[i].push_back(gpu);
    }
  }
  std::vector<InterleavedTiming> timings(simulations.size());
  for (std::size_t i = 0; i < simulations.size(); ++i) {
    timings[i].timing = summarize(wallMs[i], gpuMs[i], plan);
    try {
      simulations[i]->checkWatchdog();
    } catch (const SimulationError& error) {
      timings[i].unstable = error.what();
    }
  }
  return timings;
}

std::vector<PassTiming> timePasses(Simulation& simulation, const TimingPlan& plan) {
  const double dtS = simulation.scene().time.dtS;
  warmUp(simulation, plan);
  std::vector<std::string> passes;  // in the order of the step
  std::vector<std::vector<double>> gpuMs, wallMs, dispatches;
  for (int repeat = 0; repeat < plan.repeats; ++repeat) {
    simulation.setPassTiming(true);  // clears the sums
    for (int i = 0; i < plan.stepsPerRepeat; ++i) simulation.step(dtS);
    for (const Simulation::PassTime& time : simulation.passTimes()) {
      const std::string pass = std::filesystem::path(time.pass).stem().string();
      auto found = std::find(passes.begin(), passes.end(), pass);
      if (found == passes.end()) {
        found = passes.insert(passes.end(), pass);
        gpuMs.emplace_back();
        wallMs.emplace_back();
        dispatches.emplace_back();
      }
      const std::size_t index = std::size_t(found - passes.begin());
      gpuMs[index].push_back(time.totalMs / plan.stepsPerRepeat);
      wallMs[index].push_back(time.totalWallMs / plan.stepsPerRepeat);
      dispatches[index].push_back(double(time.dispatches) / plan.stepsPerRepeat);
    }
  }
  simulation.setPassTiming(false);
  simulation.checkWatchdog();
  std::vector<PassTiming> timings;
  for (std::size_t i = 0; i < passes.size(); ++i) {
    timings.push_back({passes[i], median(gpuMs[i]), median(wallMs[i]), median(dispatches[i])});
  }
  return timings;
}

}  // namespace firn::bench
