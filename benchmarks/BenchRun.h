#pragma once
// What every experiment of `firn bench` shares: the sizes of the run, the GL context, the bunny scenes, the
// series of atomics, progress and summary lines, and timing a set of configurations together. The experiments
// (Experiments.h) each write one table through it; Bench.cpp drives them.
#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "Bench.h"
#include "BenchScenes.h"
#include "CsvTable.h"
#include "StepTiming.h"
#include "gl/Context.h"
#include "sim/GpuState.h"
#include "sim/Simulation.h"

namespace firn::bench {

// The thesis's particle-count experiment starts its unscaled series at 47,063 particles, 4 per cell, and
// doubles the particles per cell (issue 7). That smallest bunny is also the reference scene of the grid,
// passes and P2G tables.
constexpr double kThesisSmallestParticles = 47063;
constexpr double kSmallestParticlesPerCell = 4;
// The thesis implementation's time step (s): beyond Firn's explicit bound, the semi-implicit integrator's.
constexpr double kThesisDtS = 1e-3;

struct Sizes {
  int particleGridCells = 200;  // per axis: the thesis's 200³ cells, 8 million nodes
  double smallestParticles = kThesisSmallestParticles;
  std::vector<double> unscaledParticlesPerCell;
  std::vector<int> gridExperimentCells;  // per axis; the same bunny in each
  std::vector<int> domainExperimentCells;  // per axis; the same snowball in each
  double domainSnowballParticles = 50000;
  TimingPlan timing;
  int barPeriods = 2;  // tradeoff: periods measured (the amplitude after them shows PIC's damping)
  std::vector<double> surfaceParticles;            // surface: the bunny's sizes at 8 per cell
  std::vector<double> surfaceResolutions = {1, 2, 3, 4};  // surface: the smallest bunny at each
  double stiffSimulatedS = 0.05;  // stiff: the snowball's run, each integrator the same simulated time
  double passesTargetParticles = 0;  // passes: also the quadratic bunny of this many at 8 per cell (0: not)
};

Sizes sizesFor(BenchSize size);

// "12,345": counts in messages.
std::string grouped(std::uint64_t count);
std::string fixed(double value, int decimals);
std::string nodeDims(const glm::ivec3& cells);
std::int64_t nodeCount(const glm::ivec3& cells);

// What a table will do, counted from the sizes before it runs (each experiment's plan… function, Experiments.h): the
// simulations it builds and the steps they take. A calibration on this machine turns it into seconds
// (StepCosts::seconds), so that `firn bench` says up front how long it will take.
struct PlannedWork {
  int builds = 0;            // simulations built: each compiles its programs and times the P2G shapes it may take
  double builtParticles = 0; // Σ particles over the builds (sampling them and timing the shapes on them)
  double steps = 0;          // steps of all of them, each weighted by its cost
  double particleSteps = 0;  // Σ particles × steps, weighted likewise

