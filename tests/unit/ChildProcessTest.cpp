// Untrusted work in a child process (voxelizer/ChildProcess.h): whatever it does — return, throw, abort, exhaust
// its memory, loop — the caller gets the result or the reason in words, within the limits it set.
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "voxelizer/ChildProcess.h"

namespace firn::voxelizer {
namespace {

using Clock = std::chrono::steady_clock;

ChildLimits smallLimits() {
  ChildLimits limits;
  limits.memoryBytes = std::uint64_t{256} << 20;
  limits.cpuS = 10;
  limits.wallS = 10;
  return limits;
}

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

TEST(ChildProcess, ReturnsWhatTheWorkReturns) {
  // Larger than a pipe's buffer (64 KiB), so the parent must read while the child writes.
  std::string payload(3 << 20, '\0');
  for (std::size_t i = 0; i < payload.size(); ++i) payload[i] = static_cast<char>(i * 7919 % 251);
  const ChildOutcome outcome = runInChildProcess([&] { return payload; }, smallLimits());
  ASSERT_TRUE(outcome.succeeded) << outcome.failure;
  EXPECT_EQ(outcome.result, payload);
}

TEST(ChildProcess, AnAbortIsReportedWithWhatTheChildLastSaid) {
  const ChildOutcome outcome = runInChildProcess(
      [] {
        std::fprintf(stderr, "loading\nai_assert failure in Triangulate.cpp(238): numOut != nFaces\n");
        std::abort();
        return std::string();
      },
      smallLimits());
  EXPECT_FALSE(outcome.succeeded);
  EXPECT_EQ(outcome.failure, "was killed by signal " + std::to_string(SIGABRT) + " (Aborted)");
  EXPECT_EQ(outcome.lastWords, "ai_assert failure in Triangulate.cpp(238): numOut != nFaces");
  EXPECT_TRUE(outcome.result.empty());
}

TEST(ChildProcess, AnExceptionIsReportedWithItsMessage) {
  const ChildOutcome outcome = runInChildProcess([]() -> std::string { throw std::runtime_error("bad header"); },
                                                 smallLimits());
  EXPECT_FALSE(outcome.succeeded);
  EXPECT_EQ(outcome.failure, "stopped with an error");
  EXPECT_EQ(outcome.lastWords, "bad header");
}

TEST(ChildProcess, ExhaustingMemoryStopsAtTheLimit) {
  // Allocates and touches 16 MiB at a time without end: the limit of 256 MiB must stop it, as it would a parser
  // that believes a count of billions.
  const ChildOutcome outcome = runInChildProcess(
      [] {
        std::vector<std::vector<char>> hoard;
        for (;;) hoard.emplace_back(std::size_t{16} << 20, 'x');
        return std::string();
      },
      smallLimits());
  EXPECT_FALSE(outcome.succeeded);
  EXPECT_EQ(outcome.failure, "needed more than its memory limit of 256 MiB");
}

TEST(ChildProcess, LoopingForeverIsStoppedAtTheWallClockLimit) {
  ChildLimits limits = smallLimits();
  limits.wallS = 1;
  const auto start = Clock::now();
  const ChildOutcome outcome = runInChildProcess(
      [] {
        for (volatile unsigned spin = 0;; spin = spin + 1) {
        }
        return std::string();
      },
      limits);
  const double elapsedS = secondsSince(start);
  EXPECT_FALSE(outcome.succeeded);
  EXPECT_EQ(outcome.failure, "ran for more than 1 s and was stopped");
  // Killed at the limit; the rest is the time to reap it, milliseconds, with seconds of room for a loaded machine.
  EXPECT_GE(elapsedS, 1.0);
  EXPECT_LT(elapsedS, 5.0);
}

TEST(ChildProcess, LoopingForeverIsStoppedAtTheCpuLimit) {
  ChildLimits limits = smallLimits();
  limits.cpuS = 1;
  const ChildOutcome outcome = runInChildProcess(
      [] {
        for (volatile unsigned spin = 0;; spin = spin + 1) {
        }
        return std::string();
      },
      limits);
  EXPECT_FALSE(outcome.succeeded);
  EXPECT_EQ(outcome.failure, "used more than its 1 s of CPU time");
}

}  // namespace
}  // namespace firn::voxelizer
