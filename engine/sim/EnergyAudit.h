#pragma once
// The energy audit (docs/numerics.md, "The energy audit"): every run's energy budget, from its own numbers. In a
// closed scene MPM's transfers, plasticity and collisions only remove energy, so energy that appears from nowhere is
// the signature of an unstable step, and the energy removed is the price of the transfer and the step chosen. Once a
// frame the GPU sums what the particles hold (audit_energy.comp); the steps sum what the moving colliders, the domain
// walls and the rigid bodies' coupling move in and out (common/energy.glsl); the host adds the rigid bodies' own
// energy and what arrives with emitted particles, keeps the account from the start, and says when a frame made
// energy beyond what float rounding and the step's truncation allow.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gpu/GpuLayout.h"
#include "scene/Scene.h"
#include "scene/SceneObjects.h"
#include "sim/FixedPoint.h"

namespace firn {

struct Checkpoint;

// Sets the energy ledger's scale (FixedPointScale::energyUnitsPerJ and particleEnergyLimit) for a scene, its seeds
// and the particle capacity of the run: a particle's energy is bounded, in a stable run, by
// e = m_ref ((h / Δt)² + c² + 2 |g| L + v²) — the kinetic energy of a particle moving a cell per step, the elastic
// energy of a wave's strain of order one, a fall across the domain's diagonal L, the fastest seed or collider — so the
// whole scene's by capacity × e, which is given 2^54 units: 2^−54 of it resolved, and 2^8 times it before a sum leaves
// 64 bits. No particle may hold more than 2^62 / capacity units (2^8 e) in a sum: one that does is left out and
// counted (EnergySums::beyondLimit), which the audit reports as energy beyond any stable step.
void deriveEnergyScale(FixedPointScale& scale, const Scene& scene, const std::vector<ParticleSeed>& seeds,
                       std::size_t capacity);

// The ledger's sums as integers in its units (gpu::EnergyLedger).
struct EnergySums {
  std::array<std::int64_t, 3> particles{};  // kinetic, potential, elastic: audit_energy.comp's
  std::int64_t stepTerm = 0;                // −(Δt/2) Σ V⁰ τ : ∇v: the modified energy's difference (explicit steps)
  // The moving colliders' work, what the walls removed, what the coupling gave, what snow's hardening gave.
  std::array<std::int64_t, 4> flows{};
  std::uint64_t beyondLimit = 0;            // values left out: beyond particleEnergyLimit, or not finite
};
EnergySums energySums(const gpu::EnergyLedger& ledger);

// The gravitational potential energy −m g · (x − floor) of a mass at x, above the domain's floor: the point of the
// domain lowest along gravity (its origin where gravity points down its axes), where every particle's is ≥ 0.
glm::dvec3 potentialFloorM(const Scene& scene);
double potentialEnergyJ(const glm::dvec3& gravityMPerS2, const glm::dvec3& floorM, double massKg,
                         const glm::dvec3& positionM);

// What enters the simulation with a particle that joins it (an emitter's, or one thrown in the viewer): its kinetic
// and potential energy (it joins undeformed, with C = 0).
double arrivingEnergyJ(const Scene& scene, const std::vector<ParticleSeed>& particles);

// A rigid body's kinetic energy ½ M |V|² + ½ ω · (R I Rᵀ ω) at `pose`, and its potential energy.
double rigidBodyKineticEnergyJ(const RigidBody& body, const ObjectPose& pose);

// The audit whose dissipated energy is the greatest so far: what the energy made from nothing is measured from
// (EnergyAudit::toleranceJ says why).
struct EnergyReference {
  double dissipatedJ = 0;   // the dissipated energy with the walls'
  double mechanicalJ = 0;   // the kinetic and elastic energy there, the bodies' kinetic energy with it
  double inputJ = 0;        // what entered since: positive work, arrivals, hardening, the coupling's
  double largestDtS = 0;    // the largest step since
  std::uint64_t steps = 0;  // the steps since
  double quantizationJ = 0; // what P2G's fixed-point rounding can have made since (quantizationEnergyJ)
  double massKg = 0;        // the particles' mass at the latest audit since
};

// The run's energy account: what the particles hold at the last audit, what entered and left since the start (the
// ledger's sums, kept as integers, so that a resumed run goes on to the same bits: checkpoints carry the account),
// the rigid bodies' energy, reckoned on the host from their poses, and the reference of the energy made from nothing.
struct EnergyAccount {
  EnergySums sums;              // particles: at the last audit; flows: since the start
  double bodiesKineticJ = 0;    // at the last audit
  double bodiesPotentialJ = 0;
  double arrivedJ = 0;          // since the start: what joined with emitted particles, thrown particles and bodies
  double initialJ = 0;          // the particles' and the bodies' at the start
  EnergyReference reference;
  double createdJ = 0;          // at the last audit: the energy made from nothing since the reference
  double toleranceJ = 0;        // and what the watchdog allowed (EnergyAudit::toleranceJ)
};

// stats.csv's energy columns (J) at an audit: what the particles and bodies hold, and what entered and left since
// the start. The dissipated energy is the residual, initial + work + arrived + hardening + coupling − walls − now − the
// step's term: ≥ 0 in a stable run (docs/numerics.md states what it holds for each transfer and integrator). What the
// rigid bodies' explicit coupling made (`couplingJ`) is energy from nothing too, but the coupling's own, measured apart:
// the watchdog judges what the snow's step makes.
struct EnergyBudget {
  double kineticJ = 0;
  double potentialJ = 0;
  double elasticJ = 0;
  double bodiesKineticJ = 0;
  double bodiesPotentialJ = 0;
  double colliderWorkJ = 0;
  double arrivedJ = 0;
  double wallsRemovedJ = 0;
  double couplingJ = 0;
  double hardeningJ = 0;
  double dissipatedJ = 0;
  // The explicit step's term −(Δt/2) Σ V⁰ τ : ∇v: the energy shown plus it is the modified energy the step keeps.
  double stepTermJ = 0;
  // The energy made from nothing since the reference (the audit whose modified energy's dissipation was greatest),
  // and what the watchdog allows it: a run stops when the first passes the second.
  double createdJ = 0;
  double toleranceJ = 0;

