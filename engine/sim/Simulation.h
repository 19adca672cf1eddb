#pragma once
// The MPM simulation on the GPU, as one object: a façade over the parts that each do one job —
//   GpuState        the buffers in named parts (particles, block grid, solver), save and restore (sim/GpuState.h)
//   StepPipeline    the compute passes of one step, in paper order (sim/StepPipeline.h), the rigid bodies' among
//                   them (sim/RigidBodies.h)
//   SteppingPolicy  fixed or adaptive steps, and retries (sim/SteppingPolicy.h)
//   Diagnostics     what the watchdog saw, in words (sim/Diagnostics.h)
//   EnergyAudit     the run's energy account, and whether a frame made energy from nothing (sim/EnergyAudit.h)
//   SharedParticles with a share of the domain over several processes, its particles' bookkeeping
//                   (sim/SharedParticles.h)
// and the scene's conversion into buffers (sim/SceneUpload.h, gpu/Materials.h).
#include <array>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "gl/Context.h"
#include "gl/PassTimer.h"
#include "gpu/GpuLayout.h"
#include "gpu/ParticleView.h"
#include "io/Checkpoint.h"
#include "scene/Scene.h"
#include "scene/SceneObjects.h"
#include "sim/Diagnostics.h"
#include "sim/DomainShare.h"
#include "sim/EnergyAudit.h"
#include "sim/FixedPoint.h"
#include "sim/GpuState.h"
#include "sim/SceneUpload.h"
#include "sim/SharedParticles.h"
#include "sim/StepPipeline.h"
#include "sim/SteppingPolicy.h"

namespace firn {

// Sums over the grid after P2G, from the exact integer sums (fixed point) or the float sums.
struct GridTotals {
  double massKg = 0;
  glm::dvec3 momentumKgMPerS{0.0};
  std::uint64_t activeNodes = 0;  // nodes of the active blocks
};

// One node of the active blocks after P2G (readGridAfterTransfer), converted from the fixed-point or float storage.
struct GridNodeSums {
  glm::ivec3 node{0};                  // node index per axis
  double massKg = 0;                   // Σ_p w_ip m_p
  glm::dvec3 momentumKgMPerS{0.0};     // Σ_p w_ip m_p v_p (APIC: plus the affine part and the elastic impulse)
};

// The semi-implicit solves of a stretch of steps (Simulation::takeSolverSummary); explicit steps solve nothing.
struct SolverSummary {
  std::uint64_t solves = 0;
  std::uint64_t iterations = 0;  // in all
  int mostIterations = 0;        // of any one step
  double largestResidual = 0;    // the largest relative residual a step ended with (NaN if one was not finite)
};

// How a Simulation is built beyond its scene: its buffers' room, its programs, the transfer shapes it may take and
// the part of the domain it simulates.
struct SimulationOptions {
  // The particle buffers hold this many particles (at least all the seeds), so that addParticles can add more while
  // running.
  std::size_t particleCapacity = 0;
  MaterialPrograms programs = MaterialPrograms::SceneModels;
  // The grid's pool starts with this many blocks of 4³ nodes, or (0) four times the blocks the seeds reach and at
  // least 256; it grows when the particles outgrow it (advanceTo, advanceFrame, addParticles).
  std::size_t blockCapacity = 0;
  // The transfer shapes the run times before it keeps the fastest (transferShapeCandidates): empty, every shape the
  // scene can take; else a name ("tiles", "blocks", "blocks-128", …). They write the same bytes.
  std::string transferShapes;
  // With a share (sim/DomainShare.h) the simulation is of the share's part of the domain: the seeds are still all
  // the scene's (every share takes the same decisions from them), but only the share's own are written, and the
  // share completes the grid's sums and moves particles between shares at every step.
  DomainShare* share = nullptr;
};

class Simulation {
 public:
  using PassTime = gl::PassTimer::PassTime;

  // Builds the programs and buffers the scene needs and computes the initial particle volumes. Particles with
  // a release time (emitters) join at the first step that starts at or after it. Throws InputError when the scene
  // asks for more than the driver offers (float atomics, buffer sizes) or for a transfer shape it cannot take.
  Simulation(const Scene& scene, const std::vector<ParticleSeed>& seeds, const gl::ContextInfo& gl,
             const SimulationOptions& options = {});
  // The same with the scene's distance fields baked already (bakeColliderFields), as a session keeps them from its
  // pre-flight through every restart.
  Simulation(const Scene& scene, const std::vector<ParticleSeed>& seeds, const gl::ContextInfo& gl,
             ColliderFields colliderFields, const SimulationOptions& options);

