// `firn run` fed hostile files and folders, as a user runs it (docs/command-line.md; docs/scene-format.md, Sizes
// and limits): an output folder another run holds, a claim left by a killed run, a resume into the run's own
// folder, scene files that are deeply nested, endless or blocking, and checkpoints that are damaged or hold NaN.
// Each is bad input (exit 2) with a message naming the file or folder and the problem, or, for the killed run's
// claim and the resume, a run that succeeds.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "Cli.h"
#include "io/Checkpoint.h"
#include "io/OutputFolder.h"

namespace {

namespace fs = std::filesystem;
using firn::test::fileBytes;
using firn::test::freshDirectory;
using firn::test::readCsv;
using firn::test::Result;
using firn::test::runFirn;
using firn::test::writeScene;
using Clock = std::chrono::steady_clock;

const char* const kSmallScene = R"({
  "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
  "time": { "dt": 1e-3, "frame_rate": 50, "frames": 4 },
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "sphere", "center": [0.6, 0.6, 0.6], "radius": 0.1, "material": "snow", "velocity": [1, 0, 0] } ],
  "colliders": [ { "type": "plane", "point": [0, 0.3, 0], "normal": [0, 1, 0] } ] })";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// A `firn run` of a million frames in the background, its output discarded; SIGKILLed when the test ends.