  // `simulations` built alike, each stepping `particles` for `stepCount` steps that cost `stepCost` cubic explicit
  // steps of the same particles each (kQuadraticStepCost, semiImplicitStepCost).
  void add(double particles, double stepCount, double stepCost = 1, int simulations = 1);
};

// What a semi-implicit step of `scene` costs in explicit steps of the same particles: mostly its solve's iterations,
// each a Hessian product. Fitted to llvmpipe's tables (tradeoff, stiff): the iterations grow with the step's length in
// elastic bounds, 6 (dt/bound)^0.75 up to 150 (measured: 5.6 at 1 bound, 23 at 4, 58 at 16, 85 at 30, 88–146 at
// 94), and a step costs 2 + 0.6 per iteration explicit steps (measured 8x, 21x, 31x, 47x, 50–78x).
double semiImplicitStepCost(const Scene& scene);
// What a quadratic step costs in cubic steps of the same particles: 27 nodes per particle against 64 (the thesis
// bunny's step on llvmpipe: 490–600 ms against 950–1050 ms).
constexpr double kQuadraticStepCost = 0.5;

// The steps of one configuration timed as `plan` says: its warm-up and every repeat.
double plannedSteps(const TimingPlan& plan);

// A step's and a build's wall time on this machine, from two simulations of the reference bunny (or, for the tables
// without bunnies, of a snowball), an eighth of its particles and all of them, built and stepped before the tables: a
// cubic explicit step costs stepS + particles × particleStepS in the P2G shape a run would choose; a build (sampling
// the scene, compiling its programs, timing its P2G shapes on its particles) buildS + particles × buildParticleS.
struct StepCosts {
  double buildS = 0;
  double buildParticleS = 0;
  double stepS = 0;
  double particleStepS = 0;
  double seconds(const PlannedWork& work) const {
    return work.builds * buildS + work.builtParticles * buildParticleS + work.steps * stepS +
           work.particleSteps * particleStepS;
  }
};

// One configuration's outcome: timed, or why not ("unstable": the watchdog stopped it; "skipped": it does not
// fit the domain or the driver's buffers).
struct Timed {
  std::string status = "ok";
  std::string transferShape;  // the P2G shape it ran (sim/TransferShape.h): "tiles", "blocks-128", …
  StepTiming timing;
  std::size_t particles = 0;
  std::int64_t activeNodes = 0;
  BlockUsage blocks;  // the grid's blocks at the end of the timing, and their memory
  SolverSummary solves;  // semi-implicit scenes: the solves of the warm-up and timed steps
};

// A timed row's status and transfer_shape and, when it was timed, the columns active_nodes, steps, repeats,
// ms_per_step, ms_min, ms_max, steps_per_s and gpu_ms_per_step.
void setTiming(CsvTable::Row& row, const Timed& timed);

struct Configuration {
  std::string label;
  std::function<Scene()> makeScene;
  // The P2G shapes its simulation times (SimulationOptions: "tiles", "blocks"); empty: every shape, as a run.
  std::string transferShape;
};

// A series of a table: how P2G sums, and in which shape. Fixed point is timed in both shapes, tiles and blocks (the
// group size timed as a run times it); float sums take tiles only (sim/TransferShape.h).
struct SumSeries {
  std::string atomics;        // "fixed", "float"
  std::string transferShape;  // "tiles", "blocks"
  std::string label() const { return atomics + " " + transferShape; }
};

// The shape a simulation chose, by name ("" before it has had particles).
std::string chosenTransferShape(const Simulation& simulation);

class BenchRun {
 public:
  // Loads the bunny scenes when a table needs them, then makes the GL context.
  BenchRun(const BenchOptions& options, std::ostream& log);

  const BenchOptions& options() const { return options_; }
  const Sizes& sizes() const { return sizes_; }
  bool wanted(const std::string& table) const;
  const gl::ContextInfo& gl() const { return context_.info(); }
  const std::string& renderer() const { return context_.info().renderer; }
  // The series of the particle, grid, passes and thesis tables: BenchOptions::atomics, or its default here.
  const std::vector<std::string>& atomicsSeries() const { return atomics_; }
  // The atomics series, fixed point once per P2G shape: the series of the particles, grid, passes and thesis tables.
  std::vector<SumSeries> sumSeries() const;
  const BunnyScenes& bunnies() const { return bunnies_.value(); }
  // The thesis's smallest configuration: the reference scene of the grid, passes and P2G tables.
  BunnySetup referenceBunny() const;
  // Why a configuration could not be built: float atomics the driver lacks (GL_NV_shader_atomic_float), or a
  // scene that does not fit the domain or the driver's buffers.
  std::string inputErrorStatus(const std::string& atomics) const;

  // Measures StepCosts (seconds on llvmpipe, less on a GPU).
  StepCosts calibrate();

  void progress(const std::string& line);
  void write(const CsvTable& table, const std::string& name);
  void addSummary(const std::string& line) { summary_.push_back(line); }
  const std::vector<std::string>& summaryLines() const { return summary_; }

  // Builds every configuration's scene and simulation, then times them all together, interleaved
  // (timeInterleaved); one that cannot be built (it does not fit the domain or the driver's buffers) or goes
  // unstable is an outcome, not a failure.
  // `timing` replaces the sizes' own where a table needs more steps.
  std::vector<Timed> timeConfigurations(const std::vector<Configuration>& configurations);
  std::vector<Timed> timeConfigurations(const std::vector<Configuration>& configurations, const TimingPlan& timing);

 private:
  bool wantsBunny() const;

  const BenchOptions& options_;
  std::ostream& log_;
  Sizes sizes_;
  std::optional<BunnyScenes> bunnies_;  // when a table needs them (the bar and the thesis cloud do not)
  gl::HeadlessContext context_;
  std::vector<std::string> summary_;
  std::vector<std::string> atomics_;
};

}  // namespace firn::bench
