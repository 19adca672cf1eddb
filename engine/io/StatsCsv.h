#pragma once
// stats.csv: plain CSV, a header and one row per frame (frame 0 included), flushed as it is written so a stopped run
// keeps its rows. The rows are plain numbers; the run measures them (run/HeadlessRun.cpp). What describes the run
// rather than a frame is in run.json beside it (run/RunRecord.h).
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
  double kineticEnergyJ = 0;  // the particles' (APIC: with its affine part): the energy audit's
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
  // The energy audit (docs/numerics.md, The energy audit), J: what the particles and the rigid bodies hold, and since
  // the start, the work of the moving colliders, the energy that arrived with emitted particles, what the domain
  // walls removed, what snow's hardening gave, what the bodies' explicit coupling added, the explicit step's term, and
  // the residual: what plasticity, friction and the transfers dissipated.
  double potentialEnergyJ = 0;
  double elasticEnergyJ = 0;
  double bodiesKineticEnergyJ = 0;
  double bodiesPotentialEnergyJ = 0;
  double colliderWorkJ = 0;
  double arrivedEnergyJ = 0;
  double wallsRemovedJ = 0;
  double hardeningEnergyJ = 0;
  double couplingEnergyJ = 0;
  double stepEnergyJ = 0;     // explicit steps: the modified energy the step keeps less the energy shown
  double dissipatedEnergyJ = 0;
  // The energy made from nothing since the audit whose dissipation was greatest, and what the watchdog allows it.
  double energyCreatedJ = 0;
  double energyToleranceJ = 0;
};

class StatsCsvWriter {
 public:
  // Starts the file afresh with its header. Throws InputError naming the file if it cannot be written.
  explicit StatsCsvWriter(const std::filesystem::path& path);
  // Continues the file of a run resumed at `firstFrame`: keeps its rows of the frames before it and drops the rest,
  // which the resumed run writes again. The kept rows replace the file atomically (io/AtomicFile.h), so a run stopped
  // here leaves the old file or the new one. A missing file starts afresh. Throws InputError naming the file if it
  // cannot be read or written, has another header than this build's or holds a row without a frame number.
  StatsCsvWriter(const std::filesystem::path& path, int firstFrame);
  void write(const FrameStats& stats);

  static const char* header();

 private:
  FrameCsv file_;
};

}  // namespace firn
