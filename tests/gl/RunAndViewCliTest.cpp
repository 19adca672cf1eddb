// `firn run` and `firn view` start a scene the same way (run/SimulationSession.h): the same particles, the same
// pre-flight notes, and the same refusals with the same exit status. The window runs under a virtual X server
// (xvfb-run), as docs/platform.md, The viewer under Xvfb, says.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "Cli.h"

namespace {

namespace fs = std::filesystem;
using firn::test::freshDirectory;
using firn::test::kBallScene;
using firn::test::kOnXvfb;
using firn::test::linesAfter;
using firn::test::onPath;
using firn::test::Result;
using firn::test::runFirn;
using firn::test::writeScene;

Result runScene(const fs::path& scene, const fs::path& folder) {
  return runFirn("run " + scene.string() + " --frames 0 --no-ply --out " + (folder / "out").string());
}

Result viewScene(const fs::path& scene) {
  return runFirn("view " + scene.string() + " --frames 1 --width 160 --height 120", kOnXvfb);
}

// The opening line up to the frames and the renderer (a window's context names its renderer as it likes), then
// every pre-flight note and warning, word for word under each command's prefix.
TEST(RunAndView, StartTheSameParticlesWithTheSameNotes) {
  if (!onPath("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs the xvfb package)";
  const fs::path folder = freshDirectory("run_and_view");
  const fs::path scene = writeScene(folder, "ball.json", kBallScene);
  const Result run = runScene(scene, folder);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const Result view = viewScene(scene);
  ASSERT_EQ(view.exitCode, 0) << view.output;
  std::vector<std::string> runLines = linesAfter(run.output, "firn: ");
  std::vector<std::string> viewLines = linesAfter(view.output, "firn view: ");
  // The transfers' line reports what each process measured (sim/TransferShape.h): each has one, then it is set aside.
  for (std::vector<std::string>* lines : {&runLines, &viewLines}) {
    const auto transfers = [](const std::string& line) { return line.rfind("transfers: ", 0) == 0; };
    EXPECT_EQ(std::count_if(lines->begin(), lines->end(), transfers), 1) << run.output << view.output;
    lines->erase(std::remove_if(lines->begin(), lines->end(), transfers), lines->end());
  }
  ASSERT_GE(runLines.size(), 3u) << run.output;
  ASSERT_GE(viewLines.size(), 3u) << view.output;
  const std::string opening = runLines[0].substr(0, runLines[0].find(" s, 0 frames on "));
  EXPECT_EQ(viewLines[0].rfind(opening + " s on ", 0), 0u) << run.output << view.output;
  for (std::size_t i = 1; i < runLines.size() && runLines[i].rfind("wrote ", 0) != 0; ++i) {
    ASSERT_LT(i, viewLines.size()) << view.output;
    EXPECT_EQ(viewLines[i], runLines[i]);
  }
}

// Far beyond the stable step (E = 1e9 Pa: h / c = 2.6e-5 s against dt = 1e-3 s) neither command simulates
// anything: exit 2, and the same message.
TEST(RunAndView, RefuseATimeStepFarBeyondTheBoundAlike) {
  if (!onPath("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs the xvfb package)";
  const fs::path folder = freshDirectory("run_and_view_stiff");
  std::string json = kBallScene;
  json.replace(json.find("\"preset\": \"stomakhin\""), 21, "\"preset\": \"stomakhin\", \"youngs_modulus\": 1e9");
  const fs::path scene = writeScene(folder, "stiff.json", json);
  const Result run = runScene(scene, folder);
  const Result view = viewScene(scene);
  EXPECT_EQ(run.exitCode, 2) << run.output;
  EXPECT_EQ(view.exitCode, 2) << view.output;
  const std::vector<std::string> runError = linesAfter(run.output, "firn: error: ");
  const std::vector<std::string> viewError = linesAfter(view.output, "firn: error: ");
  ASSERT_EQ(runError.size(), 1u) << run.output;
  EXPECT_NE(runError[0].find("time.dt: 0.001 s is"), std::string::npos) << run.output;
  EXPECT_EQ(viewError, runError) << view.output;
}

// A box of 2.3³ m at 1,000 particles per cell of 1 cm: about 12 billion particles, beyond the GPU's 32-bit indices
// whatever the machine. Both commands refuse it before sampling with the same estimate (the viewer also keeps room
// for its snowballs, so the room left differs).
TEST(RunAndView, RefuseAnOverBudgetSceneWithTheSameEstimate) {
  if (!onPath("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs the xvfb package)";
  const fs::path folder = freshDirectory("run_and_view_budget");
  const fs::path scene = writeScene(folder, "huge.json", R"({
    "grid": { "cells": [256, 256, 256], "cell_size": 0.01 },
    "time": { "dt": 1e-4, "frame_rate": 50, "frames": 2 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "box", "min": [0.1, 0.1, 0.1], "max": [2.4, 2.4, 2.4], "material": "snow",
                  "particles_per_cell": 1000 } ] })");
  const Result run = runScene(scene, folder);
  const Result view = viewScene(scene);
  EXPECT_EQ(run.exitCode, 2) << run.output;
  EXPECT_EQ(view.exitCode, 2) << view.output;
  // "huge.json: bodies: about N particles (bodies[0], a box at 1e+03 particles per cell: N)"
  const std::size_t start = run.output.find("huge.json: bodies: about ");
  ASSERT_NE(start, std::string::npos) << run.output;
  const std::string estimate = run.output.substr(start, run.output.find(')', start) + 1 - start);
  EXPECT_NE(estimate.find("(bodies[0], a box at "), std::string::npos) << estimate;
  EXPECT_NE(view.output.find(estimate), std::string::npos) << view.output;
  EXPECT_NE(view.output.find("(the viewer's snowballs)"), std::string::npos) << view.output;
}

}  // namespace
