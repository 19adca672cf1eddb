#pragma once
// What the GPU watchdog's findings mean to the person running the scene: which step, which particle of which
// body or which grid node, and which key of the scene to change. The watchdog itself is common/watchdog.glsl.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gpu/GpuLayout.h"
#include "scene/Scene.h"
#include "sim/EnergyAudit.h"
#include "sim/FixedPoint.h"
#include "sim/SolveReport.h"

namespace firn {

class GpuState;

// Energy a stretch of steps made from nothing (the energy audit, sim/EnergyAudit.h): steps [firstStep, endStep).
struct EnergyEvent {
  EnergyCreation creation;
  std::uint64_t firstStep = 0;
  std::uint64_t endStep = 0;
};

class Diagnostics {
 public:
  Diagnostics(const Scene& scene, const FixedPointScale& fixedPoint);
  // The scene's materials changed while it runs (Simulation::setMaterials): its elastic bound with them.
  void setMaterials(const Scene& scene);

  // Records the body and material of particles as they are written, in order; forgets those beyond `count`
  // (a restored state holds fewer). Both do nothing once ids are followed: the notes are then fixed.
  void noteParticles(const std::vector<ParticleSeed>& seeds);
  void keepParticles(std::size_t count);
  // With a share of the domain (sim/DomainShare.h): the notes are of all the scene's particles in one process's
  // order, noted at the start, and `ids` gives each of the share's particles its place among them (the messages name
  // a particle by it, as one process would).
  void followIds(const std::vector<std::uint32_t>* ids) { ids_ = ids; }

  // Throws SimulationError (exit 3) listing, in the order they happened, the fixed-point overflows, non-finite
  // values and CFL violations `status` records, a step that needed `blocksNeeded` blocks of the grid when its
  // pool held `blockCapacity` (0: none did), a semi-implicit solve that failed, and energy made from nothing;
  // `state` gives the positions of the particles it names.
  void check(const gpu::WatchdogStatus& status, const GpuState& state, std::size_t blocksNeeded,
             std::size_t blockCapacity, const std::optional<SolverFailure>& solverFailure,
             const std::optional<EnergyEvent>& energy = std::nullopt) const;

 private:
  std::string describeNode(std::int32_t node) const;
  std::string describeParticle(std::int32_t particle, const GpuState& state) const;
  // Why an explicit step went unstable, and the step to use (a non-finite particle, energy made from nothing).
  std::string instabilityCause(const GpuState& state) const;
  // Which material's particles hold the kinetic energy, and the fastest of them.
  std::string energyCarrier(const GpuState& state) const;
  // "; the rigid bodies take the water's mirrored stress explicitly …" in an explicit scene with rigid bodies and water
  // (docs/algorithm.md, Rigid bodies: the coupling's own step bound), naming `bound` as the step they may need to
  // stay below; empty without them.
  std::string rigidBodyHint(const std::string& bound) const;

  GridSpec grid_;
  double dtS_ = 0;
  double stableDtS_ = 0;      // h / c of the stiffest material
  SolverSpec solver_;
  double maxNodeValue_ = 0;   // the fixed-point range of a node sum, in reference masses
  int kernelWidth_ = 4;       // nodes of a particle's stencil per axis
  std::vector<Material> materials_;
  std::vector<Body> bodies_;
  bool imagesBoundTheStep_ = false;    // a fluid's stress mirrored into rigid bodies bounds the step too
                                       // (sim/RigidBodies.h, mirrorsStressIntoBodies)
  std::string fastestCollider_;        // "colliders[i] (… m/s)" when a collider moves, else empty
  std::vector<int> particleBody_;      // body of each particle (−1: added while running)
  std::vector<int> particleMaterial_;  // material of each particle
  const std::vector<std::uint32_t>* ids_ = nullptr;  // with a share: each of its particles' place in the notes

  // The note of (and the name for) GPU particle `particle`; the particles live on the GPU.
  std::size_t noteOf(std::size_t particle) const { return ids_ ? std::size_t((*ids_)[particle]) : particle; }
  std::size_t liveParticles() const { return ids_ ? ids_->size() : particleBody_.size(); }
};

}  // namespace firn
