#include "sim/Simulation.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

#include "Error.h"
#include "gpu/Materials.h"
#include "io/Text.h"
#include "scene/SceneObjects.h"

namespace firn {

namespace {

const Scene& requireParticles(const Scene& scene, const std::vector<ParticleSeed>& seeds) {
  if (seeds.empty()) throw InputError(sceneFileName(scene) + ": bodies: the scene has no particles");
  return scene;
}

// The particles present from the start; the emitters' others go to `pending`, in order of release.
std::vector<ParticleSeed> splitByRelease(const std::vector<ParticleSeed>& particles, std::vector<ParticleSeed>& pending) {
  std::vector<ParticleSeed> initial;
  initial.reserve(particles.size());
  for (const ParticleSeed& seed : particles) (seed.releaseTimeS > 0 ? pending : initial).push_back(seed);
  std::stable_sort(pending.begin(), pending.end(),
                   [](const ParticleSeed& a, const ParticleSeed& b) { return a.releaseTimeS < b.releaseTimeS; });
  return initial;
}

// Before the first step the fastest signal is the seeds' fastest speed plus the stiffest material's wave speed
// (semi-implicit steps: the speed alone, as g2p.comp reports it), or a rigid body's fastest surface point,
// |v| + |ω| r, as integrate_bodies.comp reports it.
double initialFastestSignalMPerS(const Scene& scene, const std::vector<ParticleSeed>& seeds) {
  const double fastestWaveMPerS = scene.solver.semiImplicit() ? 0.0 : stiffestBody(scene).waveSpeedMPerS;
  double fastestMPerS = 0;
  for (const ParticleSeed& seed : seeds) {
    fastestMPerS = std::max(fastestMPerS, double(glm::length(seed.velocityMPerS)) + fastestWaveMPerS);
  }
  for (const RigidBody& body : scene.rigidBodies) {
    if (body.parked) continue;
    fastestMPerS = std::max(fastestMPerS, rigidBodySurfaceSpeedMPerS(body));
  }
  return fastestMPerS;
}

// A pool of `wanted` blocks, or of as many as the driver's buffers hold if that is fewer but still the `needed`; a
// pool that cannot hold what is needed is left for GpuState to refuse, with the sizes.
std::size_t poolCapacity(const Scene& scene, std::size_t needed, std::size_t wanted, const gl::ContextInfo& gl) {
  const std::size_t most = GpuStateLayout::maxPoolBlocks(gl.maxStorageBlockBytes, scene.solver.semiImplicit());
  return needed > most ? needed : std::min(wanted, most);
}

// The block pool starts with room for the particles to spread: four times the blocks they reach at the start, the
// emitters' included (and at least a few hundred: a pool of 256 blocks is 256 KiB of nodes).
// With a share, the blocks its own seeds reach.
std::size_t initialBlockCapacity(const Scene& scene, const std::vector<ParticleSeed>& seeds, const DomainShare* share,
                                 const gl::ContextInfo& gl) {
  std::vector<ParticleSeed> own;
  if (share != nullptr) {
    std::copy_if(seeds.begin(), seeds.end(), std::back_inserter(own),
                 [share](const ParticleSeed& seed) { return share->owns(seed.positionM); });
  }
  const std::size_t reached = blocksReached(scene, share != nullptr ? own : seeds);
  return poolCapacity(scene, reached, std::max<std::size_t>(4 * reached, 256), gl);
}

// The fixed-point scales of a scene, its seeds and the particle capacity of one process: P2G's and the energy ledger's.
FixedPointScale fixedPointScaleFor(const Scene& scene, const std::vector<ParticleSeed>& seeds, std::size_t capacity) {
  FixedPointScale scale = fixedPointScaleFor(scene, seeds);
  deriveEnergyScale(scale, scene, seeds, capacity);
  return scale;
}

// Σ 1/m and Σ m over `particles`.
double inverseMassSum(const std::vector<ParticleSeed>& particles) {
  double sum = 0;
  for (const ParticleSeed& particle : particles) sum += 1.0 / double(particle.massKg);
  return sum;
}
double massSum(const std::vector<ParticleSeed>& particles) {
  double sum = 0;
  for (const ParticleSeed& particle : particles) sum += double(particle.massKg);
  return sum;
}

// When the pool is this full at the end of a frame, it doubles for the frames to come.
constexpr double kBlockPoolGrowthFullness = 0.75;
// A frame that needed more blocks than the pool held is redone with a pool grown to fit, up to this many times.
constexpr int kBlockPoolRetries = 3;

}  // namespace

Simulation::Simulation(const Scene& scene, const std::vector<ParticleSeed>& seeds, const gl::ContextInfo& gl,
                       const SimulationOptions& options)
    : Simulation(scene, seeds, gl, bakeColliderFields(scene), options) {}

Simulation::Simulation(const Scene& scene, const std::vector<ParticleSeed>& seeds, const gl::ContextInfo& gl,
                       ColliderFields colliderFields, const SimulationOptions& options)
    : scene_(requireParticles(scene, seeds)),
      shared_(options.share, std::max(options.particleCapacity, seeds.size()), seeds),
      pipeline_(scene_, options.programs, gl, transferShapeCandidates(scene_, options.transferShapes)),
      materialTable_(buildMaterialTable(scene_)),
      colliderFields_(std::move(colliderFields)),
      state_(GpuStateLayout::forScene(
                 scene_, shared_.startCapacity(seeds),
                 options.blockCapacity > 0 ? options.blockCapacity
                                           : initialBlockCapacity(scene_, seeds, options.share, gl),
                 needsDeformationGradient(scene_, options.programs)),
             materialTable_, buildColliderTable(scene_, colliderFields_, 0), buildBodyRecords(scene_, colliderFields_),
             colliderFields_.samples, gl, stepShaderOptions(scene_, options.programs)),
      fixedPoint_(fixedPointScaleFor(scene_, seeds, std::max(options.particleCapacity, seeds.size()))),
      stepping_(scene_, initialFastestSignalMPerS(scene_, seeds)),
      diagnostics_(scene_, fixedPoint_),
      energy_(scene_, fixedPoint_),
      gl_(gl),
      totalCapacity_(std::max(options.particleCapacity, seeds.size())),
      sceneFingerprint_(sceneFingerprint(scene_, totalCapacity_, materialTable_, colliderFields_, seeds)),
      keyframedColliders_(std::any_of(scene_.colliders.begin(), scene_.colliders.end(),
                                      [](const Collider& c) { return !c.keyframes.empty(); })) {
  const std::vector<ParticleSeed> initial = splitByRelease(seeds, pendingParticles_);
  initialParticles_ = initial.size();
  initialInverseMassSum_ = inverseMassSum_ = inverseMassSum(initial);
  initialMassKg_ = massKg_ = massSum(initial);
  if (shared_.share()) {
    // The diagnostics know every particle of the scene, in one process's order: the first, then the emitters'.
    diagnostics_.noteParticles(initial);
    diagnostics_.noteParticles(pendingParticles_);
    diagnostics_.followIds(&shared_.ids());
    // A body's images push the nodes that hold snow, which another share's particles may fill: this share must hold
    // those nodes' blocks too (docs/distributed.md).
    if (mirrorsStressIntoBodies(scene_)) state_.grid().claimImageBlocks();
  }
  const std::vector<ParticleSeed> particles = shared_.own(initial, 0);
  writeParticles(0, particles);
  particleCount_ = particles.size();

  // The first step's uniforms, for the transfers below.
  state_.writeStepUniforms(stepUniforms(scene_, fixedPoint_, scene_.time.dtS, timeS_, particleCount_, steps_));
  // Initial volumes (Stomakhin et al. 2013 §6 step 2): one P2G of mass, then V0 = m / max(ρ_grid, ρ), unless the
  // scene takes them from the materials' densities ρ alone (written above; docs/algorithm.md, Initial volumes).
  if (scene_.solver.particleVolume == ParticleVolume::GridDensity) {
    pipeline_.transferToGrid(state_, particleCount_, passTimer_);
    // A pool given too small for the first particles grows, and their grid is summed again.
    const BlockUsage usage = state_.blockUsage();
    if (usage.mostInAStep > usage.capacity) {
      state_.resizeBlockPool(poolCapacity(scene_, usage.mostInAStep, 2 * usage.mostInAStep, gl_), gl_);
      pipeline_.transferToGrid(state_, particleCount_, passTimer_);
    }
    shared_.sumSharedNodes(state_.grid());
    pipeline_.computeVolumes(state_, particleCount_, passTimer_);
  }
  // P2G's shape, timed on these particles (sim/TransferShape.h); a scene whose particles all come later chooses at
  // its first step with particles, and every run times the shapes again as its particles grow (Simulation::step).
  pipeline_.chooseTransferShape(state_, particleCount_);
  // The energy account starts from what the first particles and the bodies hold.
  energy_.start(readEnergySums(), bodyPosesInPlay());
  state_.writeEnergyRecords();
  const std::size_t objects = scene_.colliders.size() + scene_.rigidBodies.size();
  loadImpulses_.assign(objects, {0, 0, 0});
  objectWork_.assign(objects, 0);
}

void Simulation::writeParticles(std::size_t first, const std::vector<ParticleSeed>& particles) {
  state_.particles().write(first, particleRecords(scene_, materialTable_, colliderFields_, particles));
  diagnostics_.noteParticles(particles);
}

void Simulation::addParticles(const std::vector<ParticleSeed>& particles) {
  if (particles.empty()) return;
  appendParticles(particles);
  energy_.noteArrival(arrivingEnergyJ(scene_, particles));
  inverseMassSum_ += inverseMassSum(particles);
  massKg_ += massSum(particles);
  // The blocks they reach, on top of the most a step has needed, must fit three quarters of the pool: the pool is
  // grown now rather than a step leaving them out (a window throwing snowballs has no frame to redo).
  const BlockUsage usage = state_.blockUsage();
  const std::size_t needed = usage.mostInAStep + blocksReached(scene_, particles);
  if (double(needed) > kBlockPoolGrowthFullness * double(usage.capacity)) growBlockPoolTo(needed);
}

void Simulation::appendParticles(const std::vector<ParticleSeed>& particles) {
  if (particles.empty()) return;
  growParticles(particleCount_ + particles.size());
  if (particles.size() > particleCapacity() - particleCount_) {
    throw std::length_error("addParticles: " + std::to_string(particles.size()) + " particles do not fit: " +
                            std::to_string(particleCount_) + " of " + std::to_string(particleCapacity()) + " in use");
  }
  for (const ParticleSeed& seed : particles) {
    // The fixed-point bounds were derived for masses up to m_ref (docs/numerics.md, "Fixed-point atomics").
    if (double(seed.massKg) > fixedPoint_.referenceMassKg) {
      throw std::invalid_argument("addParticles: a particle of " + format("%.4g", seed.massKg) +
                                  " kg exceeds the fixed-point reference mass " +
                                  format("%.4g", fixedPoint_.referenceMassKg) + " kg");
    }
  }
  writeParticles(particleCount_, particles);
  particleCount_ += particles.size();
}

void Simulation::growParticles(std::size_t needed) {
  if (needed <= particleCapacity() || particleCapacity() >= totalCapacity_) return;
  state_.growParticles(shareParticleCapacity(needed, totalCapacity_), gl_);
}

void Simulation::releaseDueParticles() {
  std::vector<ParticleSeed> due;
  // The tolerance lets a particle due at a frame time join at that frame's first step despite rounding.
  const double nowS = timeS_ + 1e-9 * scene_.time.dtS;
  const std::size_t firstId = initialParticles_ + nextPending_;  // emitters' particles follow in release order
  while (nextPending_ < pendingParticles_.size() && pendingParticles_[nextPending_].releaseTimeS <= nowS) {
    due.push_back(pendingParticles_[nextPending_++]);
  }
  if (due.empty()) return;
  energy_.noteArrival(arrivingEnergyJ(scene_, due));  // all shares' alike: every share knows every emitter's particles
  inverseMassSum_ += inverseMassSum(due);
  massKg_ += massSum(due);
  appendParticles(shared_.own(due, firstId));
}

void Simulation::step(double dtS) {
  shared_.beginStep(steps_);
  releaseDueParticles();
  // A keyframed collider's pose changes from one segment of its motion to the next (docs/algorithm.md, Colliders).
  // The rigid bodies' entries after them are the GPU's own (integrate_bodies.comp).
  if (keyframedColliders_) state_.writeColliders(colliderEntries(scene_, colliderFields_, timeS_));
  state_.writeStepUniforms(stepUniforms(scene_, fixedPoint_, dtS, timeS_, particleCount_, steps_));
  pipeline_.chooseTransferShape(state_, particleCount_);  // at the first step with particles, and as they grow
  const SolveReport solve = pipeline_.step(state_, particleCount_, passTimer_, shared_.share());
  if (scene_.solver.semiImplicit()) noteSolve(solve);
  particleCount_ = shared_.migrate(state_, particleCount_, [this](std::size_t n) { growParticles(n); });
  timeS_ += dtS;
  ++steps_;
  largestDtSinceAudit_ = std::max(largestDtSinceAudit_, dtS);
  lastDtS_ = dtS;
  if (scene_.solver.atomics == Atomics::FixedPoint) {
    const double momentumUnitKgMPerS = scene_.time.adaptive ? fixedPoint_.referenceMassKg * scene_.grid.cellSizeM / dtS
                                                            : fixedPoint_.momentumUnitKgMPerS;
    quantizationSinceAudit_ += quantizationEnergyJ(fixedPoint_, momentumUnitKgMPerS, inverseMassSum_);
  }
  gridHoldsVelocities_ = true;
}

void Simulation::noteSolve(const SolveReport& solve) {
  ++solverSummary_.solves;
  solverSummary_.iterations += std::uint64_t(solve.iterations);
  solverSummary_.mostIterations = std::max(solverSummary_.mostIterations, solve.iterations);
  if (std::isnan(solve.residual) || std::isnan(solverSummary_.largestResidual)) {
    solverSummary_.largestResidual = std::numeric_limits<double>::quiet_NaN();
  } else {
    solverSummary_.largestResidual = std::max(solverSummary_.largestResidual, solve.residual);
  }
  const bool failed = !(solve.residual <= kSolverFailureFactor * scene_.solver.tolerance);  // NaN fails
  if (failed && !solverFailure_) solverFailure_ = SolverFailure{steps_, solve};
}

SolverSummary Simulation::takeSolverSummary() {
  const SolverSummary summary = solverSummary_;
  solverSummary_ = SolverSummary{};
  return summary;
}

int Simulation::advanceTo(double timeS) {
  // Every share steps alike: by the fastest signal in any of them.
  const int steps = stepping_.advance(
      timeS_, timeS, [this](double dtS) { step(dtS); },
      [this] { return shared_.largest(state_.fastestSignalMPerS()); });
  if (stepping_.adaptive() || steps > 0) timeS_ = timeS;  // exactly, whatever the steps' rounding
  growBlockPool(kBlockPoolGrowthFullness);
  return steps;
}

void Simulation::growBlockPool(double fullness) {
  const BlockUsage usage = state_.blockUsage();
  if (usage.mostInAStep > usage.capacity) blocksBeyondPool_ = std::max(blocksBeyondPool_, usage.mostInAStep);
  if (double(usage.mostInAStep) > fullness * double(usage.capacity)) growBlockPoolTo(usage.mostInAStep);
}

void Simulation::growBlockPoolTo(std::size_t neededBlocks) {
  const std::size_t capacity = poolCapacity(scene_, neededBlocks, 2 * neededBlocks, gl_);
  if (capacity != state_.blockUsage().capacity) state_.resizeBlockPool(capacity, gl_);
}

int Simulation::advanceFrame(double frameTimeS, std::ostream& log) {
  saveState();
  const std::size_t shapeTimedOn = transferShapeChoice() ? transferShapeChoice()->particles : 0;
  int poolRetries = 0;
  for (int attempt = 0;;) {
    blocksBeyondPool_ = 0;
    const int steps = advanceTo(frameTimeS);
    // A frame whose particles reached more blocks than the pool held left some out of a step: it is redone from
    // its start with the pool advanceTo grew, which gives the bytes a pool large enough from the start would. Shares
    // step together, so a frame one of them redoes, all redo.
    const bool beyondPool = shared_.any(blocksBeyondPool_ > 0);
    if (beyondPool && poolRetries < kBlockPoolRetries) {
      ++poolRetries;
      if (blocksBeyondPool_ > 0) {
        log << "\nfirn: the frame ending at t = " << frameTimeS << " s needed " << blocksBeyondPool_
            << " blocks of the grid, more than its pool held; redoing it with room for " << state_.blockUsage().capacity
            << "\n";
      } else {
        log << "\nfirn: the frame ending at t = " << frameTimeS << " s needed more blocks of the grid than another "
            << "process's pool held; redoing it\n";
      }
      restoreState();
      continue;
    }
    std::optional<SimulationError> failure;
    try {
      checkWatchdog();
    } catch (const SimulationError& error) {
      failure = error;
    }
    const bool failed = shared_.any(failure.has_value());
    if (!failed) {
      stepping_.resetStepScale();
      // P2G's shape, timed at the frame's first step with particles or again after the particles grew.
      const std::optional<TransferShapeChoice>& shape = transferShapeChoice();
      if (shape && shape->particles != shapeTimedOn) log << "\nfirn: transfers: " << shape->describe() << "\n";
      particleCount_ = shared_.endFrame(state_, particleCount_, [this](std::size_t n) { growParticles(n); });
      return steps;
    }
    if (!stepping_.adaptive() || !stepping_.shrinkForRetry(attempt++)) {
      if (failure) throw *failure;
      throw StoppedElsewhere("the frame ending at t = " + formatApproximately(frameTimeS) +
                             " s went unstable in another process of the run");
    }
    log << "\nfirn: the frame ending at t = " << frameTimeS << " s went unstable; redoing it with steps "
        << stepping_.stepScale() << " times as large\n";
    restoreState();
  }
}

void Simulation::saveState() {
  state_.save();
  saved_ = {timeS_,         steps_,         particleCount_, shared_.ids(), nextPending_, stepping_.fastestSignalMPerS(),
            solverSummary_, solverFailure_, energy_.pendingArrivalJ(), largestDtSinceAudit_, inverseMassSum_,
            massKg_,  quantizationSinceAudit_, energy_.account(), auditedSteps_, auditedTimeS_,
            loadImpulses_, loadDurationS_, objectWork_};
}

void Simulation::restoreState() {
  state_.restore();
  timeS_ = saved_.timeS;
  steps_ = saved_.steps;
  particleCount_ = saved_.particleCount;
  shared_.restore(saved_.ids);
  diagnostics_.keepParticles(particleCount_);
  nextPending_ = saved_.nextPending;
  stepping_.setFastestSignalMPerS(saved_.fastestSignalMPerS);
  solverSummary_ = saved_.solverSummary;
  solverFailure_ = saved_.solverFailure;
  energy_.setPendingArrivalJ(saved_.pendingArrivalJ);
  largestDtSinceAudit_ = saved_.largestDtSinceAudit;
  inverseMassSum_ = saved_.inverseMassSum;
  massKg_ = saved_.massKg;
  quantizationSinceAudit_ = saved_.quantizationSinceAudit;
  energy_.setAccount(saved_.energyAccount);
  auditedSteps_ = saved_.auditedSteps;
  auditedTimeS_ = saved_.auditedTimeS;
  loadImpulses_ = saved_.loadImpulses;
  loadDurationS_ = saved_.loadDurationS;
  objectWork_ = saved_.objectWork;
}

Checkpoint Simulation::checkpoint(int frame) const {
  Checkpoint checkpoint;
  checkpoint.sceneFingerprint = sceneFingerprint_;
  checkpoint.frame = frame;
  checkpoint.timeS = timeS_;
  checkpoint.steps = steps_;
  checkpoint.particleCount = particleCount_;
  checkpoint.releasedEmitterParticles = nextPending_;
  checkpoint.fastestSpeedMPerS = stepping_.fastestSignalMPerS();
  packEnergyAccount(energy_.account(), checkpoint);
  for (std::size_t i = 0; i < objectWork_.size(); ++i) {
    checkpoint.objectLoads.insert(checkpoint.objectLoads.end(),
                                  {loadImpulses_[i][0], loadImpulses_[i][1], loadImpulses_[i][2], objectWork_[i]});
  }
  checkpoint.objectLoadDurationS = loadDurationS_;
  checkpoint.buffers = state_.stateBytes();
  // Over several processes: every share's particles in one process's order, and the watchdogs as one.
  shared_.gatherCheckpoint(checkpoint, state_, particleCount_);
  return checkpoint;
}

void Simulation::resume(const Checkpoint& checkpoint, const std::filesystem::path& source) {
  if (checkpoint.sceneFingerprint != sceneFingerprint_) {
    throw InputError(source.string() + ": the checkpoint was written for another scene (or another version of this "
                     "one); resume it with the scene it came from");
  }
  state_.checkStateBytes(checkpoint.buffers, source.string(), totalCapacity_);
  if (checkpoint.objectLoads.size() != 4 * objectWork_.size()) {
    throw InputError(source.string() + ": the checkpoint was written for another scene (or another version of this "
                     "one); resume it with the scene it came from");
  }
  if (checkpoint.particleCount > totalCapacity_ || checkpoint.releasedEmitterParticles > pendingParticles_.size()) {
    throw InputError(source.string() + ": the checkpoint holds more particles than the scene makes");
  }
  if (!std::isfinite(checkpoint.timeS) || !std::isfinite(checkpoint.fastestSpeedMPerS) ||
      !std::isfinite(checkpoint.objectLoadDurationS) ||
      !std::all_of(checkpoint.energyReals.begin(), checkpoint.energyReals.end(),
                   [](double value) { return std::isfinite(value); })) {
    throw InputError(source.string() + ": the checkpoint's time, speed estimate or energy account is not finite; a "
                     "run never checkpoints such a state, so this file cannot be resumed");
  }
  state_.particles().checkFinite(checkpoint.buffers, checkpoint.particleCount, source.string());
  const std::size_t particles =
      shared_.scatterCheckpoint(checkpoint, state_, [this](std::size_t n) { growParticles(n); });
  timeS_ = checkpoint.timeS;
  steps_ = checkpoint.steps;
  auditedSteps_ = steps_;
  stepping_.setFastestSignalMPerS(checkpoint.fastestSpeedMPerS);
  energy_.setAccount(unpackEnergyAccount(checkpoint));
  for (std::size_t i = 0; i < objectWork_.size(); ++i) {
    const std::int64_t* load = checkpoint.objectLoads.data() + 4 * i;
    loadImpulses_[i] = {load[0], load[1], load[2]};
    objectWork_[i] = load[3];
  }
  loadDurationS_ = checkpoint.objectLoadDurationS;
  auditedTimeS_ = checkpoint.timeS;
  gridHoldsVelocities_ = false;
  energy_.setPendingArrivalJ(0);
  largestDtSinceAudit_ = 0;
  quantizationSinceAudit_ = 0;
  // The initial particles', and the emitters' that had joined by then.
  const std::vector<ParticleSeed> joined(
      pendingParticles_.begin(), pendingParticles_.begin() + std::ptrdiff_t(checkpoint.releasedEmitterParticles));
  inverseMassSum_ = initialInverseMassSum_ + inverseMassSum(joined);
  massKg_ = initialMassKg_ + massSum(joined);
  state_.writeEnergyRecords();  // a checkpoint is taken with the ledger empty; the account holds what it summed
  // The particles present: the first ones, then the emitters' in the order they were released.
  const auto released = pendingParticles_.begin() + std::ptrdiff_t(nextPending_);
  diagnostics_.noteParticles({released, pendingParticles_.begin() + std::ptrdiff_t(checkpoint.releasedEmitterParticles)});
  nextPending_ = checkpoint.releasedEmitterParticles;
  particleCount_ = particles;
}

void Simulation::setMaterials(const std::vector<Material>& materials) {
  const std::string file = sceneFileName(scene_);
  if (materials.size() != scene_.materials.size()) {
    throw InputError(file + ": materials: a material added or removed applies when the scene starts again");
  }
  for (std::size_t m = 0; m < materials.size(); ++m) {
    const Material& now = scene_.materials[m];
    const Material& edited = materials[m];
    const std::string key = "materials." + now.name;
    if (edited.name != now.name) {
      throw InputError(file + ": " + key + ": a renamed material applies when the scene starts again");
    }
    if (edited.model != now.model) {
      throw InputError(file + ": " + key +
                       ".model: another model applies when the scene starts again (the passes are compiled for it)");
    }
    if (edited.densityKgPerM3 != now.densityKgPerM3) {
      throw InputError(file + ": " + key +
                       ".density: a density is the particles' mass: it applies when the scene is sampled again");
    }
  }
  Scene edited = scene_;
  edited.materials = materials;
  const StiffestBody stiffest = stiffestBody(edited);
  if (scene_.solver.semiImplicit() && stiffest.waveSpeedMPerS > stiffestBody(scene_).waveSpeedMPerS) {
    const std::string name =
        materials[std::size_t(scene_.bodies[std::size_t(stiffest.bodyIndex)].materialIndex)].name;
    throw InputError(file + ": materials." + name + ": a wave faster than the stiffest at the start (" +
                     format("%.4g", stiffest.waveSpeedMPerS) + " m/s against " +
                     format("%.4g", stiffestBody(scene_).waveSpeedMPerS) +
                     ") applies when the scene starts again: the semi-implicit solve's fixed point is set for it");
  }
  checkWatchdog();  // the account so far, with the old moduli
  MaterialTable table = buildMaterialTable(edited);
  state_.writeMaterials(table);
  materialTable_ = std::move(table);
  scene_.materials = materials;
  diagnostics_.setMaterials(scene_);
  energy_ = EnergyAudit(scene_, fixedPoint_);
  energy_.start(readEnergySums(), bodyPosesInPlay());
  state_.writeEnergyRecords();  // the ledger sums afresh for the next reading, as at the start
}

EnergySums Simulation::readEnergySums() {
  // The uniforms of the last step's dt (the step's term) and of the particles now (some may have been added).
  state_.writeStepUniforms(stepUniforms(scene_, fixedPoint_, lastDtS_ > 0 ? lastDtS_ : scene_.time.dtS, timeS_,
                                        particleCount_, steps_));
  pipeline_.auditEnergy(state_, particleCount_, gridHoldsVelocities_, passTimer_);
  EnergySums sums = energySums(state_.energyLedger());
  // All shares' summed (one process: as they are).
  std::vector<std::int64_t> values = {sums.particles[0], sums.particles[1], sums.particles[2],
                                      sums.stepTerm,     sums.flows[0],     sums.flows[1],
                                      sums.flows[2],     sums.flows[3],     std::int64_t(sums.beyondLimit)};
  shared_.sumExactly(values);
  sums.particles = {values[0], values[1], values[2]};
  sums.stepTerm = values[3];
  sums.flows = {values[4], values[5], values[6], values[7]};
  sums.beyondLimit = std::uint64_t(values[8]);
  return sums;
}

void Simulation::checkWatchdog() {
  // The energy audit first: over several processes its sums are all shares', which every share reads here alike.
  const EnergyAudit::Reading energy =
      energy_.read(readEnergySums(), bodyPosesInPlay(), steps_ - auditedSteps_, largestDtSinceAudit_,
                   quantizationSinceAudit_, initialParticles_ + nextPending_, massKg_);
  // The objects' loads since: per entry its impulse x, y, z and its work, all shares' summed.
  std::vector<std::int64_t> loads;
  const std::vector<gpu::ObjectLoad> objectLoads = state_.objectLoads();
  for (std::size_t i = 0; i < objectWork_.size(); ++i) {
    for (int c = 0; c < 4; ++c) {
      loads.push_back(joinFixed64(objectLoads[i].low[c], objectLoads[i].high[c]));
    }
  }
  shared_.sumExactly(loads);
  std::optional<EnergyEvent> energyEvent;
  if (energy.creation) energyEvent = EnergyEvent{*energy.creation, auditedSteps_, steps_};
  const BlockUsage usage = state_.blockUsage();
  const std::size_t blocksNeeded =
      std::max(blocksBeyondPool_, usage.mostInAStep > usage.capacity ? usage.mostInAStep : std::size_t(0));
  diagnostics_.check(state_.watchdog(), state_, blocksNeeded, usage.capacity, solverFailure_, energyEvent);
  energy_.commit(energy);
  state_.writeEnergyRecords();
  for (std::size_t i = 0; i < objectWork_.size(); ++i) {
    loadImpulses_[i] = {loads[4 * i], loads[4 * i + 1], loads[4 * i + 2]};
    objectWork_[i] += loads[4 * i + 3];
  }
  loadDurationS_ = timeS_ - auditedTimeS_;
  auditedTimeS_ = timeS_;
  auditedSteps_ = steps_;
  largestDtSinceAudit_ = 0;
  quantizationSinceAudit_ = 0;
}

ParticleSnapshot Simulation::snapshot() const { return shared_.snapshot(state_.particles(), particleCount_); }

ParticleView Simulation::particleView() const {
  if (const std::optional<ParticleView> gathered = shared_.view(timeS_)) return *gathered;
  return state_.particles().view(particleCount_, timeS_);
}

void Simulation::gatherParticleView() { shared_.gatherView(state_.particles(), particleCount_); }

GridTotals Simulation::transferToGrid() {
  // Added in node order: the same node sums (fixed point's do not depend on the particles' order) give the same
  // totals to the last bit.
  GridTotals totals;
  for (const GridNodeSums& node : readGridAfterTransfer()) {
    totals.massKg += node.massKg;
    totals.momentumKgMPerS += node.momentumKgMPerS;
    ++totals.activeNodes;
  }
  return totals;
}

std::vector<GridNodeSums> Simulation::readGridAfterTransfer() {
  gridHoldsVelocities_ = false;
  state_.writeStepUniforms(stepUniforms(scene_, fixedPoint_, scene_.time.dtS, timeS_, particleCount_, steps_));
  pipeline_.transferToGrid(state_, particleCount_, passTimer_);
  std::vector<GridNodeSums> nodes;
  for (const StoredNode& stored : state_.grid().readNodes()) {
    // Nondimensional sums (grid.glsl): integers times 2^−k, or the floats themselves.
    const glm::dvec4 sums = scene_.solver.atomics == Atomics::FixedPoint
                                ? glm::dvec4(stored.sums) * fixedPoint_.resolution()
                                : glm::dvec4(glm::intBitsToFloat(stored.sums));
    nodes.push_back({stored.node, sums.w * fixedPoint_.referenceMassKg, glm::dvec3(sums) * fixedPoint_.momentumUnitKgMPerS});
  }
  return nodes;
}

std::vector<Simulation::ObjectLoadReading> Simulation::objectLoads() const {
  // gpu::ObjectLoad's units: 2^−24 m_ref h / s of impulse, the energy ledger's of work.
  const double kgMPerSPerUnit = std::ldexp(fixedPoint_.referenceMassKg * scene_.grid.cellSizeM, -24);
  std::vector<ObjectLoadReading> readings(objectWork_.size());
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const glm::dvec3 onSnowKgMPerS(double(loadImpulses_[i][0]), double(loadImpulses_[i][1]), double(loadImpulses_[i][2]));
    if (loadDurationS_ > 0) readings[i].forceN = -onSnowKgMPerS * kgMPerSPerUnit / loadDurationS_;
    readings[i].workJ = double(objectWork_[i]) * energy_.joulesPerUnit();
  }
  return readings;
}

