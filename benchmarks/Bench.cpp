// The driver of `firn bench`: checks the options, describes the machine (machine.txt), runs the experiments
// the options ask for (Experiments.h, one file each), writes summary.txt, and plots the tables.
#include "Bench.h"

#include <algorithm>
#include <chrono>
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

// machine.txt, the experiments asked for, and summary.txt: a headline (the machine, how long the run took and
// how busy the machine was) and each experiment's findings. Returns the summary.
std::string runExperiments(BenchRun& run) {
  const auto start = Clock::now();
  const std::string loadAtStart = loadAverage();
  writeMachine(run, loadAtStart);
  if (run.wanted("particles")) measureParticles(run);
  if (run.wanted("grid")) measureGrid(run);
  if (run.wanted("domain")) measureDomain(run);
  if (run.wanted("passes")) measurePasses(run);
  if (run.wanted("p2g_atomics")) measureP2GAtomics(run);
  if (run.wanted("tradeoff")) measureTradeoff(run);
  if (run.wanted("stiff")) measureStiff(run);
  if (!run.options().thesisCloud.empty() && run.wanted("thesis")) measureThesis(run);
  if (!run.options().thesisCloud.empty() && run.wanted("objects")) measureObjects(run);
  if (run.wanted("surface")) measureSurface(run);
  const double minutes = std::chrono::duration<double>(Clock::now() - start).count() / 60;
  std::string summary = "firn bench (" + sizeName(run.options().size) + ") on " + run.renderer() + ", " +
                        cpuModel() + " x " + std::to_string(std::thread::hardware_concurrency()) +
                        " cores: " + fixed(minutes, 1) + " min; load average " + loadAtStart + " at the start, " +
                        loadAverage() + " at the end\n";
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