  double totalJ() const { return kineticJ + potentialJ + elasticJ + bodiesKineticJ + bodiesPotentialJ; }
};

// The energy made from nothing since the reference, where that is more than its tolerance allows: the watchdog's
// event (sim/Diagnostics.h).
struct EnergyCreation {
  double createdJ = 0;      // the growth beyond what entered since the reference: its fall in the dissipated energy
  double toleranceJ = 0;    // float rounding and the step's truncation (EnergyAudit::toleranceJ)
  double kineticJ = 0;      // the particles' kinetic energy then, and at the frame's start
  double kineticBeforeJ = 0;
  double couplingJ = 0;     // besides: what the rigid bodies' explicit coupling made over the frame, counted apart
  std::uint64_t beyondLimit = 0;  // particles or flows beyond the scene's bound (EnergySums::beyondLimit)
};

// What one step's P2G rounding to fixed point can make (J): dithered rounding gives each contribution an error of
// mean 0 and variance q²/6 (q = 2^−k of the momentum unit m_ref h / Δt), which a particle alone at its nodes takes back
// whole from all 27 of them (quadratic; the cubic kernel's 64 nodes share more particles): its velocity's error has a
// variance of 3 × 27/6 q² / m², and its kinetic energy gains half of that times m on average, 6.75 q² / m — a
// systematic gain, though the rounding is unbiased, since the error's square is never negative. Summed over the
// particles: `inverseMassSum` is Σ 1/m. Far smaller than anything else for particles of the reference mass at a
// few per cell; what a sprinkle of light particles makes.
double quantizationEnergyJ(const FixedPointScale& scale, double momentumUnitKgMPerS, double inverseMassSum);

// The account as a checkpoint carries it (Checkpoint::energyIntegers, energyReals), and back.
void packEnergyAccount(const EnergyAccount& account, Checkpoint& checkpoint);
EnergyAccount unpackEnergyAccount(const Checkpoint& checkpoint);

class EnergyAudit {
 public:
  EnergyAudit(const Scene& scene, const FixedPointScale& scale);

  // An audit's reading: the account it would make if its frame is accepted, and the energy its frame made beyond the
  // tolerance, if it did. `frameSums` are the ledger's (all shares' summed): the particles' energy now and the
  // frame's flows; `bodyPoses` every rigid body's pose (none parked: a parked body is outside the simulation);
  // `steps` and `largestDtS` the steps since the last reading and the largest of them, `quantizationJ` what their
  // fixed-point rounding can have made (quantizationEnergyJ); `particles` and `massKg` the particles in the run (all
  // shares').
  struct Reading {
    EnergyAccount account;
    std::optional<EnergyCreation> creation;
  };
  Reading read(const EnergySums& frameSums, const std::vector<std::optional<ObjectPose>>& bodyPoses,
               std::uint64_t steps, double largestDtS, double quantizationJ, std::size_t particles,
               double massKg) const;
  // The first reading, of the initial state: the account's start.
  void start(const EnergySums& sums, const std::vector<std::optional<ObjectPose>>& bodyPoses);
  // Energy that joined during the frame (arrivingEnergyJ, a launched body's), part of the next reading.
  void noteArrival(double energyJ) { pendingArrivalJ_ += energyJ; }
  double pendingArrivalJ() const { return pendingArrivalJ_; }
  void setPendingArrivalJ(double energyJ) { pendingArrivalJ_ = energyJ; }
  // The frame is accepted: its reading becomes the account.
  void commit(const Reading& reading);

  const EnergyAccount& account() const { return account_; }
  void setAccount(const EnergyAccount& account) { account_ = account; }
  EnergyBudget budget() const { return budgetOf(account_); }
  double joulesPerUnit() const { return joulesPerUnit_; }

  // What the steps since `reference` may make from nothing and still be stable (docs/numerics.md, The energy audit):
  // the float rounding of `magnitudeJ` (the energies summed), of the `particles`' values and of their strain, and the
  // step's truncation: an explicit step's energy can grow by 2θ / (1 − θ) of the mechanical energy and what entered,
  // θ its Courant number c Δt / h (none at θ ≥ 1); a semi-implicit step's, by its solve's tolerance twice a step.
  double toleranceJ(const EnergyReference& reference, double magnitudeJ, std::size_t particles) const;

 private:
  EnergyBudget budgetOf(const EnergyAccount& account) const;
  // The bodies' energy at `bodyPoses`: kinetic, potential.
  std::array<double, 2> bodiesEnergyJ(const std::vector<std::optional<ObjectPose>>& bodyPoses) const;

  std::vector<RigidBody> rigidBodies_;
  glm::dvec3 gravityMPerS2_;
  glm::dvec3 floorM_;
  double joulesPerUnit_ = 0;
  double wavesPerStep_ = 0;           // c / h of the stiffest material: θ = c Δt / h
  double waveSpeedSquared_ = 0;       // c², m²/s²
  bool semiImplicit_ = false;
  double solverTolerance_ = 0;
  EnergyAccount account_;
  double pendingArrivalJ_ = 0;
};

}  // namespace firn