  // Adds particles at the start of the next step, undeformed, with V0 = m / ρ of their material (the grid
  // density that gave the first particles their volumes is not theirs to share), and grows the grid's pool if
  // they might not fit it. Their mass must not exceed the fixed-point reference mass. Throws std::length_error if
  // they do not fit the capacity.
  void addParticles(const std::vector<ParticleSeed>& particles);

  // One step of `dtS` seconds (no larger than the scene's dt): prepare → clear → P2G → grid update → G2P.
  void step(double dtS);
  // Steps to `timeS`, landing on it exactly; returns the count (SteppingPolicy::advance).
  int advanceTo(double timeS);
  // advanceTo, then the watchdog (checkWatchdog), once a frame. With adaptive steps, a frame the watchdog rejects
  // is redone from the state at its start with steps half as large, up to three times, saying so on `log`.
  int advanceFrame(double frameTimeS, std::ostream& log);

  // A copy of the whole state (particles, emitter progress, time, watchdog) on the GPU, for redoing a stretch
  // of simulation that went wrong.
  void saveState();
  void restoreState();

  // The complete state as a checkpoint of `frame` (io/Checkpoint.h), and back: resume() must be called on a
  // Simulation just built from the same scene; it throws InputError naming `source` if the checkpoint belongs
  // to another scene. With a share, every share calls both: checkpoint() gathers the whole state, as one process's,
  // on the share that writes the output; resume() takes a checkpoint of any number of shares and keeps its own.
  Checkpoint checkpoint(int frame) const;
  void resume(const Checkpoint& checkpoint, const std::filesystem::path& source);

  // Throws SimulationError (exit 3) saying when, where and what to change if the GPU watchdog saw a
  // fixed-point overflow, a non-finite value or a CFL violation since the start, a semi-implicit solve ended
  // with a residual above kSolverFailureFactor times its tolerance, or the steps since the last check made energy
  // beyond what float rounding and their truncation allow (the energy audit: sim/EnergyAudit.h). Otherwise the energy
  // account takes those steps (energyBudget). With a share, every share calls it at the same point.
  void checkWatchdog();

  // The energy budget at the last checkWatchdog (or the start): what the particles and bodies hold, what entered and
  // left since the start, and what was dissipated (sim/EnergyAudit.h).
  EnergyBudget energyBudget() const { return energy_.budget(); }

  // The solves since the last call (or the start), and a fresh count from here.
  SolverSummary takeSolverSummary();

  // The particles; with a share, every share's in the order of one process, on the share that writes the output
  // (empty on the others, and every share calls it).
  ParticleSnapshot snapshot() const;
  // With a share: each particle's place in the order a single process would hold it (the snapshot's order); empty
  // without one.
  const std::vector<std::uint32_t>& particleIds() const { return shared_.ids(); }
  // Each rigid body's frame now, in the scene's order (SceneObjects.h: a point p of the body's frame is at
  // positionM + orientation · p), with its velocity and angular velocity: read back from the GPU.
  std::vector<ObjectPose> rigidBodyPoses() const;
  // What each entry of the collider table (the scene's colliders, then its rigid bodies) did to the snow, as of the last
  // checkWatchdog, where bodies.csv follows the object (a rigid body, a collider that moves; 0 for the others).
  struct ObjectLoadReading {
    glm::dvec3 forceN{0.0};  // the snow's mean force on the object over the steps before that check
    double workJ = 0;        // the work the object did on the snow since the start
  };
  std::vector<ObjectLoadReading> objectLoads() const;
  // Sets parked rigid body `index` (Scene::rigidBodies, RigidBody::parked) going from the start of the next step at
  // `pose`: its position, orientation, velocity and angular velocity. A restart parks it again.
  void launchRigidBody(std::size_t index, const ObjectPose& pose);

