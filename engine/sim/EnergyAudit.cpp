#include "sim/EnergyAudit.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

#include "gpu/Materials.h"
#include "io/Checkpoint.h"
#include "scene/ColliderMotion.h"

namespace firn {

namespace {

// 2^54 units for the scene's bound, 2^8 of it more before a sum of all particles leaves 64 bits (deriveEnergyScale).
constexpr int kEnergyResolutionBits = 54;
constexpr int kEnergySumBits = 62;

// The kinetic and elastic energy of an audit, the bodies' kinetic energy with it: what the step's truncation acts on.
double mechanicalJ(const EnergyBudget& budget) { return budget.kineticJ + budget.elasticJ + budget.bodiesKineticJ; }

}  // namespace

void deriveEnergyScale(FixedPointScale& scale, const Scene& scene, const std::vector<ParticleSeed>& seeds,
                       std::size_t capacity) {
  const double h = scene.grid.cellSizeM;
  const double cellsPerStepMPerS = h / scene.time.dtS;
  const double waveMPerS = stiffestBody(scene).waveSpeedMPerS;
  const double diagonalM = glm::length(glm::dvec3(scene.grid.cells) * h);
  double fastestMPerS = 0;
  for (const ParticleSeed& seed : seeds) fastestMPerS = std::max(fastestMPerS, double(glm::length(seed.velocityMPerS)));
  for (const Collider& collider : scene.colliders) {
    fastestMPerS = std::max(fastestMPerS, fastestColliderSpeedMPerS(scene, collider));
  }
  for (const RigidBody& body : scene.rigidBodies) fastestMPerS = std::max(fastestMPerS, rigidBodySurfaceSpeedMPerS(body));
  const double particleBoundJ =
      scale.referenceMassKg * (cellsPerStepMPerS * cellsPerStepMPerS + waveMPerS * waveMPerS +
                               2 * glm::length(scene.gravityMPerS2) * diagonalM + fastestMPerS * fastestMPerS);
  const double sceneBoundJ = double(std::max<std::size_t>(capacity, 1)) * particleBoundJ;
  // A power of two, so that the GPU's float holds it exactly and the host's conversion back is exact too.
  scale.energyUnitsPerJ = std::ldexp(1.0, int(std::floor(kEnergyResolutionBits - std::log2(sceneBoundJ))));
  scale.particleEnergyLimit = std::ldexp(1.0, kEnergySumBits) / double(std::max<std::size_t>(capacity, 1));
}

EnergySums energySums(const gpu::EnergyLedger& ledger) {
  EnergySums sums;
  for (int c = 0; c < 3; ++c) sums.particles[std::size_t(c)] = joinFixed64(ledger.stateLow[c], ledger.stateHigh[c]);
  sums.stepTerm = joinFixed64(ledger.stateLow.w, ledger.stateHigh.w);
  for (int c = 0; c < 4; ++c) sums.flows[std::size_t(c)] = joinFixed64(ledger.flowLow[c], ledger.flowHigh[c]);
  sums.beyondLimit = ledger.counts.x;
  return sums;
}

glm::dvec3 potentialFloorM(const Scene& scene) {
  const glm::dvec3 low = scene.grid.originM;
  const glm::dvec3 high = low + glm::dvec3(scene.grid.cells) * scene.grid.cellSizeM;
  // The corner farthest along gravity: where g · x is largest.
  return {scene.gravityMPerS2.x > 0 ? high.x : low.x, scene.gravityMPerS2.y > 0 ? high.y : low.y,
          scene.gravityMPerS2.z > 0 ? high.z : low.z};
}

double potentialEnergyJ(const glm::dvec3& gravityMPerS2, const glm::dvec3& floorM, double massKg,
                        const glm::dvec3& positionM) {
  return -massKg * glm::dot(gravityMPerS2, positionM - floorM);
}

double arrivingEnergyJ(const Scene& scene, const std::vector<ParticleSeed>& particles) {
  const glm::dvec3 floor = potentialFloorM(scene);
  double energyJ = 0;
  for (const ParticleSeed& particle : particles) {
    const glm::dvec3 v(particle.velocityMPerS);
    energyJ += 0.5 * double(particle.massKg) * glm::dot(v, v) +
               potentialEnergyJ(scene.gravityMPerS2, floor, particle.massKg, glm::dvec3(particle.positionM));
  }
  return energyJ;
}

double rigidBodyKineticEnergyJ(const RigidBody& body, const ObjectPose& pose) {
  const glm::dmat3 turn = glm::mat3_cast(pose.orientation);
  const glm::dvec3 omega = pose.angularVelocityRadPerS;
  return 0.5 * body.massKg * glm::dot(pose.velocityMPerS, pose.velocityMPerS) +
         0.5 * glm::dot(omega, turn * body.inertiaKgM2 * glm::transpose(turn) * omega);
}

EnergyAudit::EnergyAudit(const Scene& scene, const FixedPointScale& scale)
    : rigidBodies_(scene.rigidBodies), gravityMPerS2_(scene.gravityMPerS2), floorM_(potentialFloorM(scene)),
      joulesPerUnit_(1.0 / scale.energyUnitsPerJ),
      wavesPerStep_(stiffestBody(scene).waveSpeedMPerS / scene.grid.cellSizeM),
      waveSpeedSquared_(stiffestBody(scene).waveSpeedMPerS * stiffestBody(scene).waveSpeedMPerS),
      semiImplicit_(scene.solver.semiImplicit()), solverTolerance_(scene.solver.tolerance) {}

std::array<double, 2> EnergyAudit::bodiesEnergyJ(const std::vector<std::optional<ObjectPose>>& bodyPoses) const {
  std::array<double, 2> energyJ{0, 0};
  for (std::size_t b = 0; b < bodyPoses.size() && b < rigidBodies_.size(); ++b) {
    if (!bodyPoses[b]) continue;
    energyJ[0] += rigidBodyKineticEnergyJ(rigidBodies_[b], *bodyPoses[b]);
    energyJ[1] += potentialEnergyJ(gravityMPerS2_, floorM_, rigidBodies_[b].massKg, bodyPoses[b]->positionM);
  }
  return energyJ;
}

void EnergyAudit::start(const EnergySums& sums, const std::vector<std::optional<ObjectPose>>& bodyPoses) {
  account_ = EnergyAccount{};
  account_.sums.particles = sums.particles;
  account_.sums.stepTerm = sums.stepTerm;
  account_.sums.beyondLimit = sums.beyondLimit;
  const std::array<double, 2> bodies = bodiesEnergyJ(bodyPoses);
  account_.bodiesKineticJ = bodies[0];
  account_.bodiesPotentialJ = bodies[1];
  account_.initialJ = budgetOf(account_).totalJ();
  const EnergyBudget budget = budgetOf(account_);
  account_.reference =
      EnergyReference{budget.dissipatedJ + budget.wallsRemovedJ, mechanicalJ(budget), 0.0, 0.0, 0, 0.0};
  pendingArrivalJ_ = 0;
}

EnergyBudget EnergyAudit::budgetOf(const EnergyAccount& account) const {
  EnergyBudget budget;
  budget.stepTermJ = double(account.sums.stepTerm) * joulesPerUnit_;
  budget.kineticJ = double(account.sums.particles[0]) * joulesPerUnit_;
  budget.potentialJ = double(account.sums.particles[1]) * joulesPerUnit_;
  budget.elasticJ = double(account.sums.particles[2]) * joulesPerUnit_;
  budget.bodiesKineticJ = account.bodiesKineticJ;
  budget.bodiesPotentialJ = account.bodiesPotentialJ;
  budget.colliderWorkJ = double(account.sums.flows[0]) * joulesPerUnit_;
  budget.wallsRemovedJ = double(account.sums.flows[1]) * joulesPerUnit_;
  budget.couplingJ = double(account.sums.flows[2]) * joulesPerUnit_;
  budget.hardeningJ = double(account.sums.flows[3]) * joulesPerUnit_;
  budget.arrivedJ = account.arrivedJ;
  budget.createdJ = account.createdJ;
  budget.toleranceJ = account.toleranceJ;
  // The residual is the modified energy's (the energy shown plus the step's term, which an explicit step keeps). What
  // the rigid bodies' explicit coupling made is counted apart, as it is measured: the watchdog judges the energy the
  // snow's own step makes (docs/numerics.md, The rigid bodies' coupling).
  budget.dissipatedJ = account.initialJ + budget.colliderWorkJ + budget.arrivedJ + budget.hardeningJ +
                       budget.couplingJ - budget.wallsRemovedJ - budget.totalJ() - budget.stepTermJ;
  return budget;
}

double quantizationEnergyJ(const FixedPointScale& scale, double momentumUnitKgMPerS, double inverseMassSum) {
  const double quantumKgMPerS = momentumUnitKgMPerS * scale.resolution();
  return 6.75 * quantumKgMPerS * quantumKgMPerS * inverseMassSum;
}

double EnergyAudit::toleranceJ(const EnergyReference& reference, double magnitudeJ, std::size_t particles) const {
  // Float rounding: every energy is a float's few ulps per particle (2^−24 each), and the state it measures is float
  // too: 2^−20 of all that is summed leaves 16 ulps; each particle's values round to the ledger's units; P2G's
  // fixed-point rounding makes what the steps since have summed (quantizationEnergyJ); and a strain of 2^−18 (64 ulps
  // of a float near 1, what F's products and the SVD keep through the steps) in all the particles' mass at the
  // stiffest wave, ½ M c² ε², for the elastic energy of a body at rest is no finer than that.
  const double strainJ = std::ldexp(reference.massKg * waveSpeedSquared_, -37);
  const double roundingJ = std::ldexp(magnitudeJ, -20) + 4.0 * double(particles) * joulesPerUnit_ +
                           reference.quantizationJ + strainJ;
  const double mechanicalJ = reference.mechanicalJ + reference.inputJ;
  if (semiImplicit_) return roundingJ + 2 * double(reference.steps) * solverTolerance_ * mechanicalJ;
  const double theta = wavesPerStep_ * reference.largestDtS;
  if (!(theta < 1)) return roundingJ;
  return roundingJ + 2 * theta / (1 - theta) * mechanicalJ;
}

EnergyAudit::Reading EnergyAudit::read(const EnergySums& frameSums,
                                       const std::vector<std::optional<ObjectPose>>& bodyPoses, std::uint64_t steps,
                                       double largestDtS, double quantizationJ, std::size_t particles,
                                       double massKg) const {
  Reading reading;
  EnergyAccount& next = reading.account;
  next = account_;
  next.sums.particles = frameSums.particles;
  next.sums.stepTerm = frameSums.stepTerm;
  for (std::size_t c = 0; c < 4; ++c) next.sums.flows[c] += frameSums.flows[c];
  next.sums.beyondLimit = frameSums.beyondLimit;
  const std::array<double, 2> bodies = bodiesEnergyJ(bodyPoses);
  next.bodiesKineticJ = bodies[0];
  next.bodiesPotentialJ = bodies[1];
  next.arrivedJ += pendingArrivalJ_;
  const EnergyBudget before = budgetOf(account_);
  const EnergyBudget after = budgetOf(next);

  // The steps since the reference, and what entered meanwhile.
  EnergyReference& reference = next.reference;
  reference.inputJ += std::max(after.colliderWorkJ - before.colliderWorkJ, 0.0) + (after.arrivedJ - before.arrivedJ) +
                      std::max(after.hardeningJ - before.hardeningJ, 0.0) +
                      std::max(after.couplingJ - before.couplingJ, 0.0);
  reference.largestDtS = std::max(reference.largestDtS, largestDtS);
  reference.steps += steps;
  reference.quantizationJ += quantizationJ;
  reference.massKg = massKg;
  // What left the modified energy other than by work, arrivals and hardening: the dissipated energy with what the
  // walls took.
  const double modifiedDissipatedJ = after.dissipatedJ + after.wallsRemovedJ;
  const double createdJ = reference.dissipatedJ - modifiedDissipatedJ;
  const double magnitudeJ = std::abs(after.totalJ()) + std::abs(after.colliderWorkJ) + std::abs(after.wallsRemovedJ) +
                            std::abs(after.arrivedJ) + std::abs(after.hardeningJ) + std::abs(after.couplingJ) +
                            std::abs(after.stepTermJ) + std::abs(account_.initialJ);
  const double toleranceJ = this->toleranceJ(reference, magnitudeJ, particles);
  next.createdJ = createdJ;
  next.toleranceJ = toleranceJ;
  if (frameSums.beyondLimit > 0 || !(createdJ <= toleranceJ)) {
    EnergyCreation creation;
    creation.createdJ = createdJ;
    creation.toleranceJ = toleranceJ;
    creation.kineticJ = after.kineticJ;
    creation.kineticBeforeJ = before.kineticJ;
    creation.couplingJ = after.couplingJ - before.couplingJ;
    creation.beyondLimit = frameSums.beyondLimit;
    reading.creation = creation;
  }
  // The dissipated energy's new greatest: the reference from here.
  if (modifiedDissipatedJ >= reference.dissipatedJ) {
    reference = EnergyReference{modifiedDissipatedJ, mechanicalJ(after), 0.0, 0.0, 0, 0.0, massKg};
  }
  return reading;
}

void packEnergyAccount(const EnergyAccount& account, Checkpoint& checkpoint) {
  const EnergySums& sums = account.sums;
  checkpoint.energyIntegers = {sums.particles[0], sums.particles[1], sums.particles[2], sums.stepTerm,
                               sums.flows[0],     sums.flows[1],     sums.flows[2],     sums.flows[3],
                               std::int64_t(sums.beyondLimit), std::int64_t(account.reference.steps)};
  checkpoint.energyReals = {account.bodiesKineticJ,        account.bodiesPotentialJ,      account.arrivedJ,
                            account.initialJ,              account.reference.dissipatedJ, account.reference.mechanicalJ,
                            account.reference.inputJ,      account.reference.largestDtS,  account.createdJ,
                            account.toleranceJ,            account.reference.quantizationJ, account.reference.massKg};
}

EnergyAccount unpackEnergyAccount(const Checkpoint& checkpoint) {
  const auto& n = checkpoint.energyIntegers;
  const auto& r = checkpoint.energyReals;
  EnergyAccount account;
  account.sums.particles = {n[0], n[1], n[2]};
  account.sums.stepTerm = n[3];
  account.sums.flows = {n[4], n[5], n[6], n[7]};
  account.sums.beyondLimit = std::uint64_t(n[8]);
  account.reference.steps = std::uint64_t(n[9]);
  account.bodiesKineticJ = r[0];
  account.bodiesPotentialJ = r[1];
  account.arrivedJ = r[2];
  account.initialJ = r[3];
  account.reference.dissipatedJ = r[4];
  account.reference.mechanicalJ = r[5];
  account.reference.inputJ = r[6];
  account.reference.largestDtS = r[7];
  account.createdJ = r[8];
  account.toleranceJ = r[9];
  account.reference.quantizationJ = r[10];
  account.reference.massKg = r[11];
  return account;
}

void EnergyAudit::commit(const Reading& reading) {
  account_ = reading.account;
  pendingArrivalJ_ = 0;
}

}  // namespace firn
