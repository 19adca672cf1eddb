// The `firn` command line as a user runs it: outputs, exit codes and messages (docs/command-line.md).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "Cli.h"
#include "io/Ply.h"

namespace {

namespace fs = std::filesystem;
using firn::test::freshDirectory;
using firn::test::readCsv;
using firn::test::Result;
using firn::test::runFirn;
using firn::test::writeScene;

const char* const kSmallScene = R"({
  "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
  "time": { "dt": 1e-3, "frame_rate": 50, "frames": 3 },
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.15, "material": "snow" } ] })";

// `firn run --check` does what a run does before its first step and stops: pre-flight's report, then a line saying
// the scene is ready with the particles the run samples (the same count as the run's stats.csv) and its steps (3
// frames of 1/50 s at 1e-3 s: 60), exit 0, and no output folder. A scene or a checkpoint the run refuses is refused
// alike: exit 2, the same message, nothing written.
TEST(Cli, CheckReportsPreflightAndWritesNothing) {
  const fs::path directory = freshDirectory("check");
  const fs::path scene = writeScene(directory, "ball.json", kSmallScene);
  const Result checked = runFirn("run " + scene.string() + " --check --out " + (directory / "checked").string());
  ASSERT_EQ(checked.exitCode, 0) << checked.output;
  EXPECT_NE(checked.output.find("stable time step: elastic bound"), std::string::npos) << checked.output;
  EXPECT_FALSE(fs::exists(directory / "checked"));
  const Result ran = runFirn("run " + scene.string() + " --frames 1 --checkpoint-every 1 --no-ply --out " +
                             (directory / "ran").string());
  ASSERT_EQ(ran.exitCode, 0) << ran.output;
  const auto rows = readCsv(directory / "ran" / "stats.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0][3], "particles");
  const std::string particles = std::to_string(std::stoi(rows[1][3]));
  const std::string grouped =
      particles.size() > 3 ? particles.substr(0, particles.size() - 3) + "," + particles.substr(particles.size() - 3)
                           : particles;
  // The fingerprint the check prints is the run's (run.json), which a scene written anew must reproduce (the Blender
  // add-on's round trip).
  std::ifstream record(directory / "ran" / "run.json");
  const std::string fingerprint = nlohmann::json::parse(record)["scene"]["fingerprint"].get<std::string>();
  EXPECT_NE(checked.output.find("firn: check: ready to run: " + grouped + " particles, 3 frames, 60 steps of 0.001 s, "
                                "scene fingerprint " + fingerprint + ";"),
            std::string::npos)
      << checked.output;
  // Resumed, the check resumes the checkpoint as the run would: from frame 1, 2 frames of 20 steps are left; with
  // another scene (a larger ball) it is refused.
  const std::string checkpoint = (directory / "ran" / "checkpoint_0001.firn").string();
  const Result resumed = runFirn("run " + scene.string() + " --check --resume " + checkpoint);
  ASSERT_EQ(resumed.exitCode, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("particles, 2 frames from frame 1, 40 steps of 0.001 s"), std::string::npos)
      << resumed.output;
  std::string larger = kSmallScene;
  larger.replace(larger.find("\"radius\": 0.15"), 14, "\"radius\": 0.2");
  const fs::path other = writeScene(directory, "larger.json", larger);
  const Result otherScene = runFirn("run " + other.string() + " --check --resume " + checkpoint);
  EXPECT_EQ(otherScene.exitCode, 2) << otherScene.output;
  EXPECT_NE(otherScene.output.find("the checkpoint was written for another scene"), std::string::npos)
      << otherScene.output;

  std::string json = kSmallScene;
  json.replace(json.find("\"preset\": \"stomakhin\""), 21, "\"preset\": \"stomakhin\", \"youngs_modulus\": 1e9");
  const fs::path stiff = writeScene(directory, "stiff.json", json);
  const Result refused = runFirn("run " + stiff.string() + " --check --out " + (directory / "refused").string());
  EXPECT_EQ(refused.exitCode, 2) << refused.output;
  EXPECT_NE(refused.output.find("Set time.dt to at most 2.6"), std::string::npos) << refused.output;
  EXPECT_FALSE(fs::exists(directory / "refused"));
}

// `--transfer-shape` gives the run the transfer shapes it times (here one, so none is timed; the name in any case), and
// its log says so; a name it does not know, or blocks for float sums, is bad input (exit 2).
TEST(Cli, TransferShapeOptionGivesTheRunItsShapes) {
  const fs::path directory = freshDirectory("shapes");
  const fs::path scene = writeScene(directory, "small.json", kSmallScene);
  const Result tiles = runFirn("run " + scene.string() + " --check --transfer-shape Tiles");  // any case
  ASSERT_EQ(tiles.exitCode, 0) << tiles.output;
  EXPECT_NE(tiles.output.find("transfers: P2G by tiles, as the run was asked"), std::string::npos) << tiles.output;
  const Result unknown = runFirn("run " + scene.string() + " --check --transfer-shape warps");
  EXPECT_EQ(unknown.exitCode, 2) << unknown.output;
  EXPECT_NE(unknown.output.find("--transfer-shape: must be one of tiles, blocks, blocks-64"), std::string::npos)
      << unknown.output;
  std::string json = kSmallScene;
  json.replace(json.find("\"grid\""), 6, "\"solver\": { \"atomics\": \"float\" }, \"grid\"");
  const fs::path floatSums = writeScene(directory, "float.json", json);
  const Result blocks = runFirn("run " + floatSums.string() + " --check --transfer-shape blocks");
  EXPECT_EQ(blocks.exitCode, 2) << blocks.output;
  EXPECT_NE(blocks.output.find("transfer shape blocks: blocks sum in fixed point only"), std::string::npos)
      << blocks.output;
}

// `firn run` with no scene runs the built-in one and writes stats.csv (plain CSV: header + frame 0 + N frames, frame N
// at N / frame_rate), one PLY per frame with the particles' state, and run.json, whose transfers are those the run's
// log names; mass never changes. The grid's active blocks follow the snowball: a ball of radius 6 cells and its
// stencils span at most 16 nodes, 5 blocks a side.
TEST(Cli, DefaultSceneWritesStatsAndFrames) {
  const fs::path out = freshDirectory("default");
  const Result result = runFirn("run --frames 2 --out " + out.string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  std::ifstream record(out / "run.json");
  const std::string transfers = nlohmann::json::parse(record)["transfers"]["description"].get<std::string>();
  EXPECT_EQ(transfers.rfind("P2G by ", 0), 0u) << transfers;
  EXPECT_NE(transfers.find("x faster than "), std::string::npos) << transfers;  // fixed point: tiles and blocks timed
  EXPECT_NE(result.output.find("transfers: " + transfers), std::string::npos) << "the log's header says the same\n"
                                                                              << result.output;
  const auto rows = readCsv(out / "stats.csv");
  ASSERT_EQ(rows.size(), 4u);
  const std::vector<std::string> expectedColumns = {"frame", "time_s", "steps", "particles", "mass_kg", "momentum_x",
                                                    "momentum_y", "momentum_z", "kinetic_energy_j", "wall_ms"};
  for (std::size_t i = 0; i < expectedColumns.size(); ++i) EXPECT_EQ(rows[0][i], expectedColumns[i]);
  for (int frame = 0; frame <= 2; ++frame) {
    const auto& row = rows[static_cast<std::size_t>(frame) + 1];
    EXPECT_EQ(std::stoi(row[0]), frame);
    EXPECT_NEAR(std::stod(row[1]), frame / 30.0, 1e-9);  // the default scene's frame rate is 30
    EXPECT_EQ(row[4], rows[1][4]) << "mass changed at frame " << frame;
    const auto blocksColumn = std::find(rows[0].begin(), rows[0].end(), "active_blocks");
    ASSERT_NE(blocksColumn, rows[0].end());
    const std::string& blocks = row[static_cast<std::size_t>(blocksColumn - rows[0].begin())];
    EXPECT_GE(std::stoul(blocks), 1u);
    EXPECT_LE(std::stoul(blocks), 125u);
    const firn::PointCache cache = firn::readPly(out / ("frame_000" + std::to_string(frame) + ".ply"));
    EXPECT_EQ(std::to_string(cache.size()), row[3]);
    for (std::size_t p = 0; p < cache.size(); ++p) {
      ASSERT_TRUE(std::isfinite(cache.positionsM[p].x + cache.velocitiesMPerS[p].y + cache.plasticJ[p]));
    }
  }
  EXPECT_NE(result.output.find("wrote 3 frames"), std::string::npos) << result.output;
}

// Each class of bad input exits with 2 and a message naming the file, the key and the problem.
TEST(Cli, BadInputExitsWithTwoNamingFileAndKey) {
  const fs::path directory = freshDirectory("bad");
  struct Case {
    std::string name;
    std::string json;
    std::string expected;
  };
  const std::string good = kSmallScene;
  auto edit = [&](const std::string& from, const std::string& to) {
    std::string json = good;
    json.replace(json.find(from), from.size(), to);
    return json;
  };
  const std::vector<Case> cases = {
      {"unknown_key.json", edit("\"cell_size\"", "\"cell_sise\""), "grid.cell_sise: unknown key"},
      {"wrong_type.json", edit("\"radius\": 0.15", "\"radius\": \"big\""), "bodies[0].radius"},
      {"out_of_range.json", edit("\"radius\": 0.15", "\"radius\": -0.15"), "bodies[0].radius: must be greater than 0"},
      {"outside.json", edit("[0.6, 0.6, 0.6]", "[1.1, 0.6, 0.6]"), "bodies[0]"},
      {"material.json", edit("\"material\": \"snow\"", "\"material\": \"slush\""), "bodies[0].material"},
      {"syntax.json", edit("\"frames\": 3 }", "\"frames\": 3 "), "JSON syntax error"},
      {"no_hessian.json",
       edit("{ \"snow\": { \"preset\": \"stomakhin\" } }",
            "{ \"snow\": { \"model\": \"water\", \"density\": 1000, \"bulk_modulus\": 1e5, \"gamma\": 7 } }, "
            "\"solver\": { \"integrator\": \"semi_implicit\" }"),
       "solver.integrator: \"semi_implicit\" needs the Hessian of each material's energy, and material \"snow\" uses the "
       "model \"water\""},
  };
  for (const Case& c : cases) {
    const fs::path scene = writeScene(directory, c.name, c.json);
    const Result result = runFirn("run " + scene.string() + " --out " + (directory / "out").string());
    EXPECT_EQ(result.exitCode, 2) << c.name << ": " << result.output;
    EXPECT_NE(result.output.find(scene.string()), std::string::npos) << c.name << ": " << result.output;
    EXPECT_NE(result.output.find(c.expected), std::string::npos) << c.name << ": " << result.output;
  }
  const Result missing = runFirn("run " + (directory / "absent.json").string());
  EXPECT_EQ(missing.exitCode, 2) << missing.output;
  EXPECT_NE(missing.output.find("absent.json"), std::string::npos) << missing.output;
  const Result badFlag = runFirn("run --frames -3");
  EXPECT_EQ(badFlag.exitCode, 2) << badFlag.output;
  EXPECT_NE(badFlag.output.find("--frames"), std::string::npos) << badFlag.output;
}

// A scene too stiff for its step (E = 6e6 Pa: the elastic bound is dt < h / c = 3.4e-4 s, the scene asks for
// 1e-3 s, 2.9 times more: the pre-flight check warns but lets it run) blows up: exit 3, a message saying what to
// change, and the frames written before stay on disk, every value in them finite.
// Far beyond the bound (E = 1e9 Pa: h / c = 2.6e-5 s against dt = 1e-3 s) nothing is run: exit 2, with the
// numbers and the step to use, and no output written.
TEST(Cli, TimeStepFarBeyondTheStableBoundIsBadInput) {
  const fs::path directory = freshDirectory("far_beyond");
  std::string json = kSmallScene;
  json.replace(json.find("\"preset\": \"stomakhin\""), 21, "\"preset\": \"stomakhin\", \"youngs_modulus\": 1e9");
  const fs::path scene = writeScene(directory, "stiff.json", json);
  const Result result = runFirn("run " + scene.string() + " --out " + (directory / "out").string());
  ASSERT_EQ(result.exitCode, 2) << result.output;
  EXPECT_NE(result.output.find("time.dt: 0.001 s is"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("Set time.dt to at most 2.6"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(directory / "out" / "frame_0000.ply"));

  // A semi-implicit step is bounded by the particles' CFL condition alone: the same scene runs, pre-flight gives the
  // elastic bound as information, and the stats say how its solves went: none far from the tolerance (1e-4), or
  // the watchdog would have stopped the run (at 100 times it). The ball falls at 38 times the bound (measured: at
  // most 12 iterations a step, within the default 100; 100 left a residual of 0.019 when the solve started at v*).
  json.replace(json.find("\"materials\""), 0, "\"solver\": { \"integrator\": \"semi_implicit\" }, ");
  const fs::path semiImplicit = writeScene(directory, "stiff_semi_implicit.json", json);
  const Result ran = runFirn("run " + semiImplicit.string() + " --frames 1 --no-ply --out " + (directory / "semi").string());
  ASSERT_EQ(ran.exitCode, 0) << ran.output;
  EXPECT_NE(ran.output.find("semi-implicit, bounded by the CFL conditions"), std::string::npos) << ran.output;
  const auto rows = readCsv(directory / "semi" / "stats.csv");
  ASSERT_EQ(rows.size(), 3u);
  const auto column = std::find(rows[0].begin(), rows[0].end(), "solver_residual");
  ASSERT_NE(column, rows[0].end());
  EXPECT_LE(std::stod(rows[2][std::size_t(column - rows[0].begin())]), 1e-2);

  // Two iterations cannot solve the same ball's impact on the floor at 3 m/s: the first solve ends far above 100
  // times the tolerance (measured: a relative residual of 2.7), and the watchdog stops the run at the frame's end
  // (exit 3) with what to change.
  json.replace(json.find("\"integrator\": \"semi_implicit\""), 29, "\"integrator\": \"semi_implicit\", \"max_iterations\": 2");
  json.replace(json.find("\"center\": [0.6, 0.6, 0.6]"), 25, "\"center\": [0.6, 0.3, 0.6], \"velocity\": [0, -3, 0]");
  const fs::path starved = writeScene(directory, "two_iterations.json", json);
  const Result failed = runFirn("run " + starved.string() + " --no-ply --out " + (directory / "starved").string());
  EXPECT_EQ(failed.exitCode, 3) << failed.output;
  EXPECT_NE(failed.output.find("the semi-implicit solve stopped after 2 iterations"), std::string::npos)
      << failed.output;
  EXPECT_NE(failed.output.find("Raise solver.max_iterations (now 2)"), std::string::npos) << failed.output;
}

TEST(Cli, UnstableSceneExitsWithThreeAndKeepsGoodFrames) {
  const fs::path directory = freshDirectory("unstable");
  std::string json = kSmallScene;
  // 3.8 times the elastic bound, inside pre-flight's refusal at 4 (at 2.9 times, E = 6e6, the ball fell 10 frames
  // without blowing up since its surface particles no longer carry the grid density's extra volume).
  json.replace(json.find("\"preset\": \"stomakhin\""), 21, "\"preset\": \"stomakhin\", \"youngs_modulus\": 1.05e7");
  json.replace(json.find("\"frames\": 3"), 11, "\"frames\": 10");
  const fs::path scene = writeScene(directory, "stiff.json", json);
  const fs::path out = directory / "out";
  const Result result = runFirn("run " + scene.string() + " --out " + out.string());
  ASSERT_EQ(result.exitCode, 3) << result.output;
  EXPECT_NE(result.output.find("warning: time.dt = 0.001 s exceeds the elastic bound"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("unstable"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("Reduce time.dt"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("dt < h / c"), std::string::npos) << result.output;
  ASSERT_TRUE(fs::exists(out / "frame_0000.ply"));
  for (const auto& entry : fs::directory_iterator(out)) {
    if (entry.path().extension() != ".ply") continue;
    const firn::PointCache cache = firn::readPly(entry.path());
    for (std::size_t p = 0; p < cache.size(); ++p) {
      ASSERT_TRUE(std::isfinite(cache.positionsM[p].x) && std::isfinite(cache.positionsM[p].y) &&
                  std::isfinite(cache.positionsM[p].z) && std::isfinite(cache.velocitiesMPerS[p].x))
          << entry.path();
    }
  }
  const auto rows = readCsv(out / "stats.csv");
  EXPECT_LT(rows.size(), 12u);  // stopped before the last frame
  for (const auto& row : rows) {
    for (const auto& cell : row) EXPECT_EQ(cell.find("nan"), std::string::npos);
  }
}

// No usable OpenGL: exit 4 with what was found. An EGL device index that does not exist stands in for a
// machine without a GPU or Mesa.
TEST(Cli, NoUsableOpenGLExitsWithFour) {
  const Result result = runFirn("run --frames 1 --out " + freshDirectory("nogl").string(), "FIRN_EGL_DEVICE=99");
  EXPECT_EQ(result.exitCode, 4) << result.output;
  EXPECT_NE(result.output.find("FIRN_EGL_DEVICE=99"), std::string::npos) << result.output;
}

TEST(Cli, HelpDescribesCommands) {
  const Result top = runFirn("--help");
  EXPECT_EQ(top.exitCode, 0);
  EXPECT_NE(top.output.find("run"), std::string::npos) << top.output;
  const Result run = runFirn("run --help");
  EXPECT_EQ(run.exitCode, 0);
  EXPECT_NE(run.output.find("--frames"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("--out"), std::string::npos) << run.output;
}

// docs/command-line.md, Checkpoints: `--checkpoint-every K` writes checkpoint_NNNN.firn every K frames, and
// `--resume FILE` continues from
// one bit for bit as if never interrupted: the frames after the checkpoint are byte-identical to the
// uninterrupted run's, here with an emitter half-way through its release at the checkpoint. A checkpoint of
// another scene, a truncated one and a file that is not one are bad input (exit 2) naming the file.
TEST(Cli, ResumedRunIsBitIdenticalToAnUninterruptedOne) {
  const fs::path directory = freshDirectory("checkpoint");
  const std::string json = R"({
    "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 50, "frames": 4 },
    "solver": { "transfer": "apic", "kernel": "quadratic" },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [
      { "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.15, "material": "snow", "velocity": [1, 2, 0] },
      { "shape": "box", "min": [0.3, 0.8, 0.3], "max": [0.5, 0.9, 0.5], "material": "snow",
        "start_frame": 1, "duration_frames": 2 } ],
    "colliders": [ { "type": "plane", "point": [0, 0.3, 0], "normal": [0, 1, 0] } ] })";
  const fs::path scene = writeScene(directory, "scene.json", json);
  Result result = runFirn("run " + scene.string() + " --checkpoint-every 2 --out " + (directory / "full").string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const fs::path checkpoint = directory / "full" / "checkpoint_0002.firn";
  ASSERT_TRUE(fs::exists(checkpoint));
  ASSERT_TRUE(fs::exists(directory / "full" / "checkpoint_0004.firn"));

  result = runFirn("run " + scene.string() + " --resume " + checkpoint.string() + " --out " +
                   (directory / "resumed").string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  EXPECT_FALSE(fs::exists(directory / "resumed" / "frame_0001.ply"));
  const auto bytes = [](const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  for (const char* frame : {"frame_0003.ply", "frame_0004.ply"}) {
    const std::string uninterrupted = bytes(directory / "full" / frame);
    ASSERT_FALSE(uninterrupted.empty());
    EXPECT_EQ(bytes(directory / "resumed" / frame), uninterrupted) << frame;
  }

  std::string otherJson = json;
  const std::string radius = "\"radius\": 0.15";
  otherJson.replace(otherJson.find(radius), radius.size(), "\"radius\": 0.14");
  const fs::path other = writeScene(directory, "other.json", otherJson);
  result = runFirn("run " + other.string() + " --resume " + checkpoint.string() + " --out " + (directory / "x").string());
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_NE(result.output.find("checkpoint_0002.firn: the checkpoint was written for another scene"), std::string::npos)
      << result.output;

  const fs::path truncated = directory / "truncated.firn";
  fs::copy_file(checkpoint, truncated);
  fs::resize_file(truncated, fs::file_size(truncated) / 2);
  result = runFirn("run " + scene.string() + " --resume " + truncated.string() + " --out " + (directory / "y").string());
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_NE(result.output.find("truncated.firn: truncated checkpoint"), std::string::npos) << result.output;

  result = runFirn("run " + scene.string() + " --resume " + scene.string() + " --out " + (directory / "z").string());
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_NE(result.output.find("scene.json: not a Firn checkpoint"), std::string::npos) << result.output;
}

// A ball thrown at 20 m/s at the edge of the grid with nothing in the way (adaptive steps, as the splash is fast):
// the domain walls stop it and it rebounds. No particle is lost, wrapped to the other side or left outside the
// interior, and stats.csv counts those pressed against the wall (particles_at_walls, 0 at the start).
TEST(Cli, DomainWallsStopParticlesAndStatsCountThem) {
  const fs::path directory = freshDirectory("walls");
  const fs::path scene = writeScene(directory, "wall.json", R"({
    "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 50, "frames": 5, "adaptive": true },
    "gravity": [0, 0, 0],
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.15, "material": "snow",
                  "velocity": [20, 0, 0] } ] })");
  const Result result = runFirn("run " + scene.string() + " --out " + (directory / "out").string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const auto rows = readCsv(directory / "out" / "stats.csv");
  ASSERT_EQ(rows.size(), 7u);
  const auto atWalls = std::find(rows[0].begin(), rows[0].end(), "particles_at_walls");
  ASSERT_NE(atWalls, rows[0].end());
  const std::size_t column = std::size_t(atWalls - rows[0].begin());
  EXPECT_EQ(rows[1][column], "0");
  // At 20 m/s the ball reaches the wall within the first frame (0.02 s) and rebounds from it.
  unsigned long mostAtWalls = 0;
  for (std::size_t row = 1; row < rows.size(); ++row) mostAtWalls = std::max(mostAtWalls, std::stoul(rows[row][column]));
  EXPECT_GT(mostAtWalls, 50u) << "the ball is pressed against the wall at x = 1.1 m";
  EXPECT_EQ(rows[6][3], rows[1][3]) << "no particle is removed";
  const firn::PointCache last = firn::readPly(directory / "out" / "frame_0005.ply");
  for (const glm::vec3& p : last.positionsM) {
    ASSERT_LE(p.x, 1.1f + 1e-6f) << "a particle beyond the wall (interior ends 2 cells in, at 1.1 m)";
    ASSERT_GE(p.x, 0.1f - 1e-6f);
  }
}

}  // namespace