class BackgroundRun {
 public:
  BackgroundRun(const fs::path& scene, const fs::path& out) {
    pid_ = fork();
    if (pid_ == 0) {
      const int null = ::open("/dev/null", O_WRONLY);
      dup2(null, STDOUT_FILENO);
      dup2(null, STDERR_FILENO);
      execl(FIRN_EXECUTABLE, FIRN_EXECUTABLE, "run", scene.c_str(), "--frames", "1000000", "--no-ply", "--out",
            out.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
  }
  BackgroundRun(const BackgroundRun&) = delete;
  BackgroundRun& operator=(const BackgroundRun&) = delete;
  ~BackgroundRun() { kill(); }

  pid_t pid() const { return pid_; }
  // Waits up to 60 s (a loaded machine) for the run to claim `out`: its process id in the lock file.
  bool waitForClaim(const fs::path& out) const {
    const fs::path lockFile = out / firn::OutputFolderClaim::kLockFileName;
    for (const auto start = Clock::now(); secondsSince(start) < 60;) {
      if (fileBytes(lockFile) == std::to_string(pid_) + "\n") return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }
  // SIGKILL, as a user's `kill -9` or the OOM killer: the process gets no chance to release anything.
  void kill() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

// ----- Output folders -----

// The issue's case: two runs into one --out both exited 0 with their rows glued together. The second is refused
// while the first holds the folder, naming the folder and the first run's process, and writes nothing there.
TEST(HostileInputCli, SecondRunIntoAHeldOutputFolderIsRefused) {
  const fs::path directory = freshDirectory("held");
  const fs::path scene = writeScene(directory, "scene.json", kSmallScene);
  const fs::path out = directory / "out";
  BackgroundRun first(scene, out);
  ASSERT_TRUE(first.waitForClaim(out));
  const Result second = runFirn("run " + scene.string() + " --frames 1 --out " + out.string());
  EXPECT_EQ(second.exitCode, 2) << second.output;
  EXPECT_TRUE(contains(second.output, "firn: error: " + out.string() + ": output folder in use by another firn (process " +
                                          std::to_string(first.pid()) + "); wait for it to end or give another --out"))
      << second.output;
  EXPECT_FALSE(contains(second.output, "wrote")) << second.output;
}

// A run killed with SIGKILL leaves its lock file (naming it) behind; the kernel has dropped its lock, so the next
// run takes the folder over, writes a stats.csv of its own rows alone (the header and frames 0 and 1) and, ending
// normally, removes the lock file.
TEST(HostileInputCli, ClaimOfAKilledRunIsTakenOver) {
  const fs::path directory = freshDirectory("stale");
  const fs::path scene = writeScene(directory, "scene.json", kSmallScene);
  const fs::path out = directory / "out";
  BackgroundRun killed(scene, out);
  ASSERT_TRUE(killed.waitForClaim(out));
  const std::string killedPid = std::to_string(killed.pid()) + "\n";
  killed.kill();
  const fs::path lockFile = out / firn::OutputFolderClaim::kLockFileName;
  ASSERT_EQ(fileBytes(lockFile), killedPid) << "the killed run's claim is left behind";
  const Result next = runFirn("run " + scene.string() + " --frames 1 --no-ply --out " + out.string());
  ASSERT_EQ(next.exitCode, 0) << next.output;
  EXPECT_FALSE(fs::exists(lockFile));
  const auto rows = readCsv(out / "stats.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1][0], "0");
  EXPECT_EQ(rows[2][0], "1");
}

// ----- Resuming -----

// Resumed into its own folder from the checkpoint of frame 2, a run keeps stats.csv's rows of frames 0 and 1 byte
// for byte (their wall_ms too, which no second run would repeat) and writes frames 2 to 4 again: one row per
// frame, each as the uninterrupted run wrote it (resume is bit for bit: docs/numerics.md, Bitwise determinism) but
// for wall_ms and, in the resumed run's first row, what its frame's steps measured (steps is 0 and active_blocks
// the initial grid's, as in any run's first row: the resumed run took no step to frame 2).
TEST(HostileInputCli, ResumeInTheRunsOwnFolderKeepsTheEarlierRows) {
  const fs::path directory = freshDirectory("resume_rows");
  const fs::path scene = writeScene(directory, "scene.json", kSmallScene);
  const fs::path out = directory / "out";
  Result result = runFirn("run " + scene.string() + " --no-ply --checkpoint-every 2 --out " + out.string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const auto uninterrupted = readCsv(out / "stats.csv");
  ASSERT_EQ(uninterrupted.size(), 6u);
  // The lines after the comment, which names the transfers' shape and its timing: the resumed run's own.
  const auto linesAfterComment = [](const fs::path& path) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) {
      if (!(lines.empty() && line.rfind("# transfers: ", 0) == 0)) lines.push_back(line);
    }
    return lines;
  };
  const std::vector<std::string> originalLines = linesAfterComment(out / "stats.csv");

  result = runFirn("run " + scene.string() + " --no-ply --resume " + (out / "checkpoint_0002.firn").string() +
                   " --out " + out.string());
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const std::vector<std::string> resumedLines = linesAfterComment(out / "stats.csv");
  ASSERT_EQ(resumedLines.size(), 6u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(resumedLines[i], originalLines[i]) << "line " << i + 1;
  const auto resumed = readCsv(out / "stats.csv");
  const std::vector<std::string>& header = resumed[0];
  for (std::size_t row = 3; row < 6; ++row) {
    for (std::size_t column = 0; column < header.size(); ++column) {
      const bool measuresSteps = header[column] == "steps" || header[column] == "active_blocks" ||
                                 header[column] == "solver_iterations" || header[column] == "solver_residual";
      if (header[column] == "wall_ms" || (row == 3 && measuresSteps)) continue;
      EXPECT_EQ(resumed[row][column], uninterrupted[row][column]) << "frame " << row - 1 << ", " << header[column];
    }
  }
  EXPECT_EQ(resumed[3][2], "0");
}

// ----- Scene files -----

// 150 KB of '[' made the parser overflow the stack (SIGSEGV). It is refused before parsing, naming the file and
// the position past the 64 levels docs/scene-format.md allows, in well under a second (5 s: the process's start on
// a loaded machine; the scan takes microseconds).
TEST(HostileInputCli, DeeplyNestedSceneIsRefusedFast) {
  const fs::path directory = freshDirectory("nested");
  const fs::path scene = writeScene(directory, "deep.json", std::string(150 * 1024, '['));
  const auto start = Clock::now();
  const Result result = runFirn("run " + scene.string() + " --out " + (directory / "out").string());
  EXPECT_LT(secondsSince(start), 5.0);
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "firn: error: " + scene.string() +
                                          ": line 1, column 65: arrays and objects nested more than 64 levels deep"))
      << result.output;
}

// A named pipe with no writer blocked `firn run` for ever, and /dev/zero read until memory ran out (exit 1). Both
// are refused from their stat, exit 2 naming the file and what it is, within a second of starting the process.
TEST(HostileInputCli, PipeAndDeviceScenesAreRefusedWithinASecond) {
  const fs::path directory = freshDirectory("pipe");
  const fs::path fifo = directory / "scene.json";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
  struct Case {
    fs::path scene;
    std::string kind;
  };
  for (const Case& input : {Case{fifo, "a named pipe (FIFO)"}, Case{"/dev/zero", "a character device"}}) {
    const auto start = Clock::now();
    const Result result = runFirn("run " + input.scene.string() + " --out " + (directory / "out").string(),
                                  "timeout -s KILL 30");
    const double wallS = secondsSince(start);
    EXPECT_EQ(result.exitCode, 2) << result.output;
    EXPECT_TRUE(contains(result.output, "firn: error: " + input.scene.string() + ": is not a regular file but " +
                                            input.kind + "; a scene file is read from a regular file only"))
        << result.output;
    EXPECT_LT(wallS, 1.0) << input.scene;
  }
}

// ----- Checkpoints -----

class DamagedCheckpoint : public testing::Test {
 protected:
  void SetUp() override {
    directory_ = freshDirectory("damaged_checkpoint");
    scene_ = writeScene(directory_, "scene.json", kSmallScene);
    const Result result =
        runFirn("run " + scene_.string() + " --no-ply --frames 2 --checkpoint-every 2 --out " + (directory_ / "full").string());
    ASSERT_EQ(result.exitCode, 0) << result.output;
    checkpoint_ = directory_ / "full" / "checkpoint_0002.firn";
  }
  Result resume(const fs::path& checkpoint) {
    return runFirn("run " + scene_.string() + " --no-ply --resume " + checkpoint.string() + " --out " +
                   (directory_ / "resumed").string());
  }

  fs::path directory_, scene_, checkpoint_;
};

// One flipped byte in the particles' data loaded silently before checksums. Now the buffer's CRC-32 catches it:
// exit 2 naming the file and the buffer, before a context is made.
TEST_F(DamagedCheckpoint, OneFlippedByteIsRefusedNamingTheFileAndBuffer) {
  const fs::path damaged = directory_ / "flipped.firn";
  std::string bytes = fileBytes(checkpoint_);
  bytes[bytes.size() / 2] ^= 0x04;  // inside the particle buffers, which are nearly all of the file
  std::ofstream(damaged, std::ios::binary) << bytes;
  const Result result = resume(damaged);
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "firn: error: " + damaged.string() + ": corrupt checkpoint: the CRC-32 of buffer "))
      << result.output;
  EXPECT_FALSE(fs::exists(directory_ / "resumed" / "stats.csv"));
}

// A checkpoint whose particles hold NaN, with correct checksums (as a run that checkpointed a broken state would
// write it), ended in exit 1 when the first stats row was not finite. It is bad input naming the file, the buffer
// and the particle.
TEST_F(DamagedCheckpoint, NonFiniteParticleDataIsRefusedNamingTheFileAndBuffer) {
  firn::Checkpoint checkpoint = firn::readCheckpoint(checkpoint_);
  ASSERT_GT(checkpoint.particleCount, 7u);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(checkpoint.buffers.at(1).data() + 7 * 16 + 4, &nan, sizeof nan);  // particle 7's velocity y
  const fs::path damaged = directory_ / "nan.firn";
  firn::writeCheckpoint(damaged, checkpoint);
  const Result result = resume(damaged);
  EXPECT_EQ(result.exitCode, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "firn: error: " + damaged.string() +
                                          ": buffer 2 of the checkpoint (particles: velocity, volume) holds a value "
                                          "that is not finite (NaN) for particle 7"))
      << result.output;
}

}  // namespace
