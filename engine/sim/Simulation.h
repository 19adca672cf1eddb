#pragma once
// The MPM snow simulation on the GPU: owns the particle, grid, material, collider and bookkeeping buffers and
// the compute programs built for this scene, and runs the step as a flat list of passes in paper order.
#include <chrono>
#include <filesystem>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gl/Buffer.h"
#include "gl/Context.h"
#include "gl/Program.h"
#include "gl/Query.h"
#include "io/Checkpoint.h"
#include "scene/Scene.h"
#include "sim/FixedPoint.h"
#include "sim/GpuLayout.h"

namespace firn {

// Particle state read back from the GPU.
struct ParticleSnapshot {
  std::vector<glm::vec4> positionMass;    // x (m), mass (kg)
  std::vector<glm::vec4> velocityVolume;  // v (m/s), V0 (m³)
  std::vector<float> plasticJ;            // J_P
  std::size_t size() const { return positionMass.size(); }
};

// Sums over the grid after P2G, from the exact integer sums (fixed point) or the float sums.
struct GridTotals {
  double massKg = 0;
  glm::dvec3 momentumKgMPerS{0.0};
  std::uint64_t activeNodes = 0;  // nodes in the active box
};

// One node of the active box after P2G (readGridAfterTransfer), converted from the fixed-point or float storage.
struct GridNodeSums {
  glm::ivec3 node{0};                  // node index per axis
  double massKg = 0;                   // Σ_p w_ip m_p
  glm::dvec3 momentumKgMPerS{0.0};     // Σ_p w_ip m_p v_p (APIC: plus the affine part and the elastic impulse)
};

// Which material models the programs are built for: the scene's (the default, design.md: "a scene pays only for
// what it uses"), or every model with F for all, as one general build would: for measuring what that costs.
enum class MaterialPrograms { SceneModels, EveryModel };

class Simulation {
 public:
  // Builds the programs and buffers the scene needs and computes the initial particle volumes. Particles with
  // a release time (emitters) join at the first step that starts at or after it. The particle buffers hold
  // `particleCapacity` particles (at least all the seeds), so that addParticles can add more while running.
  // Throws InputError when the scene asks for more than the driver offers (float atomics, buffer sizes).
  Simulation(const Scene& scene, const std::vector<ParticleSeed>& seeds, const gl::ContextInfo& gl,
             std::size_t particleCapacity = 0, MaterialPrograms programs = MaterialPrograms::SceneModels);

  // Adds particles at the start of the next step, undeformed, with V0 = m / ρ of their material (the grid
  // density that gave the first particles their volumes is not theirs to share). Their mass must not exceed
  // the fixed-point reference mass. Throws std::length_error if they do not fit the capacity.
  void addParticles(const std::vector<ParticleSeed>& particles);

  // One step of `dtS` seconds (no larger than the scene's dt): prepare → clear → P2G → grid update → G2P.
  void step(double dtS);
  // Steps to `timeS`, landing on it exactly; returns the count. Fixed dt: equal steps no larger than the scene's
  // dt. Adaptive (time.adaptive): each step as large as the CFL and elastic bounds allow (times time.cfl).
  int advanceTo(double timeS);

  // A copy of the whole state (particles, emitter progress, time, watchdog) on the GPU, for redoing a stretch
  // of simulation that went wrong (adaptive stepping retries a failed frame with smaller steps).
  void saveState();
  void restoreState();
  // Adaptive stepping: scales the step it would take (1 normally; a retry halves it).
  void setAdaptiveStepScale(double scale) { adaptiveStepScale_ = scale; }

  // The complete state as a checkpoint of `frame` (io/Checkpoint.h), and back: resume() must be called on a
  // Simulation just built from the same scene; it throws InputError naming `source` if the checkpoint belongs
  // to another scene.
  Checkpoint checkpoint(int frame) const;
  void resume(const Checkpoint& checkpoint, const std::filesystem::path& source);

  // Throws SimulationError (exit 3) saying when, where and what to change if the GPU watchdog saw a
  // fixed-point overflow, a non-finite value or a CFL violation since the start.
  void checkWatchdog() const;

  ParticleSnapshot snapshot() const;
  // Binds the particle buffers to their storage binding points (gpu::PositionMass, VelocityVolume,
  // PlasticState, KirchhoffStress), for passes outside the step that read particles in place: the renderer
  // draws straight from them. The first particleCount() entries are live.
  void bindParticleBuffers() const;
  // readGridAfterTransfer's nodes, summed (a diagnostic: conservation tests).
  GridTotals transferToGrid();
  // The active node box of the last step (its node count is what the grid passes cost).
  gpu::ActiveRegionData activeRegion() const;

  double timeS() const { return timeS_; }
  std::uint64_t stepCount() const { return steps_; }
  std::size_t particleCount() const { return particleCount_; }
  std::size_t particleCapacity() const { return particleCapacity_; }
  // Emitters' particles still to come.
  std::size_t pendingParticleCount() const { return pendingParticles_.size() - nextPending_; }
  const FixedPointScale& fixedPoint() const { return fixedPoint_; }
  const Scene& scene() const { return scene_; }

  // GPU time per pass from GL_TIME_ELAPSED queries, summed over the steps since timing was switched on.
  // Timing waits for each pass, so it is for benchmarks, not for production runs.
  void setPassTiming(bool enabled);
  struct PassTime {
    std::string pass;
    double totalMs = 0;      // GPU time from the timer query
    double totalWallMs = 0;  // host time from before the dispatch until glFinish returns
    std::uint64_t dispatches = 0;
  };
  const std::vector<PassTime>& passTimes() const { return passTimes_; }

