#pragma once
// The step as a list of compute passes in the order of Stomakhin et al. 2013 §6 (docs/algorithm.md): the blocks
// of the grid this step needs and the particles sorted into them (the block grid's own passes, sim/BlockGrid.h);
// particle to grid, and a fluid's stress mirrored into the rigid bodies; the grid update (forces, gravity,
// colliders, walls); grid to particle with the deformation update, plasticity and advection; then the rigid bodies,
// pushed by the snow. The programs are built for the scene: its kernel, transfer, atomics, colliders, rigid bodies
// and material models, and nothing else.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "gl/ComputePass.h"
#include "gl/Context.h"
#include "gpu/GpuLayout.h"
#include "scene/Scene.h"
#include "sim/DomainShare.h"
#include "sim/FixedPoint.h"
#include "sim/GpuState.h"
#include "sim/ImplicitSolver.h"
#include "sim/RigidBodies.h"
#include "sim/TransferPasses.h"
#include "sim/TransferShape.h"

namespace firn {

// Which material models the programs are built for: the scene's (the default: a scene pays only for what it
// uses), or every model with F for all, as one general build would: for measuring what that costs.
enum class MaterialPrograms { SceneModels, EveryModel };

// Whether a semi-implicit step takes the product of its solution after the solve (FIRN_SOLUTION_PRODUCT): its held
// components are the colliders' push on the snow, which rigid bodies take back and moving colliders do work with.
bool needsSolutionProduct(const Scene& scene);

// Whether the scene's particles carry a deformation gradient F (every model but water needs one).
bool needsDeformationGradient(const Scene& scene, MaterialPrograms programs);

// The defines and extensions the step's programs are built with: the scene's kernel, transfer, atomics, colliders,
// material models and integrator.
gl::ShaderOptions stepShaderOptions(const Scene& scene, MaterialPrograms programs);

// The uniform block of one step of `dtS` seconds starting at `timeS`.
gpu::StepUniforms stepUniforms(const Scene& scene, const FixedPointScale& fixedPoint, double dtS, double timeS,
                               std::size_t particles, std::uint64_t step);

class StepPipeline {
 public:
  // The transfers take the shapes of `candidates` (sim/TransferShape.h), the fastest of them once timed
  // (chooseTransferShape). Throws InputError when the scene asks for what the driver lacks (float atomics).
  StepPipeline(const Scene& scene, MaterialPrograms programs, const gl::ContextInfo& gl,
               const TransferShapeCandidates& candidates);

  // Steps 1–2 of §6: the grid's blocks for this step and the particles sorted into them (BlockGrid), then particle
  // to grid in the chosen shape.
  void transferToGrid(GpuState& state, std::size_t particles, gl::PassTimer& timer) const;
  // The same with the sort `sortFor` asks (the tiles for a tile product while P2G runs by blocks).
  void transferToGrid(GpuState& state, std::size_t particles, BlockGrid::SortFor sortFor, gl::PassTimer& timer) const;
  // Times P2G in each shape this scene can take (sim/TransferShape.h) on the particles in `state`, each with the
  // sort it reads, and runs the fastest from then on; with one shape (the only one named, or float sums)
  // there is nothing to time. Times them once a run has particles (a scene of emitters: at its first), and again each
  // time its particles have grown fourfold since (the faster shape can change with the count). A semi-implicit scene's
  // Hessian product is timed in each shape too, on its own, and may take another. Returns whether it timed them now.
  // Leaves the grid as transferToGrid does.
  bool chooseTransferShape(GpuState& state, std::size_t particles);
  // The choice, once made.
  const std::optional<TransferShapeChoice>& transferShapeChoice() const { return transferChoice_; }
  // One whole step: transferToGrid, the shared nodes' sums completed (with a `share`), the bodies' mirrored stress,
  // the grid update, the semi-implicit solve if the scene asks for one, grid to particle, the rigid bodies. With a
  // `share`, each body's sums are summed over the shares before a pass reads them. Returns how the solve ended
  // (explicit steps: no iterations).
  SolveReport step(GpuState& state, std::size_t particles, gl::PassTimer& timer, DomainShare* share = nullptr) const;
  // The semi-implicit solve, if the scene has one, and the transfers' shapes in the order they were given (tests
  // reach their passes through them).
  const ImplicitSolver* implicitSolver() const { return implicitSolver_ ? &*implicitSolver_ : nullptr; }
  const std::vector<TransferPasses>& transfers() const { return transfers_; }
  // The rigid bodies' part, if the scene has bodies.
  const RigidBodies* rigidBodies() const { return bodies_ ? &*bodies_ : nullptr; }
  // The initial volumes V0 = m / ρ_grid (§6 step 2), after a transferToGrid of the first particles.
  void computeVolumes(GpuState& state, std::size_t particles, gl::PassTimer& timer) const;
  // The energy audit's sums over the particles into the ledger (audit_energy.comp; sim/EnergyAudit.h); with
  // `gridVelocities` (the grid holds the last step's velocities) also the explicit step's term.
  void auditEnergy(GpuState& state, std::size_t particles, bool gridVelocities, gl::PassTimer& timer) const;

 private:
  // The sort the step's transfers read: for tiles where P2G or the Hessian product runs by tiles.
  BlockGrid::SortFor sortFor() const;
  // transferToGrid's passes, their last writes left to the barriers of the passes that follow.
  void sortAndTransfer(GpuState& state, std::size_t particles, BlockGrid::SortFor sortFor, gl::PassTimer& timer) const;

  int maxWorkGroupsX_ = 65535;
  // The transfers in each shape the run was given, P2G's shape and the Hessian product's.
  std::vector<TransferPasses> transfers_;
  std::size_t chosen_ = 0;
  std::size_t productChosen_ = 0;
  bool transferShapeForced_ = false;
  std::optional<TransferShapeChoice> transferChoice_;
  BlockGrid::StepPass updateGrid_;
  gl::ComputePass gridToParticle_;
  gl::ComputePass computeVolumes_;
  gl::ComputePass auditEnergy_;
  std::optional<RigidBodies> bodies_;  // scenes with rigid bodies
  std::optional<ImplicitSolver> implicitSolver_;
};

}  // namespace firn
