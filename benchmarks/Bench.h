#pragma once
// `firn bench` (issue 7): the source thesis's scaling experiments on its bunny (Snow thesis 2015 §5.2: time per
// step against particle count, scaled and unscaled, and against grid size), per-pass GPU times, the atomics'
// speed and P2G error, and the speed/accuracy trade on a reference problem with a known answer
// (benchmarks/ElasticBar.h). Each configuration is built, warmed up (excluded), then timed in repeated runs
// whose median is reported; every table names the renderer, and machine.txt the machine.
// benchmarks/README.md says what each table holds; Experiments.h lists the experiments, one file each.
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace firn::bench {

// Default: real GPUs, up to millions of particles. Quick: a CPU renderer (llvmpipe on 2 cores, under 3 minutes),
// every table's shape with fewer and smaller points. Tiny: the smallest sizes, for tests of the machinery; they
// measure nothing.
enum class BenchSize { Default, Quick, Tiny };

// The tables, by file name without ".csv" (what --only takes).
const std::vector<std::string>& tableNames();

struct BenchOptions {
  std::filesystem::path outputDir = "firn-bench";
  BenchSize size = BenchSize::Default;
  int repeats = 0;                     // timed runs per configuration; 0: the size's own
  int stepsPerRepeat = 0;              // 0: the size's own
  std::filesystem::path assetsDir;     // holds scenes/bunny_thesis.json and meshes/bunny.obj
  std::filesystem::path thesisCloud;   // the thesis implementation's bunny; empty: no thesis.csv
  double thesisDtS = 2.5e-4;           // the thesis's 1e-3 s is beyond Firn's explicit elastic bound
  std::vector<std::string> tables;     // empty: all of them (thesis only with a thesisCloud)
  // How P2G sums (solver.atomics) in the particle, grid, passes and thesis tables, each a series of its own.
  // Empty: "fixed" (the default), and "float" where the driver has float atomics.
  std::vector<std::string> atomics;
};

// The source tree's assets folder and plot script, where this build found them.
std::filesystem::path defaultAssetsDir();
std::filesystem::path plotScript();

// Runs the experiments and writes their tables, machine.txt and summary.txt into options.outputDir (created;
// its parent must exist), with progress on `log`: first an estimate of the whole run, then each table's time
// against it. Returns the summary. Throws InputError (exit 2) for bad
// options or missing inputs, before any measuring where it can; a configuration that goes unstable or does
// not fit the driver's buffers is a row that says so, not a failure.
std::string runBench(const BenchOptions& options, std::ostream& log);

// Plots DIR/*.csv into DIR/*.png with benchmarks/plot.sh. Without gnuplot, or without the script, says how to
// get them on `log` and returns false. Throws InputError if the script fails.
bool makePlots(const std::filesystem::path& dir, std::ostream& log);

}  // namespace firn::bench
