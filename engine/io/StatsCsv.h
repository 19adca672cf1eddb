#pragma once
// stats.csv: a comment line (how the run moves its particles' sums to the grid: the shape it timed fastest, and by
// how much), then one row per frame (frame 0 included), flushed as it is written so a stopped run keeps its rows.
// The rows are plain numbers; the run measures them (run/HeadlessRun.cpp).
#include <cstdint>
#include <filesystem>
#include <string>

#include <glm/vec3.hpp>

#include "io/FrameCsv.h"

namespace firn {

struct FrameStats {
  int frame = 0;
  double timeS = 0;
  std::uint64_t steps = 0;  // steps taken since the previous frame
  std::uint64_t particles = 0;
  double massKg = 0;
  glm::dvec3 momentumKgMPerS{0.0};
  double kineticEnergyJ = 0;
  double wallMs = 0;        // wall-clock time since the previous frame
  double meanPlasticJ = 1;  // mean J_P: below 1 the snow has compacted
  glm::dvec3 centerOfMassM{0.0};
  // Particles held at the domain's walls (within a cell of them). Firn never removes or wraps a particle
  // that reaches the edge of the grid: the walls stop it, and this count says how many are pressed there.
  std::uint64_t particlesAtWalls = 0;
  // Blocks of the grid (4³ nodes each) the frame's last step used: the grid's cost and memory follow them.
  std::uint64_t activeBlocks = 0;
  // Semi-implicit steps (solver.integrator): the most conjugate residual iterations any of the frame's steps took,
  // and the largest relative residual one ended with; 0 for explicit steps.
  int solverIterations = 0;
  double solverResidual = 0;
};

class StatsCsvWriter {
 public:
  // Starts the file afresh: `comment` (one line, without its "# "; none if empty), then the header. Throws
  // InputError naming the file if it cannot be written.
  explicit StatsCsvWriter(const std::filesystem::path& path, const std::string& comment = "");
  // Continues the file of a run resumed at `firstFrame`: keeps its rows of the frames before it and drops the rest,
  // which the resumed run writes again; `comment` replaces the earlier run's. The kept rows replace the file
  // atomically (io/AtomicFile.h), so a run stopped here leaves the old file or the new one. A missing file starts
  // afresh. Throws InputError naming the file if it cannot be read or written, has another header than this
  // build's or holds a row without a frame number.
  StatsCsvWriter(const std::filesystem::path& path, int firstFrame, const std::string& comment = "");
  void write(const FrameStats& stats);

  static const char* header();

 private:
  FrameCsv file_;
};

}  // namespace firn
