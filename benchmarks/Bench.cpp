// The driver of `firn bench`: checks the options, describes the machine (machine.txt), runs the experiments
// the options ask for (Experiments.h, one file each), writes summary.txt, and plots the tables.
#include "Bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <thread>

#include "Error.h"
#include "Experiments.h"
#include "io/AtomicFile.h"
#include "io/EnergyPlot.h"
#include "io/OutputFolder.h"

namespace firn::bench {

namespace {

using Clock = std::chrono::steady_clock;

// The rows of a CSV table below its header (0 for a file that is not there).
std::size_t readCsvRows(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::size_t lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  return lines > 0 ? lines - 1 : 0;
}

std::string sizeName(BenchSize size) {
  switch (size) {
    case BenchSize::Default: return "default";
    case BenchSize::Quick: return "quick";
    case BenchSize::Tiny: return "tiny";
  }
  return "";
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

// Single quotes for the shell, with embedded single quotes closed, escaped and reopened.
std::string shellQuoted(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

void writeMachine(BenchRun& run, const std::string& loadAtStart) {
  const gl::ContextInfo& info = run.gl();
  const TimingPlan& timing = run.sizes().timing;
  std::string text;
  text += "renderer: " + info.renderer + "\n";
  text += "vendor: " + info.vendor + "\n";
  text += "gl_version: " + info.version + "\n";
  text += "platform: " + info.platform + "\n";
  text += "cpu: " + cpuModel() + "\n";
  text += "cpu_cores: " + std::to_string(std::thread::hardware_concurrency()) + "\n";
  text += "firn_version: " FIRN_VERSION "\n";
  text += "date_utc: " + utcNow() + "\n";
  text += "load_average_at_start: " + loadAtStart + "\n";
  text += "sizes: " + sizeName(run.options().size) + "\n";
  text += "timing: " + std::to_string(timing.warmupSteps) + " warm-up steps (excluded), then " +
          std::to_string(timing.repeats) + " runs of " + std::to_string(timing.stepsPerRepeat) +
          " steps, each glFinish to glFinish; medians\n";
  writeFileAtomically(run.options().outputDir / "machine.txt", text, "machine description");
  run.progress("on " + info.renderer + " (" + info.platform + "), " + cpuModel());
}

// A table of the run: what it will do, and doing it.
struct Experiment {
  std::string table;
  PlannedWork (*plan)(const BenchRun&);
  void (*measure)(BenchRun&);
};

// The tables the options ask for, in the order they run; thesis and objects only with the thesis's cloud.
std::vector<Experiment> wantedExperiments(const BenchRun& run) {
  const std::vector<Experiment> all = {{"particles", planParticles, measureParticles},
                                       {"grid", planGrid, measureGrid},
                                       {"domain", planDomain, measureDomain},
                                       {"passes", planPasses, measurePasses},
                                       {"p2g_atomics", planP2GAtomics, measureP2GAtomics},
                                       {"tradeoff", planTradeoff, measureTradeoff},
                                       {"stiff", planStiff, measureStiff},
                                       {"thesis", planThesis, measureThesis},
                                       {"objects", planObjects, measureObjects},
                                       {"surface", planSurface, measureSurface}};
  std::vector<Experiment> wanted;
  for (const Experiment& experiment : all) {
    const bool needsCloud = experiment.table == "thesis" || experiment.table == "objects";
    if (run.wanted(experiment.table) && (!needsCloud || !run.options().thesisCloud.empty())) {
      wanted.push_back(experiment);
    }
  }
  return wanted;
}

// "42 s", "3 min 07 s".
std::string minutesAndSeconds(double seconds) {
  const long whole = std::lround(seconds);
  if (whole < 60) return std::to_string(whole) + " s";
  return std::to_string(whole / 60) + " min " + (whole % 60 < 10 ? "0" : "") + std::to_string(whole % 60) + " s";
}

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// machine.txt, the experiments asked for, and summary.txt: a headline (the machine, how long the run took against
// the estimate said before it, how busy the machine was) and each experiment's findings. Before the tables, a
// calibration on this machine turns each table's planned work into an estimate, said up front; after each table,
// its time against its estimate and what is left. Returns the summary.
std::string runExperiments(BenchRun& run) {
  const auto start = Clock::now();
  const std::string loadAtStart = loadAverage();
  writeMachine(run, loadAtStart);
  const std::vector<Experiment> experiments = wantedExperiments(run);
  const StepCosts costs = run.calibrate();
  std::vector<double> estimatesS;
  std::string plan;
  double estimatedTotalS = 0;
  for (const Experiment& experiment : experiments) {
    try {
      estimatesS.push_back(costs.seconds(experiment.plan(run)));
    } catch (const InputError& error) {
      // A scene of the table that cannot be made: the table makes its row say so; the estimate leaves the table out.
      estimatesS.push_back(0);
      run.progress("no estimate for " + experiment.table + ": " + error.what());
    }
    estimatedTotalS += estimatesS.back();
    plan += (plan.empty() ? "" : ", ") + experiment.table + " " + minutesAndSeconds(estimatesS.back());
  }
  estimatedTotalS += secondsSince(start);  // the calibration and the planning
  run.progress("estimated " + minutesAndSeconds(estimatedTotalS) + " in all, the calibration included (" + plan + ")");
  std::string tableTimes;
  for (std::size_t i = 0; i < experiments.size(); ++i) {
    const auto tableStart = Clock::now();
    run.progress("table " + std::to_string(i + 1) + " of " + std::to_string(experiments.size()) + ", " +
                 experiments[i].table + ": about " + minutesAndSeconds(estimatesS[i]));
    experiments[i].measure(run);
    double leftS = 0;
    for (std::size_t k = i + 1; k < experiments.size(); ++k) leftS += estimatesS[k];
    const std::string took = minutesAndSeconds(secondsSince(tableStart));
    tableTimes += (tableTimes.empty() ? "" : ", ") + experiments[i].table + " " + took + " (estimated " +
                  minutesAndSeconds(estimatesS[i]) + ")";
    run.progress(experiments[i].table + " took " + took + " (estimated " + minutesAndSeconds(estimatesS[i]) + "); " +
                 minutesAndSeconds(secondsSince(start)) + " so far, about " + minutesAndSeconds(leftS) + " left");
  }
  std::string summary = "firn bench (" + sizeName(run.options().size) + ") on " + run.renderer() + ", " +
                        cpuModel() + " x " + std::to_string(std::thread::hardware_concurrency()) +
                        " cores: " + minutesAndSeconds(secondsSince(start)) + ", estimated " +
                        minutesAndSeconds(estimatedTotalS) + " before it started; load average " + loadAtStart +
                        " at the start, " + loadAverage() + " at the end\n";
  summary += "tables: " + tableTimes + "\n";
  for (const std::string& line : run.summaryLines()) summary += line + "\n";
  writeFileAtomically(run.options().outputDir / "summary.txt", summary, "benchmark summary");
  return summary;
}

}  // namespace

const std::vector<std::string>& tableNames() {
  static const std::vector<std::string> names = {"particles", "grid", "domain", "passes", "p2g_atomics", "tradeoff",
                                                    "stiff", "thesis", "surface", "objects"};
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
  // Held to the end of the measurements: no other run writes here meanwhile.
  const OutputFolderClaim outputFolder(options.outputDir);
  if (!options.thesisCloud.empty() && !std::filesystem::is_regular_file(options.thesisCloud)) {
    throw InputError("--thesis-cloud: " + options.thesisCloud.string() + ": no such file");
  }
  for (const char* bunnyTable : {"thesis", "objects"}) {
    if (!options.thesisCloud.empty() ||
        std::find(options.tables.begin(), options.tables.end(), bunnyTable) == options.tables.end()) {
      continue;
    }
    throw InputError(std::string("--only ") + bunnyTable + ": the " + bunnyTable +
                     " table needs --thesis-cloud FILE, the bunny of the Snow thesis 2015 implementation as a point "
                     "cloud (one x,y,z per line, or a PLY), which Firn does not ship. "
                     "`firn voxelize assets/meshes/bunny.obj --scale 0.01557 --translate 0,0.033,0 --spacing 0.002 "
                     "--out thesis_bunny.ply` makes a comparable one, 91,599 particles against its 91,897 "
                     "(benchmarks/README.md, the thesis table)");
  }
  BenchRun run(options, log);
  return runExperiments(run);
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
  // The energy budget over time of the trade-off table's baseline bar, as `firn run --plot` draws a run's.
  const std::filesystem::path energy = dir / "energy.csv";
  if (readCsvRows(energy) > 0) {
    plotEnergy(energy, dir, "The elastic bar's energy (tradeoff.csv's baseline)");
    log << "firn bench: wrote " << (dir / "energy.png").string() << "\n";
  }
  return true;
}

}  // namespace firn::bench
