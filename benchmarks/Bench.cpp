#include "Bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <thread>

#include "BenchScenes.h"
#include "CsvTable.h"
#include "ElasticBar.h"
#include "Error.h"
#include "P2GReference.h"
#include "StepTiming.h"
#include "gl/Context.h"
#include "io/AtomicFile.h"
#include "sim/Simulation.h"

namespace firn::bench {

namespace {

using Clock = std::chrono::steady_clock;

// The thesis's particle-count experiment starts its unscaled series at 47,063 particles, 4 per cell, and
// doubles the particles per cell; its scaled series keeps 8 per cell and grows the bunny (issue 7).
constexpr double kThesisSmallestParticles = 47063;
constexpr double kSmallestParticlesPerCell = 4;
constexpr double kScaledParticlesPerCell = 8;
// The thesis implementation's median time per physics step on its own bunny, at its step (issue 7).
constexpr double kThesisMsPerStep = 546;
constexpr double kThesisDtS = 1e-3;
// The particle exponent is fitted over each series' largest sizes (issue 7: ≤ 1.15 there), where the fixed
// costs of a step (a dispatch, the grid box) no longer matter.
constexpr std::size_t kExponentFitSizes = 3;
// The first steps of a tradeoff run are left out of its time: the first dispatch of each program compiles it.
constexpr std::size_t kTradeoffWarmupSteps = 3;
// A bar whose vibration grows by more than this over the periods measured is going unstable, however slowly:
// "growing", and off the Pareto front. (The peaks are sampled once per step and carry the higher modes that
// the slabs' start excites. Measured over 2 periods: 0.92–0.997 for APIC and PIC/FLIP where stable, 0.70 for
// PIC, 0.29 with one particle per cell; 1.13–1.25 where the step was too long but the watchdog not yet tripped.)
constexpr double kAmplitudeGrowthTolerance = 1.02;
// The velocity field of the P2G comparison: a falling, spinning bunny, so momentum sums are nonzero and vary
// (at rest they would all be zero, and fixed and float both exact).
constexpr glm::dvec3 kP2GVelocityMPerS{0.0, -3.0, 0.0};
constexpr glm::dvec3 kP2GAngularVelocityRadPerS{0.0, 2.0, 0.0};

struct Sizes {
  int particleGridCells = 200;  // per axis: the thesis's 200³ cells, 8 million nodes
  double smallestParticles = kThesisSmallestParticles;
  std::vector<double> unscaledParticlesPerCell;
  std::vector<int> gridExperimentCells;  // per axis; the same bunny in each
  TimingPlan timing;
  int barPeriods = 2;  // tradeoff: periods measured (the amplitude after them shows PIC's damping)
};

Sizes sizesFor(BenchSize size) {
  Sizes sizes;
  switch (size) {
    case BenchSize::Default:
      // Up to 6 million particles; 128 per cell leaves 19 bits of fixed-point resolution.
      sizes.unscaledParticlesPerCell = {4, 8, 16, 32, 64, 128};
      sizes.gridExperimentCells = {50, 64, 80, 100, 128, 160, 200};
      sizes.timing = {5, 5, 20};
      sizes.barPeriods = 3;
      break;
    case BenchSize::Quick:
      // Up to 376k particles: on llvmpipe (2 cores) a 188k-particle cubic step takes about half a second.
      sizes.unscaledParticlesPerCell = {4, 8, 16, 32};
      sizes.gridExperimentCells = {50, 64, 80, 100, 128, 160, 200};
      sizes.timing = {2, 5, 3};
      sizes.barPeriods = 2;
      break;
    case BenchSize::Tiny:
      sizes.particleGridCells = 40;
      sizes.smallestParticles = 1500;
      sizes.unscaledParticlesPerCell = {4, 8};
      sizes.gridExperimentCells = {24, 40};
      sizes.timing = {1, 3, 1};
      sizes.barPeriods = 1;
      break;
  }
  return sizes;
}

struct TradeoffCase {
  std::string name;
  BarSetup setup;
};

// A baseline, each factor varied alone from it, and three combinations a user might pick: a cheap preview, a
// production setting and a validation run.
std::vector<TradeoffCase> tradeoffCases(BenchSize size, int periods) {
  BarSetup baseline;
  baseline.model = "fixed_corotated";
  baseline.dtFraction = 0.5;
  baseline.periods = periods;
  const auto with = [&](const std::string& name, const std::function<void(BarSetup&)>& change) {
    BarSetup setup = baseline;
    change(setup);
    return TradeoffCase{name, setup};
  };
  const auto unchanged = [](BarSetup&) {};
  if (size == BenchSize::Tiny) {
    baseline.cellsAlongBar = 12;
    return {with("baseline", unchanged), with("float_atomics", [](BarSetup& s) { s.atomics = "float"; })};
  }
  std::vector<TradeoffCase> cases = {
      with("baseline", unchanged),
      with("cubic", [](BarSetup& s) { s.kernel = "cubic"; }),
      with("flip_0.95", [](BarSetup& s) { s.transfer = "pic_flip"; }),
      with("pic", [](BarSetup& s) {
        s.transfer = "pic_flip";
        s.flipRatio = 0;
      }),
      with("float_atomics", [](BarSetup& s) { s.atomics = "float"; }),
      with("no_atomics", [](BarSetup& s) { s.atomics = "none"; }),
      with("material_volumes", [](BarSetup& s) { s.particleVolume = "material_density"; }),
      with("dt_0.25", [](BarSetup& s) { s.dtFraction = 0.25; }),
      with("dt_0.9", [](BarSetup& s) { s.dtFraction = 0.9; }),
      with("ppc_1", [](BarSetup& s) { s.particlesPerCell = 1; }),
      with("ppc_27", [](BarSetup& s) { s.particlesPerCell = 27; }),
      with("h_L12", [](BarSetup& s) { s.cellsAlongBar = 12; }),
      with("h_L36", [](BarSetup& s) { s.cellsAlongBar = 36; }),
      // PIC/FLIP's energy grows on this bar at half the bound with h = L/12 (measured); 0.4 keeps it stable.
      with("preview", [](BarSetup& s) {
        s.transfer = "pic_flip";
        s.dtFraction = 0.4;
        s.cellsAlongBar = 12;
      }),
      with("production", [](BarSetup& s) { s.cellsAlongBar = 24; }),
      with("validation", [](BarSetup& s) {
        s.kernel = "cubic";
        s.dtFraction = 0.25;
        s.particlesPerCell = 27;
        s.cellsAlongBar = 36;
      }),
  };
  if (size == BenchSize::Default) {
    cases.push_back(with("ppc_64", [](BarSetup& s) { s.particlesPerCell = 64; }));
    cases.push_back(with("h_L72", [](BarSetup& s) { s.cellsAlongBar = 72; }));
    cases.push_back(with("validation_L72", [](BarSetup& s) {
      s.kernel = "cubic";
      s.dtFraction = 0.25;
      s.particlesPerCell = 27;
      s.cellsAlongBar = 72;
    }));
  }
  return cases;
}

std::string sizeName(BenchSize size) {
  switch (size) {
    case BenchSize::Default: return "default";
    case BenchSize::Quick: return "quick";
    case BenchSize::Tiny: return "tiny";
  }
  return "";
}

// "12,345": counts in messages.
std::string grouped(std::uint64_t count) {
  std::string digits = std::to_string(count);
  for (int i = int(digits.size()) - 3; i > 0; i -= 3) digits.insert(std::size_t(i), ",");
  return digits;
}

std::string fixed(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

std::string nodeDims(const glm::ivec3& cells) {
  return std::to_string(cells.x + 1) + "x" + std::to_string(cells.y + 1) + "x" + std::to_string(cells.z + 1);
}

std::int64_t nodeCount(const glm::ivec3& cells) {
  return std::int64_t(cells.x + 1) * std::int64_t(cells.y + 1) * std::int64_t(cells.z + 1);
}

std::string cpuModel() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  }
  return "unknown";
}

// The 1-minute load average (/proc/loadavg): how busy the machine was besides this run.
std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string oneMinute;
  return in >> oneMinute ? oneMinute : "unknown";
}

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return text;
}