  // Takes `materials` (the scene's, edited: the scene editor's live materials) from the next step on, where a step can
  // take them without the scene sampled again: the same materials by name and model, at the same densities (a density
  // is the particles' mass; a model, the passes compiled), and for the semi-implicit step no wave faster than the
  // stiffest at the start (its fixed point is set for that). Throws InputError naming the material and the key that
  // needs a new start. The step's moduli, Poisson's ratios, snow's θc, θs and ξ, water's k, γ and viscosity and sand's
  // friction change; the energy account starts again from the particles as they are (the same strain holds another
  // elastic energy), the watchdog read first.
  void setMaterials(const std::vector<Material>& materials);
  // The particles as the readers beside the simulation see them (the renderer, the surface reconstruction): their
  // buffers, read in place, the live count and the time; valid until the next step or addParticles.
  ParticleView particleView() const;
  // With a share: gathers every share's particles into a copy on the GPU of the share that writes the output, which
  // particleView() shows from then on (to the renderer and the surface), and snapshot() reads until the next step.
  // Every share calls it; without a share it does nothing.
  void gatherParticleView();
  // readGridAfterTransfer's nodes, summed (a diagnostic: conservation tests).
  GridTotals transferToGrid();
  // The blocks of the grid the last step used (what the grid passes cost), and the pool's capacity.
  BlockUsage blockUsage() const { return state_.blockUsage(); }

  double timeS() const { return timeS_; }
  std::uint64_t stepCount() const { return steps_; }
  std::size_t particleCount() const { return particleCount_; }
  std::size_t particleCapacity() const { return state_.particleCapacity(); }
  // Emitters' particles still to come.
  std::size_t pendingParticleCount() const { return pendingParticles_.size() - nextPending_; }
  const FixedPointScale& fixedPoint() const { return fixedPoint_; }
  // P2G's shape and the times that chose it, last timed; none until the run has had particles (sim/TransferShape.h).
  const std::optional<TransferShapeChoice>& transferShapeChoice() const { return pipeline_.transferShapeChoice(); }
  const Scene& scene() const { return scene_; }
  // The scene's and its particles' fingerprint, which its checkpoints carry (sim/SceneUpload.h).
  std::uint64_t fingerprint() const { return sceneFingerprint_; }

  // GPU time per pass from GL_TIME_ELAPSED queries, summed over the steps since timing was switched on.
  // Timing waits for each pass, so it is for benchmarks, not for production runs.
  void setPassTiming(bool enabled) { passTimer_.setEnabled(enabled); }
  const std::vector<PassTime>& passTimes() const { return passTimer_.times(); }

  // What one dispatch of a step moved, as its shader's declarations say (gl/StorageAccess.h): each block it reads or
  // writes counted whole, a record per particle or per node of the pool (GpuState::storageRecordBytes). An upper
  // bound of what a pass touches (a pass that writes x of positionMass counts its mass too), and the measure the
  // step's passes are compared with: the floor of one read and one write of each particle's state.
  struct PassTraffic {
    std::string pass;  // the phase name, as passTimes() names it
    std::size_t readBytesPerParticle = 0;
    std::size_t writtenBytesPerParticle = 0;
    std::size_t readBytesPerNode = 0;
    std::size_t writtenBytesPerNode = 0;
  };
  // One step(dtS), recording what each of its dispatches moved, in their order, and the barriers placed between
  // them (gl/BufferBindings.h).
  struct StepTraffic {
    std::vector<PassTraffic> dispatches;
    std::size_t barriers = 0;
  };
  StepTraffic stepRecordingTraffic(double dtS);
  // The bytes of one particle's state, the particle buffers the step carries over (positionMass, velocityVolume, and
  // as the scene needs them F, τ, C and the plastic state): what a step must read once and write once at the least.
  std::size_t particleStateBytes() const;

  // Runs the sort and P2G on the current state and returns every node of the active blocks with its sums in kg
  // and kg m/s (a diagnostic: the atomics' error against a double-precision CPU sum, in
  // `firn bench`). On a state just built (no stress yet, C = 0) the momentum is Σ w m v for every transfer.
  std::vector<GridNodeSums> readGridAfterTransfer();

 private:
  friend class SimulationProbe;  // the tests' access to the parts (tests/support/SimulationProbe.h)