std::vector<std::optional<ObjectPose>> Simulation::bodyPosesInPlay() const {
  const RigidBodies* bodies = pipeline_.rigidBodies();
  return bodies ? bodies->posesInPlay(state_) : std::vector<std::optional<ObjectPose>>();
}

std::vector<ObjectPose> Simulation::rigidBodyPoses() const {
  const RigidBodies* bodies = pipeline_.rigidBodies();
  return bodies ? bodies->poses(state_) : std::vector<ObjectPose>();
}

void Simulation::launchRigidBody(std::size_t index, const ObjectPose& pose) {
  RigidBody body = scene_.rigidBodies.at(index);
  body.parked = false;
  energy_.noteArrival(rigidBodyKineticEnergyJ(body, pose) +
                      potentialEnergyJ(scene_.gravityMPerS2, potentialFloorM(scene_), body.massKg, pose.positionM));
  pipeline_.rigidBodies()->write(state_, index, rigidBodyEntry(body, colliderFields_, index, pose, timeS_),
                                 rigidBodyRecord(body, colliderFields_, index, pose));
}

Simulation::StepTraffic Simulation::stepRecordingTraffic(double dtS) {
  std::vector<gl::BufferBindings::PassRecord> record;
  const std::size_t barriersBefore = state_.bindings().barriers();
  state_.bindings().recordPasses(&record);
  try {
    step(dtS);
  } catch (...) {
    state_.bindings().recordPasses(nullptr);
    throw;
  }
  state_.bindings().recordPasses(nullptr);
  const StorageRecordBytes bytes = state_.storageRecordBytes();
  StepTraffic traffic;
  traffic.barriers = state_.bindings().barriers() - barriersBefore;
  for (const gl::BufferBindings::PassRecord& pass : record) {
    PassTraffic moved;
    moved.pass = pass.phase;
    for (std::size_t binding = 0; binding < bytes.perParticle.size(); ++binding) {
      // (A pass that declares nothing counts as reading and writing every block it has: gl::undeclaredAccess.)
      const gl::BindingSet bit = gl::bindingBit(unsigned(binding));
      const bool reads = (pass.access.reads & bit) != 0;
      const bool writes = (pass.access.writes & bit) != 0;
      if (reads) moved.readBytesPerParticle += bytes.perParticle[binding];
      if (writes) moved.writtenBytesPerParticle += bytes.perParticle[binding];
      if (reads) moved.readBytesPerNode += bytes.perNode[binding];
      if (writes) moved.writtenBytesPerNode += bytes.perNode[binding];
    }
    traffic.dispatches.push_back(std::move(moved));
  }
  return traffic;
}

std::size_t Simulation::particleStateBytes() const {
  const StorageRecordBytes bytes = state_.storageRecordBytes();
  std::size_t state = 0;
  for (unsigned binding = FIRN_PARTICLE_BINDINGS_FIRST; binding < FIRN_PARTICLE_BINDINGS_END; ++binding) {
    state += bytes.perParticle[binding];
  }
  return state;
}

}  // namespace firn