// Least-squares slope of log(y) against log(x).
double logLogSlope(const std::vector<std::pair<double, double>>& points) {
  double meanX = 0, meanY = 0;
  for (const auto& [x, y] : points) {
    meanX += std::log(x);
    meanY += std::log(y);
  }
  meanX /= double(points.size());
  meanY /= double(points.size());
  double covariance = 0, variance = 0;
  for (const auto& [x, y] : points) {
    covariance += (std::log(x) - meanX) * (std::log(y) - meanY);
    variance += (std::log(x) - meanX) * (std::log(x) - meanX);
  }
  return variance > 0 ? covariance / variance : std::nan("");
}

// Single quotes for the shell, with embedded single quotes closed, escaped and reopened.
std::string shellQuoted(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// One configuration's outcome: timed, or why not ("unstable": the watchdog stopped it; "skipped": it does not
// fit the domain or the driver's buffers).
struct Timed {
  std::string status = "ok";
  StepTiming timing;
  std::size_t particles = 0;
  std::int64_t activeNodes = 0;
};

class BenchRun {
 public:
  BenchRun(const BenchOptions& options, std::ostream& log)
      : options_(options),
        log_(log),
        sizes_(sizesFor(options.size)),
        // Loaded before the GL context: missing assets are reported at once.
        bunnies_(wantsBunny() ? std::optional<BunnyScenes>(std::in_place, options.assetsDir) : std::nullopt) {
    if (options.stepsPerRepeat > 0) sizes_.timing.stepsPerRepeat = options.stepsPerRepeat;
    sizes_.timing.repeats = options.repeats;
    atomics_ = options.atomics;
    if (atomics_.empty()) {
      const std::string& name = context_.info().renderer;
      const bool cpuRenderer = name.find("llvmpipe") != std::string::npos || name.find("softpipe") != std::string::npos;
      atomics_ = {"fixed", cpuRenderer ? "none" : "float"};
    }
  }

  void run() {
    const auto start = Clock::now();
    loadAtStart_ = loadAverage();
    writeMachine();
    if (wanted("particles")) particles();
    if (wanted("grid")) grid();
    if (wanted("passes")) passes();
    if (wanted("p2g_atomics")) p2gAtomics();
    if (wanted("tradeoff")) tradeoff();
    if (!options_.thesisCloud.empty() && wanted("thesis")) thesis();
    const double minutes = std::chrono::duration<double>(Clock::now() - start).count() / 60;
    summary_.insert(summary_.begin(), "firn bench (" + sizeName(options_.size) + ") on " + renderer() + ", " +
                                          cpuModel() + " x " + std::to_string(std::thread::hardware_concurrency()) +
                                          " cores: " + fixed(minutes, 1) + " min; load average " + loadAtStart_ +
                                          " at the start, " + loadAverage() + " at the end");
    writeFileAtomically(options_.outputDir / "summary.txt", summary(), "benchmark summary");
  }

  std::string summary() const {
    std::string text;
    for (const std::string& line : summary_) text += line + "\n";
    return text;
  }

 private:
  bool wanted(const std::string& table) const {
    return options_.tables.empty() ||
           std::find(options_.tables.begin(), options_.tables.end(), table) != options_.tables.end();
  }
  const std::string& renderer() const { return context_.info().renderer; }
  bool wantsBunny() const {
    return wanted("particles") || wanted("grid") || wanted("passes") || wanted("p2g_atomics");
  }
  const BunnyScenes& bunnies() const { return bunnies_.value(); }
  // The thesis's smallest configuration: the reference scene of the grid, passes and P2G tables.
  BunnySetup referenceBunny() const {
    BunnySetup setup;
    setup.gridCells = sizes_.particleGridCells;
    setup.scale = bunnies().scaleFor(sizes_.smallestParticles, kSmallestParticlesPerCell);
    setup.particlesPerCell = kSmallestParticlesPerCell;
    return setup;
  }
  // Why a configuration could not be built: float atomics the driver lacks (GL_NV_shader_atomic_float), or a
  // scene that does not fit the domain or the driver's buffers.
  std::string inputErrorStatus(const std::string& atomics) const {
    return atomics == "float" && !context_.info().hasFloatAtomics ? "unsupported" : "skipped";
  }
  void progress(const std::string& line) { log_ << "firn bench: " << line << "\n" << std::flush; }
  void write(const CsvTable& table, const std::string& name) {
    table.write(options_.outputDir / (name + ".csv"));
    progress("wrote " + (options_.outputDir / (name + ".csv")).string());
  }

  void writeMachine() {
    const gl::ContextInfo& info = context_.info();
    std::string text;
    text += "renderer: " + info.renderer + "\n";
    text += "vendor: " + info.vendor + "\n";
    text += "gl_version: " + info.version + "\n";
    text += "platform: " + info.platform + "\n";
    text += "cpu: " + cpuModel() + "\n";
    text += "cpu_cores: " + std::to_string(std::thread::hardware_concurrency()) + "\n";
    text += "firn_version: " FIRN_VERSION "\n";
    text += "date_utc: " + utcNow() + "\n";
    text += "load_average_at_start: " + loadAtStart_ + "\n";
    text += "sizes: " + sizeName(options_.size) + "\n";
    text += "timing: " + std::to_string(sizes_.timing.warmupSteps) + " warm-up steps (excluded), then " +
            std::to_string(sizes_.timing.repeats) + " runs of " + std::to_string(sizes_.timing.stepsPerRepeat) +
            " steps, each glFinish to glFinish; medians\n";
    writeFileAtomically(options_.outputDir / "machine.txt", text, "machine description");
    progress("on " + info.renderer + " (" + info.platform + "), " + cpuModel());
  }

  struct Configuration {
    std::string label;
    std::function<Scene()> makeScene;
  };

  // Builds every configuration's scene and simulation, then times them all together, interleaved
  // (timeInterleaved); one that cannot be built (it does not fit the domain or the driver's buffers) or goes
  // unstable is an outcome, not a failure.
  std::vector<Timed> timeConfigurations(const std::vector<Configuration>& configurations) {
    std::vector<Timed> results(configurations.size());
    std::vector<std::unique_ptr<Simulation>> simulations;
    std::vector<Simulation*> built;
    std::vector<std::size_t> builtIndex;
    for (std::size_t i = 0; i < configurations.size(); ++i) {
      try {
        const Scene scene = configurations[i].makeScene();
        const std::vector<ParticleSeed> seeds = sampleBodies(scene);
        results[i].particles = seeds.size();
        simulations.push_back(std::make_unique<Simulation>(scene, seeds, context_.info()));
        built.push_back(simulations.back().get());
        builtIndex.push_back(i);
        progress(configurations[i].label + ": " + grouped(seeds.size()) + " particles, " + nodeDims(scene.grid.cells) +
                 " nodes");
      } catch (const InputError& error) {
        results[i].status = "skipped";
        progress(configurations[i].label + ": skipped: " + error.what());
      }
    }
    progress("timing " + std::to_string(built.size()) + " configurations interleaved: " +
             std::to_string(sizes_.timing.warmupSteps) + " warm-up steps each, then " +
             std::to_string(sizes_.timing.repeats) + " rounds of " + std::to_string(sizes_.timing.stepsPerRepeat) +
             " steps of each");
    const std::vector<InterleavedTiming> timings = timeInterleaved(built, sizes_.timing);
    for (std::size_t k = 0; k < built.size(); ++k) {
      Timed& result = results[builtIndex[k]];
      const std::string& label = configurations[builtIndex[k]].label;
      if (!timings[k].unstable.empty()) {
        result.status = "unstable";
        progress(label + ": unstable: " + timings[k].unstable);
        continue;
      }
      result.timing = timings[k].timing;
      result.activeNodes = built[k]->activeRegion().boxSize.w;
      progress(label + ": " + fixed(result.timing.medianMs, 2) + " ms per step (runs " + fixed(result.timing.minMs, 2) +
               "–" + fixed(result.timing.maxMs, 2) + ")");
    }
    return results;
  }

  static void setTiming(CsvTable::Row& row, const Timed& timed) {
    row.setText("status", timed.status);
    if (timed.status != "ok") return;
    row.setCount("active_nodes", timed.activeNodes)
        .setCount("steps", timed.timing.stepsPerRepeat)
        .setCount("repeats", timed.timing.repeats)
        .set("ms_per_step", timed.timing.medianMs)
        .set("ms_min", timed.timing.minMs)
        .set("ms_max", timed.timing.maxMs)
        .set("steps_per_s", 1e3 / timed.timing.medianMs)
        .set("gpu_ms_per_step", timed.timing.gpuMedianMs);
  }

  // Time per step against particle count on the thesis's 200³ grid: the unscaled series (one bunny, more
  // particles per cell) and the scaled one (8 per cell, a bunny ∛2 larger per size, so the counts match).
  void particles() {
    CsvTable table({"series", "atomics", "particles", "grid_cells", "grid_dims", "cell_size_m", "particles_per_cell",
                    "bunny_scale", "active_nodes", "steps", "repeats", "ms_per_step", "ms_min", "ms_max",
                    "steps_per_s", "gpu_ms_per_step", "status", "renderer"});
    const double smallestScale = bunnies().scaleFor(sizes_.smallestParticles, kSmallestParticlesPerCell);
    std::vector<std::string> series;
    std::vector<BunnySetup> setups;
    for (const std::string& atomics : atomics_) {
    for (const std::string name : {"unscaled", "scaled"}) {
      for (const double unscaledPerCell : sizes_.unscaledParticlesPerCell) {
        BunnySetup setup;
        setup.atomics = atomics;
        setup.gridCells = sizes_.particleGridCells;
        if (name == "unscaled") {
          setup.scale = smallestScale;
          setup.particlesPerCell = unscaledPerCell;
        } else {
          setup.scale = smallestScale * std::cbrt(unscaledPerCell / kScaledParticlesPerCell);
          setup.particlesPerCell = kScaledParticlesPerCell;
        }
        series.push_back(name);
        setups.push_back(setup);
      }
    }
    }
    std::vector<Configuration> configurations;
    for (std::size_t i = 0; i < setups.size(); ++i) {
      configurations.push_back({"particles, " + setups[i].atomics + " atomics, " + series[i] + ", " +
                                    fixed(setups[i].particlesPerCell, 0) +
                                    " per cell, bunny scale " + fixed(setups[i].scale, 3),
                                [&, i] { return bunnies().scene(setups[i]); }});
    }
    const std::vector<Timed> timed = timeConfigurations(configurations);
    std::string exponents;
    for (const std::string& atomics : atomics_) {
    for (const std::string name : {"unscaled", "scaled"}) {
      std::vector<std::pair<double, double>> points;
      for (std::size_t i = 0; i < setups.size(); ++i) {
        if (series[i] != name || setups[i].atomics != atomics) continue;
        const glm::ivec3 cells(setups[i].gridCells);
        CsvTable::Row& row = table.addRow();
        row.setText("series", name)
            .setText("atomics", atomics)
            .setCount("particles", std::int64_t(timed[i].particles))
            .setCount("grid_cells", nodeCount(cells))
            .setText("grid_dims", nodeDims(cells))
            .set("cell_size_m", bunnies().cellSizeM())
            .set("particles_per_cell", setups[i].particlesPerCell)
            .set("bunny_scale", setups[i].scale)
            .setText("renderer", renderer());
        setTiming(row, timed[i]);
        if (timed[i].status == "ok") points.emplace_back(double(timed[i].particles), timed[i].timing.medianMs);
      }
      if (points.size() >= 2) {
        const std::vector<std::pair<double, double>> largest(
            points.end() - std::ptrdiff_t(std::min(points.size(), kExponentFitSizes)), points.end());
        exponents += (exponents.empty() ? "" : ", ") + name + " " + atomics + " " + fixed(logLogSlope(largest), 3) +
                     " (" + grouped(std::uint64_t(largest.front().first)) + "–" +
                     grouped(std::uint64_t(largest.back().first)) + " particles)";
      }
    }
    }
    write(table, "particles");
    if (!exponents.empty()) {
      summary_.push_back("particles: exponent of ms per step against particles over the largest " +
                         std::to_string(kExponentFitSizes) + " sizes: " + exponents + "; issue bound 1.15");
    }
  }

  // Time per step against grid size with the same particles: the bunny sits in the domain's low corner, so
  // every domain holds exactly the same particles.
  void grid() {
    CsvTable table({"atomics", "grid_cells", "grid_dims", "particles", "active_nodes", "steps", "repeats",
                    "ms_per_step", "ms_min", "ms_max", "steps_per_s", "gpu_ms_per_step", "status", "renderer"});
    std::vector<Configuration> configurations;
    for (const std::string& atomics : atomics_) {
      BunnySetup setup = referenceBunny();
      setup.centred = false;
      setup.atomics = atomics;
      for (const int cells : sizes_.gridExperimentCells) {
        configurations.push_back({"grid, " + atomics + " atomics, " + std::to_string(cells) + "³ cells",
                                  [setup, cells, this]() mutable {
                                    setup.gridCells = cells;
                                    return bunnies().scene(setup);
                                  }});
      }
    }
    const std::vector<Timed> timed = timeConfigurations(configurations);
    std::string ratios;
    for (std::size_t series = 0; series < atomics_.size(); ++series) {
    std::vector<std::pair<std::int64_t, double>> timedSizes;
    for (std::size_t size = 0; size < sizes_.gridExperimentCells.size(); ++size) {
      const std::size_t i = series * sizes_.gridExperimentCells.size() + size;
      const glm::ivec3 cells(sizes_.gridExperimentCells[size]);
      CsvTable::Row& row = table.addRow();
      row.setText("atomics", atomics_[series])
          .setCount("grid_cells", nodeCount(cells))
          .setText("grid_dims", nodeDims(cells))
          .setCount("particles", std::int64_t(timed[i].particles))
          .setText("renderer", renderer());
      setTiming(row, timed[i]);
      if (timed[i].status == "ok") timedSizes.emplace_back(nodeCount(cells), timed[i].timing.medianMs);
    }
    if (timedSizes.size() >= 2) {
      ratios += (ratios.empty() ? "" : "; ") + atomics_[series] + " atomics: " +
                grouped(std::uint64_t(timedSizes.back().first)) + " nodes cost " +
                fixed(timedSizes.back().second / timedSizes.front().second, 3) + "x what " +
                grouped(std::uint64_t(timedSizes.front().first)) + " nodes cost";
    }
    }
    write(table, "grid");
    if (!ratios.empty()) summary_.push_back("grid, the same particles: " + ratios + "; issue bound 1.5");
  }

  // Each pass timed alone (GL_TIME_ELAPSED and wall time to glFinish) on the reference scene.
  void passes() {
    CsvTable table(
        {"atomics", "pass", "gpu_ms", "wall_ms", "share_of_step", "dispatches_per_step", "particles", "renderer"});
    for (const std::string& atomics : atomics_) {
    try {
      BunnySetup setup = referenceBunny();
      setup.atomics = atomics;
      const Scene scene = bunnies().scene(setup);
      const std::vector<ParticleSeed> seeds = sampleBodies(scene);
      Simulation simulation(scene, seeds, context_.info());
      const std::vector<PassTiming> timings = timePasses(simulation, sizes_.timing);
      double totalWallMs = 0, totalGpuMs = 0;
      for (const PassTiming& timing : timings) {
        totalWallMs += timing.wallMs;
        totalGpuMs += timing.gpuMs;
      }
      std::string shares;
      for (const PassTiming& timing : timings) {
        table.addRow()
            .setText("atomics", atomics)
            .setText("pass", timing.pass)
            .set("gpu_ms", timing.gpuMs)
            .set("wall_ms", timing.wallMs)
            .set("share_of_step", timing.wallMs / totalWallMs)
            .set("dispatches_per_step", timing.dispatchesPerStep)
            .setCount("particles", std::int64_t(seeds.size()))
            .setText("renderer", renderer());
        shares += (shares.empty() ? "" : ", ") + timing.pass + " " + fixed(100 * timing.wallMs / totalWallMs, 1) +
                  "% (" + fixed(timing.wallMs, 2) + " ms)";
      }
      progress("passes: " + shares);
      summary_.push_back("passes (" + grouped(seeds.size()) + " particles, cubic, PIC/FLIP, " + atomics +
                         " atomics), wall time " +
                         "per step, each pass timed alone: " + shares + "; sum " + fixed(totalWallMs, 2) +
                         " ms wall, " + fixed(totalGpuMs, 2) + " ms GL_TIME_ELAPSED");
    } catch (const SimulationError& error) {
      progress(std::string("passes: unstable: ") + error.what());
    } catch (const InputError& error) {
      progress(std::string("passes: skipped: ") + error.what());
    }
    }
    write(table, "passes");
  }

  // Fixed-point against float atomics: P2G's time, and its sums on the reference scene (falling and spinning)
  // against the same contributions added in double on the CPU.
  void p2gAtomics() {
    CsvTable table({"atomics", "p2g_ms", "p2g_gpu_ms", "mass_max_rel_error", "mass_rms_rel_error",
                    "momentum_max_rel_error", "momentum_rms_rel_error", "mass_max_error_units",
                    "momentum_max_error_units", "fraction_bits", "resolution_units", "max_contributions", "nodes",
                    "particles", "status", "renderer"});
    std::string summary;
    for (const std::string atomics : {"fixed", "float", "none"}) {
      CsvTable::Row& row = table.addRow();
      row.setText("atomics", atomics).setText("renderer", renderer());
      try {
        BunnySetup setup = referenceBunny();
        setup.atomics = atomics;
        setup.velocityMPerS = kP2GVelocityMPerS;
        setup.angularVelocityRadPerS = kP2GAngularVelocityRadPerS;
        const Scene scene = bunnies().scene(setup);
        const std::vector<ParticleSeed> seeds = sampleBodies(scene);
        Simulation simulation(scene, seeds, context_.info());
        const FixedPointScale& scale = simulation.fixedPoint();
        const ReferenceGrid reference = referenceParticleToGrid(scene, scale, simulation.snapshot());
        const SumErrorSummary errors =
            summarizeErrors(compareWithReference(simulation.readGridAfterTransfer(), reference, scene, scale));
        const std::vector<PassTiming> timings = timePasses(simulation, sizes_.timing);
        // P2G is one pass with atomics, binning and the coloured scatter without ("none").
        PassTiming p2g{"p2g"};
        for (const PassTiming& timing : timings) {
          if (timing.pass == "p2g" || timing.pass == "p2g_blocks" || timing.pass.rfind("bin_", 0) == 0) {
            p2g.wallMs += timing.wallMs;
            p2g.gpuMs += timing.gpuMs;
          }
        }
        if (p2g.wallMs == 0) throw std::logic_error("no p2g pass among the timed passes");
        row.set("p2g_ms", p2g.wallMs)
            .set("p2g_gpu_ms", p2g.gpuMs)
            .set("mass_max_rel_error", errors.massMaxRelative)
            .set("mass_rms_rel_error", errors.massRmsRelative)
            .set("momentum_max_rel_error", errors.momentumMaxRelative)
            .set("momentum_rms_rel_error", errors.momentumRmsRelative)
            .set("mass_max_error_units", errors.massMaxUnits)
            .set("momentum_max_error_units", errors.momentumMaxUnits)
            .setCount("max_contributions", errors.maxContributions)
            .setCount("nodes", std::int64_t(errors.nodes))
            .setCount("particles", std::int64_t(seeds.size()))
            .setText("status", "ok");
        if (atomics == "fixed") row.setCount("fraction_bits", scale.fractionBits).set("resolution_units", scale.resolution());
        const std::string line = atomics + ": P2G " + fixed(p2g.wallMs, 2) + " ms, relative error max/RMS mass " +
                                 formatNumber(errors.massMaxRelative) + "/" + formatNumber(errors.massRmsRelative) +
                                 ", momentum " + formatNumber(errors.momentumMaxRelative) + "/" +
                                 formatNumber(errors.momentumRmsRelative);
        progress("p2g atomics, " + line);
        summary += (summary.empty() ? "" : "; ") + line;
      } catch (const SimulationError& error) {
        row.setText("status", "unstable");
        progress("p2g atomics, " + atomics + ": unstable: " + error.what());
      } catch (const InputError& error) {
        row.setText("status", inputErrorStatus(atomics));
        progress("p2g atomics, " + atomics + ": " + error.what());
      }
    }
    write(table, "p2g_atomics");
    summary_.push_back("p2g atomics (" + fixed(bunnies().cellSizeM(), 2) + " m cells, bunny falling at " +
                       fixed(-kP2GVelocityMPerS.y, 0) + " m/s and spinning at " + fixed(kP2GAngularVelocityRadPerS.y, 0) +
                       " rad/s): " + summary);
  }

  // The elastic bar's period error against the cost of a simulated second, per configuration.
  void tradeoff() {
    CsvTable table({"configuration", "kernel", "transfer", "flip_ratio", "atomics", "dt_s", "dt_fraction",
                    "particles_per_cell", "cell_size_m", "particles", "steps", "ms_per_step",
                    "ms_per_simulated_second", "period_s", "error", "signed_error", "uncorrected_error",
                    "amplitude_retained", "kappa", "pareto", "status", "renderer"});
    struct Result {
      CsvTable::Row* row;
      std::string configuration;
      double costMs;  // per simulated second
      double error;
    };
    std::vector<Result> results;
    const double analyticPeriodS = barAnalyticPeriodS();
    for (const TradeoffCase& configuration : tradeoffCases(options_.size, sizes_.barPeriods)) {
      const BarSetup& setup = configuration.setup;
      CsvTable::Row& row = table.addRow();
      const std::string transfer = setup.transfer == "apic" ? "apic" : setup.flipRatio == 0 ? "pic" : "pic_flip";
      row.setText("configuration", configuration.name)
          .setText("kernel", setup.kernel)
          .setText("transfer", transfer)
          .setText("atomics", setup.atomics)
          .set("dt_fraction", setup.dtFraction)
          .set("particles_per_cell", setup.particlesPerCell)
          .set("cell_size_m", kBarLengthM / setup.cellsAlongBar)
          .setText("renderer", renderer());
      if (transfer != "apic") row.set("flip_ratio", setup.flipRatio);
      try {
        const BarVibration bar = measureBarVibration(setup, context_.info());
        row.set("dt_s", bar.dtS).setCount("particles", std::int64_t(bar.particles));
        const std::vector<double> timedMs(
            bar.stepWallMs.begin() + std::ptrdiff_t(std::min(kTradeoffWarmupSteps, bar.stepWallMs.size() - 1)),
            bar.stepWallMs.end());
        const double msPerStep = median(timedMs);
        row.setCount("steps", std::int64_t(timedMs.size()))
            .set("ms_per_step", msPerStep)
            .set("ms_per_simulated_second", msPerStep / bar.dtS)
            .set("kappa", bar.kappa);
        if (bar.periodS <= 0) {
          row.setText("status", "no_period");
          progress("tradeoff, " + configuration.name + ": no full period within the steps allowed");
          continue;
        }
        const double signedError = bar.periodS / (analyticPeriodS / std::sqrt(bar.kappa)) - 1;
        row.set("period_s", bar.periodS)
            .set("error", std::abs(signedError))
            .set("signed_error", signedError)
            .set("uncorrected_error", std::abs(bar.periodS / analyticPeriodS - 1))
            .set("amplitude_retained", bar.amplitudeRetained);
        if (bar.amplitudeRetained > kAmplitudeGrowthTolerance) {
          row.setText("status", "growing");
        } else {
          row.setText("status", "ok");
          results.push_back({&row, configuration.name, msPerStep / bar.dtS, std::abs(signedError)});
        }
        progress("tradeoff, " + configuration.name + ": " + grouped(bar.particles) + " particles, " +
                 fixed(msPerStep, 2) + " ms per step, " + fixed(msPerStep / bar.dtS / 1e3, 2) +
                 " s per simulated second, period error " + fixed(100 * signedError, 2) + "%, amplitude kept " +
                 fixed(bar.amplitudeRetained, 3));
      } catch (const SimulationError& error) {
        row.setText("status", "unstable");
        progress("tradeoff, " + configuration.name + ": unstable: " + error.what());
      } catch (const InputError& error) {
        row.setText("status", inputErrorStatus(setup.atomics));
        progress("tradeoff, " + configuration.name + ": " + error.what());
      }
    }
    // Pareto: no other configuration is at once no more costly and no less accurate, and better in one.
    std::vector<const Result*> front;
    for (const Result& result : results) {
      const bool dominated = std::any_of(results.begin(), results.end(), [&](const Result& other) {
        return other.costMs <= result.costMs && other.error <= result.error &&
               (other.costMs < result.costMs || other.error < result.error);
      });
      result.row->setCount("pareto", dominated ? 0 : 1);
      if (!dominated) front.push_back(&result);
    }
    std::sort(front.begin(), front.end(), [](const Result* a, const Result* b) { return a->costMs < b->costMs; });
    std::string frontText;
    for (const Result* result : front) {
      frontText += (frontText.empty() ? "" : ", ") + result->configuration + " (" + fixed(result->costMs / 1e3, 2) +
                   " s per simulated s, error " + formatNumber(result->error) + ")";
    }
    write(table, "tradeoff");
    summary_.push_back("tradeoff (elastic bar, period error against T/sqrt(kappa)): Pareto front " +
                       (frontText.empty() ? std::string("empty") : frontText));
  }

  // The thesis implementation's own bunny in Firn, against its 546 ms per step, once per atomics.
  void thesis() {
    CsvTable table({"atomics", "particles", "grid_dims", "dt_s", "steps", "repeats", "ms_per_step", "ms_min",
                    "ms_max", "ms_per_simulated_second", "thesis_ms_per_step", "thesis_dt_s", "speedup_per_step",
                    "speedup_per_simulated_second", "status", "renderer"});
    std::vector<Configuration> configurations;
    for (const std::string& atomics : atomics_) {
      configurations.push_back({"thesis bunny, " + atomics + " atomics, dt " + formatNumber(options_.thesisDtS) + " s",
                                [this, atomics] {
                                  return thesisCloudScene(options_.thesisCloud, options_.thesisDtS, atomics);
                                }});
    }
    const std::vector<Timed> timed = timeConfigurations(configurations);
    for (std::size_t i = 0; i < timed.size(); ++i) {
      CsvTable::Row& row = table.addRow();
      row.setText("atomics", atomics_[i])
          .setCount("particles", std::int64_t(timed[i].particles))
          .setText("grid_dims", nodeDims(glm::ivec3(kThesisGridCells)))
          .set("dt_s", options_.thesisDtS)
          .set("thesis_ms_per_step", kThesisMsPerStep)
          .set("thesis_dt_s", kThesisDtS)
          .setText("status", timed[i].status)
          .setText("renderer", renderer());
      if (timed[i].status != "ok") continue;
      const double msPerStep = timed[i].timing.medianMs;
      const double msPerSimulatedSecond = msPerStep / options_.thesisDtS;
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
      summary_.push_back("thesis bunny (" + grouped(timed[i].particles) + " particles, " + atomics_[i] + " atomics, dt " +
                         formatNumber(options_.thesisDtS) + " s): " + fixed(msPerStep, 1) + " ms per step, " +
                         fixed(speedupPerStep, 2) + "x faster than the thesis's 546 ms per step; per simulated second " +
                         fixed(speedupPerSimulatedSecond, 2) + "x (the thesis steps 1e-3 s)");
    }
    write(table, "thesis");
  }

  const BenchOptions& options_;
  std::ostream& log_;
  Sizes sizes_;
  std::optional<BunnyScenes> bunnies_;  // when a table needs them (the bar and the thesis cloud do not)
  gl::HeadlessContext context_;
  std::vector<std::string> summary_;
  std::string loadAtStart_;
  std::vector<std::string> atomics_;  // the series of the particle, grid, passes and thesis tables
};

}  // namespace

