// The energy audit as `firn run` reports it (docs/command-line.md: stats.csv, bodies.csv, run.json, --plot): a step
// three times the elastic bound stops the run (exit 3) when its energy grows from nothing, and a moving collider's
// work on the snow is the ∫ F · v its bodies.csv rows give.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "Cli.h"

namespace {

namespace fs = std::filesystem;
using firn::test::freshDirectory;
using firn::test::readTable;
using firn::test::Table;
using firn::test::Result;
using firn::test::runFirn;
using firn::test::writeScene;

nlohmann::json runRecord(const fs::path& folder) {
  std::ifstream in(folder / "run.json");
  return nlohmann::json::parse(in);
}

// The issue's case: a snowball of E = 1e9 Pa (c = 1889 m/s) in 5 cm cells at Δt = 7.5e-5 s, 2.8 times the elastic
// bound h / c = 2.65e-5 s that pre-flight states (and below the 4 times it refuses). Before the audit it ran to its
// end with exit 0, its kinetic energy going from 0.84 J to 114 J in the first frame. Now the first frame's audit stops
// it: exit 3, saying how much energy appeared, which material carries it and the step to use; nothing non-finite is
// written, and run.json says how the run ended.
TEST(EnergyCli, StepThreeTimesTheBoundStopsWhenItsEnergyGrows) {
  const fs::path directory = freshDirectory("energy_unstable");
  const fs::path scene = writeScene(directory, "stiff.json", R"({
    "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
    "time": { "dt": 7.5e-5, "frame_rate": 50, "frames": 4 },
    "materials": { "snow": { "preset": "stomakhin", "youngs_modulus": 1e9 } },
    "bodies": [ { "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.1, "material": "snow", "velocity": [1, 0, 0] } ],
    "colliders": [ { "type": "plane", "point": [0, 0.3, 0], "normal": [0, 1, 0] } ] })");
  const fs::path out = directory / "out";
  const Result result = runFirn("run " + scene.string() + " --out " + out.string());
  ASSERT_EQ(result.exitCode, 3) << result.output;
  EXPECT_NE(result.output.find("the energy grew by"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("The particles of material \"snow\" carry"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("dt < h / c = 2.647e-05 s"), std::string::npos) << result.output;
  const Table stats = readTable(out / "stats.csv");
  ASSERT_EQ(stats.rows.size(), 1u);  // frame 0 alone: the first frame is not written
  for (const auto& row : stats.rows) {
    for (const auto& cell : row) EXPECT_TRUE(std::isfinite(std::stod(cell))) << cell;
  }
  const nlohmann::json run = runRecord(out);
  EXPECT_EQ(run["exit"]["status"], 3);
  EXPECT_NE(run["exit"]["message"].get<std::string>().find("the energy grew by"), std::string::npos);
  EXPECT_EQ(run["frames"]["last"], 0);
}

// A box collider moving at 0.6 m/s through a block of snow on the floor: the work it does on the snow is what its
// bodies.csv rows say, ∫ F · v dt = Σ −F · v Δt over the frames (F the snow's mean force on the box over a frame: for a
// box that only translates, the frame's impulse times its velocity, exactly), and stats.csv's collider_work_j is the
// same energy: both are the audit's sums, to their 9 and 17 digits. Most of the energy it puts in, the snow
// dissipates (the run ends with exit 0: nothing was made beyond the audit's tolerance). stats.csv is plain CSV (its
// header first), run.json records the run, and --plot draws energy.png where gnuplot is installed.
TEST(EnergyCli, MovingColliderWorkIsTheForceTimesItsVelocity) {
  const fs::path directory = freshDirectory("energy_collider");
  const fs::path scene = writeScene(directory, "push.json", R"({
    "grid": { "cells": [24, 16, 16], "cell_size": 0.04 },
    "time": { "dt": 5e-4, "frame_rate": 50, "frames": 8 },
    "solver": { "kernel": "quadratic", "transfer": "apic" },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "box", "min": [0.3, 0.08, 0.2], "max": [0.5, 0.2, 0.44], "material": "snow",
                  "particles_per_cell": 4 } ],
    "colliders": [
      { "type": "plane", "point": [0, 0.08, 0], "normal": [0, 1, 0], "friction": 0.3 },
      { "type": "box", "min": [0.16, 0.08, 0.24], "max": [0.24, 0.3, 0.4], "velocity": [0.6, 0, 0],
        "boundary": "sticky" } ] })");
  const fs::path out = directory / "out";
  const bool plots = firn::test::onPath("gnuplot");
  const Result result = runFirn("run " + scene.string() + " --no-ply --out " + out.string() + (plots ? " --plot" : ""));
  ASSERT_EQ(result.exitCode, 0) << result.output;
  std::ifstream statsFile(out / "stats.csv");
  std::string firstLine;
  std::getline(statsFile, firstLine);
  EXPECT_EQ(firstLine.rfind("frame,time_s,", 0), 0u) << firstLine;

  const Table stats = readTable(out / "stats.csv");
  const Table bodies = readTable(out / "bodies.csv");
  ASSERT_EQ(stats.rows.size(), 9u);
  ASSERT_EQ(bodies.rows.size(), 9u);  // the moving box alone: the plane stays
  double forceWorkJ = 0;
  for (std::size_t frame = 1; frame < bodies.rows.size(); ++frame) {
    const double frameS = bodies.at(frame, "time_s") - bodies.at(frame - 1, "time_s");
    forceWorkJ -= (bodies.at(frame, "fx_n") * bodies.at(frame, "vx_m_per_s") +
                   bodies.at(frame, "fy_n") * bodies.at(frame, "vy_m_per_s") +
                   bodies.at(frame, "fz_n") * bodies.at(frame, "vz_m_per_s")) * frameS;
    const double workJ = bodies.at(frame, "work_j");
    EXPECT_NEAR(workJ, stats.at(frame, "collider_work_j"), 1e-8 * workJ) << "frame " << frame;
    EXPECT_NEAR(workJ, forceWorkJ, 1e-6 * workJ) << "frame " << frame;
  }
  const double totalWorkJ = bodies.at(8, "work_j");
  EXPECT_GT(totalWorkJ, 0.01);  // the box pushed the snow a good way
  EXPECT_GT(stats.at(8, "dissipated_energy_j"), 0.5 * totalWorkJ);  // and most of what it gave, the snow dissipated

  const nlohmann::json run = runRecord(out);
  EXPECT_EQ(run["exit"]["status"], 0);
  EXPECT_EQ(run["exit"]["message"], "");
  EXPECT_EQ(run["frames"]["last"], 8);
  EXPECT_EQ(run["scene"]["fingerprint"].get<std::string>().size(), 16u);
  EXPECT_FALSE(run["transfers"]["shape"].get<std::string>().empty());
  EXPECT_FALSE(run["device"]["renderer"].get<std::string>().empty());
  EXPECT_EQ(run["command_line"][1], "run");
  if (plots) {
    EXPECT_TRUE(fs::is_regular_file(out / "energy.png")) << result.output;
    EXPECT_GT(fs::file_size(out / "energy.png"), 10000u);
    EXPECT_TRUE(fs::is_regular_file(out / "energy.gp"));
  }
}

}  // namespace