  // Test hook: overwrite one particle's velocity, e.g. with a NaN, to exercise the watchdog.
  void setParticleVelocity(std::size_t particle, const glm::vec3& velocityMPerS);

  // Runs prepare → clear → P2G on the current state and returns every node of the active box with its sums in kg
  // and kg m/s (a diagnostic: the atomics' error against a double-precision CPU sum, in
  // `firn bench`). On a state just built (no stress yet, C = 0) the momentum is Σ w m v for every transfer.
  std::vector<GridNodeSums> readGridAfterTransfer();

 private:
  void buildPrograms();
  bool needsDeformationGradient() const;
  void allocateParticles();
  // The buffers whose contents carry over from one step to the next (the grid is rebuilt every step), as
  // pointers to const or mutable buffers after `self`.
  template <class Self>
  static auto stateBuffers(Self& self) {
    std::vector<decltype(&self.positionMass_)> buffers;
    for (auto* buffer : {&self.positionMass_, &self.velocityVolume_, &self.elasticDeformation_, &self.kirchhoffStress_,
                         &self.affine_, &self.plasticState_, &self.activeRegion_, &self.watchdog_}) {
      if (*buffer) buffers.push_back(buffer);
    }
    return buffers;
  }
  double adaptiveDtS() const;
  void readFastestSpeed();
  void releaseDueParticles();
  void writeParticles(std::size_t first, const std::vector<ParticleSeed>& particles, bool volumeFromDensity);
  void uploadMaterialsAndColliders();
  void seedActiveRegion(const std::vector<glm::vec3>& positions);
  void noteAddedParticles(const std::vector<glm::vec3>& positions);
  void accumulateCells(const std::vector<glm::vec3>& positions, glm::ivec4& cellMin, glm::ivec4& cellMax) const;
  void writeStepUniforms(double dtS);
  void bindAll() const;
  void runOnce(const gl::Program& program);
  void runOverGrid(const gl::Program& program);
  void runOverParticles(const gl::Program& program);
  void beginPass();
  void endPass(const gl::Program& program);
  void scatterToGrid();
  void scatterInBlocks();
  bool binsParticles() const { return scene_.solver.atomics == Atomics::None; }
  std::string describeNode(std::int32_t node) const;
  std::string describeParticle(std::int32_t particle) const;

  Scene scene_;
  MaterialPrograms materialPrograms_;
  FixedPointScale fixedPoint_;
  std::size_t particleCount_ = 0;
  std::size_t particleCapacity_ = 0;
  glm::ivec3 gridNodes_{0};
  int maxWorkGroupsX_ = 65535;
  std::vector<int> particleBody_;      // body of each particle (−1: added while running), for messages
  std::vector<int> particleMaterial_;  // material of each particle, for messages
  std::vector<std::uint32_t> bodyMaterialEntry_;  // each body's entry in the GPU material table
  std::vector<ParticleSeed> pendingParticles_;    // emitters' particles not yet released, by release time
  std::size_t nextPending_ = 0;

  double timeS_ = 0;
  std::uint64_t steps_ = 0;
  // Cells of the particles added since the last prepare_grid (it resets its GPU copy; scatterToGrid this one).
  glm::ivec4 addedCellMin_{0}, addedCellMax_{0};
  double fastestSpeedMPerS_ = 0;  // adaptive dt: the largest |v| + c, from the seeds, then from each step's G2P
  double adaptiveStepScale_ = 1;

  // saveState's copy: the buffers whose contents carry over from step to step, and the counters.
  struct SavedState {
    std::vector<std::pair<gl::Buffer*, gl::Buffer>> buffers;  // (live buffer, its copy)
    double timeS = 0;
    std::uint64_t steps = 0;
    std::size_t particleCount = 0;
    std::size_t nextPending = 0;
    double fastestSpeedMPerS = 0;
  };
  SavedState saved_;
  std::uint64_t sceneFingerprint_ = 0;

  gl::Program prepareGrid_;
  gl::Program clearGrid_;
  gl::Program particleToGrid_;
  gl::Program updateGrid_;
  gl::Program gridToParticle_;
  gl::Program computeVolumes_;
  // P2G without atomics (solver.atomics "none"): binning and the coloured scatter.
  gl::Program binCount_;
  gl::Program binScan_;
  gl::Program binPlace_;
  gl::Program particleToGridBlocks_;

  gl::Buffer positionMass_;
  gl::Buffer velocityVolume_;
  gl::Buffer elasticDeformation_;  // F (F_E for snow and sand); water-only scenes carry J alone
  gl::Buffer kirchhoffStress_;
  gl::Buffer affine_;  // APIC only
  gl::Buffer plasticState_;
  gl::Buffer gridMomentumMass_;
  gl::Buffer gridImpulse_;  // PIC/FLIP only
  gl::Buffer materials_;
  gl::Buffer colliders_;
  gl::Buffer activeRegion_;
  gl::Buffer watchdog_;
  gl::Buffer stepUniforms_;
  gl::Buffer blocks_;          // BlockTable (solver.atomics "none")
  gl::Buffer particleSlots_;   // "none": each particle's place in its bin
  gl::Buffer blockParticles_;  // "none": particle indices, bin after bin
  gl::Buffer blockOrder_;      // "none": each colour's non-empty blocks

  bool timingPasses_ = false;
  gl::TimerQuery passTimer_;
  std::chrono::steady_clock::time_point passWallStart_;
  std::vector<PassTime> passTimes_;
};

}  // namespace firn