const std::vector<std::string>& tableNames() {
  static const std::vector<std::string> names = {"particles", "grid", "passes", "p2g_atomics", "tradeoff", "thesis"};
  return names;
}

std::filesystem::path defaultAssetsDir() { return std::filesystem::path(FIRN_SOURCE_DIR) / "assets"; }
std::filesystem::path plotScript() { return std::filesystem::path(FIRN_SOURCE_DIR) / "benchmarks" / "plot.sh"; }

std::string runBench(const BenchOptions& options, std::ostream& log) {
  // Said before any measuring: a run of many minutes should not end in "cannot write".
  const std::filesystem::path parent = std::filesystem::absolute(options.outputDir).parent_path();
  if (!std::filesystem::is_directory(parent)) {
    throw InputError("--out: " + options.outputDir.string() + ": its parent folder " + parent.string() +
                     " does not exist");
  }
  std::error_code error;
  std::filesystem::create_directories(options.outputDir, error);
  if (error) throw InputError("--out: " + options.outputDir.string() + ": cannot create the folder (" + error.message() + ")");
  if (!options.thesisCloud.empty() && !std::filesystem::is_regular_file(options.thesisCloud)) {
    throw InputError("--thesis-cloud: " + options.thesisCloud.string() + ": no such file");
  }
  if (options.thesisCloud.empty() &&
      std::find(options.tables.begin(), options.tables.end(), "thesis") != options.tables.end()) {
    throw InputError("--only thesis: the thesis table needs the thesis's point cloud (--thesis-cloud PATH)");
  }
  BenchRun run(options, log);
  run.run();
  return run.summary();
}

bool makePlots(const std::filesystem::path& dir, std::ostream& log) {
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    log << "firn bench: no plots: gnuplot is not installed (Debian: apt-get install gnuplot-nox); the tables are "
           "written, and `firn bench --plots-only "
        << dir.string() << "` plots them later\n";
    return false;
  }
  const std::filesystem::path script = plotScript();
  if (!std::filesystem::is_regular_file(script)) {
    log << "firn bench: no plots: " << script.string() << " (Firn's source tree) is not there\n";
    return false;
  }
  const int status = std::system(("bash " + shellQuoted(script.string()) + " " + shellQuoted(dir.string())).c_str());
  if (status != 0) throw std::runtime_error(script.string() + " failed on " + dir.string());
  return true;
}

}  // namespace firn::bench
