#pragma once
// How the benchmarks time a simulation: warm-up steps first (excluded: the first dispatch of each program
// JIT-compiles it), then repeated runs of steps, each from glFinish to glFinish, summarised by their median.
// Wall time is what every driver can measure; GL_TIME_ELAPSED is recorded beside it (Mesa's llvmpipe reports 0
// for compute work).
#include <string>
#include <vector>

#include "sim/Simulation.h"

namespace firn::bench {

struct TimingPlan {
  int warmupSteps = 3;
  int repeats = 5;
  int stepsPerRepeat = 10;
};

struct StepTiming {
  int stepsPerRepeat = 0;
  int repeats = 0;
  double medianMs = 0;     // wall time per step, dispatch to glFinish: the median over the repeats
  double minMs = 0;        // the fastest and slowest repeat
  double maxMs = 0;
  double gpuMedianMs = 0;  // GL_TIME_ELAPSED per step, median over the repeats
};

// Steps `simulation` at its scene's dt as `plan` says. Throws SimulationError (exit 3) if the watchdog saw the
// run go unstable: a time for an exploding state is not a time for the scene.
StepTiming timeSteps(Simulation& simulation, const TimingPlan& plan);

// Several simulations timed in rounds, one run of each per round, so that a change in the machine's load (shared
// build machines are noisy) falls on all of them alike and their ratios stay meaningful. Returns each one's
// timing, or the SimulationError message that made it unstable.
struct InterleavedTiming {
  StepTiming timing;
  std::string unstable;  // empty: stable
};
std::vector<InterleavedTiming> timeInterleaved(const std::vector<Simulation*>& simulations, const TimingPlan& plan);

struct PassTiming {
  std::string pass;  // the shader's name without folder and extension: "p2g"
  double gpuMs = 0;  // GL_TIME_ELAPSED per step, median over the repeats
  double wallMs = 0; // dispatch to glFinish per step, median over the repeats
  double dispatchesPerStep = 0;
};

// Per-pass times (Simulation::setPassTiming) over the same plan, in the order the step runs the passes. Timing
// waits for each pass, so their sum exceeds an untimed step by the synchronisation.
std::vector<PassTiming> timePasses(Simulation& simulation, const TimingPlan& plan);

double median(std::vector<double> values);

}  // namespace firn::bench