  // Grows the block pool to twice the most blocks a step claimed when that passed `fullness` of its capacity, and
  // notes a step that needed more than the pool held (blocksBeyondPool_).
  void growBlockPool(double fullness);
  // A pool of twice `neededBlocks`, or as many as the driver's buffers hold if fewer (GpuState refuses a pool
  // too small for `neededBlocks`).
  void growBlockPoolTo(std::size_t neededBlocks);
  void releaseDueParticles();
  // Room in the particle buffers for `needed` particles, and some more, never beyond one process's capacity: a share's
  // grow as particles come; one process's hold it all from the start.
  void growParticles(std::size_t needed);
  // The energy audit's sums of the steps since the last check and of the particles now (audit_energy.comp), all
  // shares' summed.
  EnergySums readEnergySums();
  // Each rigid body's pose, none for a parked one (outside the simulation until launched): what the audit counts.
  std::vector<std::optional<ObjectPose>> bodyPosesInPlay() const;
  // Adds a semi-implicit step's solve to the summary, and notes the first that failed (kSolverFailureFactor).
  void noteSolve(const SolveReport& solve);
  // addParticles without growing the pool: emitters' particles, which the pool was sized for.
  void appendParticles(const std::vector<ParticleSeed>& particles);
  void writeParticles(std::size_t first, const std::vector<ParticleSeed>& particles);

  // In the order of their checks: the float atomics the pipeline needs, the buffer sizes, the fixed-point range.
  Scene scene_;
  SharedParticles shared_;  // with a share of the domain: its particles' ids, their gathering (none: all of it)
  StepPipeline pipeline_;
  MaterialTable materialTable_;
  ColliderFields colliderFields_;  // baked once: the collider table's mesh entries and the bodies' probes index it
  GpuState state_;
  FixedPointScale fixedPoint_;
  SteppingPolicy stepping_;
  Diagnostics diagnostics_;
  EnergyAudit energy_;
  std::uint64_t auditedSteps_ = 0;     // the steps the energy account has taken
  double auditedTimeS_ = 0;            // and the time they reached
  // Per entry of the collider table: the impulse its last audited steps gave the snow (x, y, z, in gpu::ObjectLoad's
  // units) and the steps' duration; the work it did since the start (the energy ledger's units).
  std::vector<std::array<std::int64_t, 3>> loadImpulses_;
  double loadDurationS_ = 0;
  std::vector<std::int64_t> objectWork_;
  double largestDtSinceAudit_ = 0;     // the largest step since
  double lastDtS_ = 0;                 // the last step's
  double inverseMassSum_ = 0;          // Σ 1/m over the particles in the run (all shares'): quantizationEnergyJ
  double initialInverseMassSum_ = 0;   // and over those present from the start
  double massKg_ = 0;                  // their mass (all shares')
  double initialMassKg_ = 0;
  double quantizationSinceAudit_ = 0;  // what the steps since the audit's fixed-point rounding can have made (J)
  bool gridHoldsVelocities_ = false;   // the grid holds the last step's velocities (audit_energy.comp's step term)
  gl::PassTimer passTimer_;
  gl::ContextInfo gl_;
  std::size_t totalCapacity_ = 0;  // one process's particle capacity (a share's buffers hold its own particles)
  std::uint64_t sceneFingerprint_ = 0;
  bool keyframedColliders_ = false;  // whether the collider table changes as the steps go
  std::size_t initialParticles_ = 0; // the particles present from the start, in all shares

  std::size_t particleCount_ = 0;
  std::vector<ParticleSeed> pendingParticles_;  // emitters' particles not yet released, by release time
  std::size_t nextPending_ = 0;
  double timeS_ = 0;
  std::uint64_t steps_ = 0;
  std::size_t blocksBeyondPool_ = 0;  // the most blocks a step needed, when that was more than the pool held
  SolverSummary solverSummary_;
  std::optional<SolverFailure> solverFailure_;  // the first solve that ended far from its tolerance

  // saveState's counters (GpuState keeps the buffers' copies).
  struct SavedCounters {
    double timeS = 0;
    std::uint64_t steps = 0;
    std::size_t particleCount = 0;
    std::vector<std::uint32_t> ids;
    std::size_t nextPending = 0;
    double fastestSignalMPerS = 0;
    SolverSummary solverSummary;
    std::optional<SolverFailure> solverFailure;
    double pendingArrivalJ = 0;
    double largestDtSinceAudit = 0;
    double inverseMassSum = 0;
    double massKg = 0;
    double quantizationSinceAudit = 0;
    // The audit's, which a frame's share commits before all shares have accepted the frame (a frame another share
    // rejects is redone, and must not count twice).
    EnergyAccount energyAccount;
    std::uint64_t auditedSteps = 0;
    double auditedTimeS = 0;
    std::vector<std::array<std::int64_t, 3>> loadImpulses;
    double loadDurationS = 0;
    std::vector<std::int64_t> objectWork;
  };
  SavedCounters saved_;
};

}  // namespace firn
