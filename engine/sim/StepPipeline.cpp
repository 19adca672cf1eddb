#include "sim/StepPipeline.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "Error.h"
#include "sim/EnergyAudit.h"

namespace firn {

gl::ShaderOptions stepShaderOptions(const Scene& scene, MaterialPrograms programs) {
  gl::ShaderOptions options;
  options.defines.emplace_back("FIRN_WALL_CELLS", std::to_string(GridSpec::wallCells));
  options.defines.emplace_back(scene.solver.kernel == Kernel::Cubic ? "FIRN_KERNEL_CUBIC" : "FIRN_KERNEL_QUADRATIC", "1");
  options.defines.emplace_back(scene.solver.transfer == Transfer::Apic ? "FIRN_TRANSFER_APIC" : "FIRN_TRANSFER_PIC_FLIP",
                               "1");
  if (!scene.colliders.empty() || !scene.rigidBodies.empty()) options.defines.emplace_back("FIRN_HAS_COLLIDERS", "1");
  // Distance fields (mesh colliders and bodies) and the bodies' contact probes are read from one buffer texture.
  const bool meshColliders = std::any_of(scene.colliders.begin(), scene.colliders.end(),
                                         [](const Collider& c) { return c.shape == ColliderShape::Mesh; });
  if (meshColliders || !scene.rigidBodies.empty()) options.defines.emplace_back("FIRN_HAS_COLLIDER_FIELDS", "1");
  // The meshes' exact distances (common/shared_functions.h, meshRestDistance) only where a mesh is: llvmpipe runs a
  // scene of analytic bodies 3.6 times slower with that code present, though no branch of it is taken.
  const bool meshBodies = std::any_of(scene.rigidBodies.begin(), scene.rigidBodies.end(),
                                      [](const RigidBody& body) { return body.shape == RigidShape::Mesh; });
  if (meshColliders || meshBodies) options.defines.emplace_back("FIRN_HAS_MESH_SHAPES", "1");
  if (!scene.rigidBodies.empty()) options.defines.emplace_back("FIRN_HAS_RIGID_BODIES", "1");
  if (scene.solver.semiImplicit() && needsSolutionProduct(scene)) options.defines.emplace_back("FIRN_SOLUTION_PRODUCT", "1");
  // Only the material models present are compiled in, and F only where one of them needs it.
  for (const auto& [model, define] : {std::pair{MaterialModel::Snow, "FIRN_MATERIAL_SNOW"},
                                      std::pair{MaterialModel::FixedCorotated, "FIRN_MATERIAL_FIXED_COROTATED"},
                                      std::pair{MaterialModel::NeoHookean, "FIRN_MATERIAL_NEO_HOOKEAN"},
                                      std::pair{MaterialModel::Water, "FIRN_MATERIAL_WATER"},
                                      std::pair{MaterialModel::DruckerPrager, "FIRN_MATERIAL_DRUCKER_PRAGER"}}) {
    const bool present = programs == MaterialPrograms::EveryModel ||
                         std::any_of(scene.materials.begin(), scene.materials.end(),
                                     // A copy: C++17 cannot capture a structured binding (clang refuses).
                                     [model = model](const Material& material) { return material.model == model; });
    if (present) options.defines.emplace_back(define, "1");
  }
  if (needsDeformationGradient(scene, programs)) options.defines.emplace_back("FIRN_HAS_DEFORMATION_GRADIENT", "1");
  if (scene.time.adaptive) options.defines.emplace_back("FIRN_ADAPTIVE_DT", "1");
  if (scene.solver.semiImplicit()) options.defines.emplace_back("FIRN_SEMI_IMPLICIT", "1");
  if (scene.solver.atomics == Atomics::Float) {
    options.defines.emplace_back("FIRN_FLOAT_ATOMICS", "1");
    options.extensions.push_back("GL_NV_shader_atomic_float");
  }
  return options;
}

bool needsSolutionProduct(const Scene& scene) {
  return !scene.rigidBodies.empty() ||
         std::any_of(scene.colliders.begin(), scene.colliders.end(), [](const Collider& collider) {
           return !collider.keyframes.empty() || collider.velocityMPerS != glm::dvec3(0.0);
         });
}

bool needsDeformationGradient(const Scene& scene, MaterialPrograms programs) {
  if (programs == MaterialPrograms::EveryModel) return true;
  return std::any_of(scene.materials.begin(), scene.materials.end(),
                     [](const Material& material) { return material.needsDeformationGradient(); });
}

gpu::StepUniforms stepUniforms(const Scene& scene, const FixedPointScale& fixedPoint, double dtS, double timeS,
                               std::size_t particles, std::uint64_t step) {
  gpu::StepUniforms uniforms{};
  const double h = scene.grid.cellSizeM;
  uniforms.gridOriginM = glm::vec3(scene.grid.originM);
  uniforms.cellSizeM = float(h);
  uniforms.gridNodes = scene.grid.cells + 1;
  uniforms.particleCount = static_cast<std::uint32_t>(particles);
  uniforms.gravityMPerS2 = glm::vec3(scene.gravityMPerS2);
  uniforms.dtS = float(dtS);
  uniforms.timeS = float(timeS);
  uniforms.flipRatio = float(scene.solver.flipRatio);
  // APIC's D_p⁻¹ (Jiang et al. 2015): 4/h² for quadratic, 3/h² for cubic B-splines.
  uniforms.apicInverseInertiaPerM2 = float((scene.solver.kernel == Kernel::Cubic ? 3.0 : 4.0) / (h * h));
  uniforms.stepIndex = static_cast<std::uint32_t>(step);
  // Adaptive steps shrink with speed, so the momentum unit m_ref·h/Δt follows the step taken: a node's velocity
  // in cells per step, which the CFL factor keeps below 1, is what the fixed-point bound assumes.
  const double momentumUnitKgMPerS =
      scene.time.adaptive ? fixedPoint.referenceMassKg * h / dtS : fixedPoint.momentumUnitKgMPerS;
  uniforms.referenceMassKg = float(fixedPoint.referenceMassKg);
  uniforms.momentumUnitKgMPerS = float(momentumUnitKgMPerS);
  // The shaders multiply by these rather than divide (gpu_contract.h): the same bits in every program.
  uniforms.cellsPerM = float(1.0 / h);
  uniforms.massUnitsPerKg = float(1.0 / fixedPoint.referenceMassKg);
  uniforms.momentumUnitsPerKgMPerS = float(1.0 / momentumUnitKgMPerS);
  uniforms.impulseUnitsPerPaM3 = float(-dtS / momentumUnitKgMPerS);
  // The energy audit's (common/energy.glsl, sim/EnergyAudit.h).
  uniforms.potentialFloorM = glm::vec3(potentialFloorM(scene));
  uniforms.energyUnitsPerJ = float(fixedPoint.energyUnitsPerJ);
  uniforms.particleEnergyLimit = float(fixedPoint.particleEnergyLimit);
  uniforms.apicInertiaM2 = float(1.0 / double(uniforms.apicInverseInertiaPerM2));
  uniforms.fixedPointFractionBits = fixedPoint.fractionBits;
  uniforms.colliderCount = static_cast<std::uint32_t>(scene.colliders.size() + scene.rigidBodies.size());
  uniforms.rigidBodyCount = static_cast<std::uint32_t>(scene.rigidBodies.size());
  if (scene.solver.semiImplicit()) {
    uniforms.implicitRatio = float(scene.solver.implicitRatio);
    uniforms.solverToleranceSquared = float(scene.solver.tolerance * scene.solver.tolerance);
    uniforms.solverFractionBits = fixedPoint.solverFractionBits;
  }
  return uniforms;
}

StepPipeline::StepPipeline(const Scene& scene, MaterialPrograms programs, const gl::ContextInfo& gl,
                           const TransferShapeCandidates& candidates)
    : maxWorkGroupsX_(gl.maxComputeWorkGroupCountX) {
  if (scene.solver.atomics == Atomics::Float && !gl.hasFloatAtomics) {
    throw InputError("solver.atomics: \"float\" needs GL_NV_shader_atomic_float, which " + gl.renderer +
                     " does not offer; use \"fixed\"");
  }
  const gl::ShaderOptions options = stepShaderOptions(scene, programs);
  const gl::ShaderLibrary library;
  for (const TransferShape& shape : candidates.shapes) {
    transfers_.emplace_back(shape, library, options, scene.solver.semiImplicit());
  }
  transferShapeForced_ = candidates.forced;
  if (transfers_.size() == 1) {
    TransferShapeChoice only;
    only.shape = only.productShape = transfers_[0].shape();
    only.forced = candidates.forced;
    transferChoice_ = std::move(only);
  }
  updateGrid_ = BlockGrid::StepPass(library, "sim/update_grid.comp", options,
                                    offsetof(gpu::BlockTableHeader, blockDispatch));
  gridToParticle_ = gl::ComputePass(library, "sim/g2p.comp", options);
  computeVolumes_ = gl::ComputePass(library, "sim/compute_volumes.comp", options);
  auditEnergy_ = gl::ComputePass(library, "sim/audit_energy.comp", options);
  if (!scene.rigidBodies.empty()) bodies_.emplace(scene, library, options, maxWorkGroupsX_);
  if (scene.solver.semiImplicit()) implicitSolver_.emplace(scene, library, options);
}

namespace {

// Timed rounds of every shape (fastestOfRounds).
constexpr int kTransferShapeRounds = 3;
// The shapes are timed again when the particles have grown this many times since they were last timed.
constexpr std::size_t kTransferShapeRetimeGrowth = 4;

}  // namespace

BlockGrid::SortFor StepPipeline::sortFor() const {
  if (implicitSolver_ && transfers_[productChosen_].sortFor() == BlockGrid::SortFor::Tiles) {
    return BlockGrid::SortFor::Tiles;
  }
  return transfers_[chosen_].sortFor();
}

void StepPipeline::transferToGrid(GpuState& state, std::size_t particles, gl::PassTimer& timer) const {
  transferToGrid(state, particles, sortFor(), timer);
}

void StepPipeline::transferToGrid(GpuState& state, std::size_t particles, BlockGrid::SortFor sortFor,
                                  gl::PassTimer& timer) const {
  sortAndTransfer(state, particles, sortFor, timer);
  state.bindings().completeWrites();
}

void StepPipeline::sortAndTransfer(GpuState& state, std::size_t particles, BlockGrid::SortFor sortFor,
                                   gl::PassTimer& timer) const {
  state.grid().sortParticles(particles, sortFor, state.bindings(), timer);
  transfers_[chosen_].particleToGrid(state, timer);
}

bool StepPipeline::chooseTransferShape(GpuState& state, std::size_t particles) {
  if (particles == 0 || transfers_.size() == 1) return false;
  if (transferChoice_ && particles < kTransferShapeRetimeGrowth * transferChoice_->particles) return false;
  gl::PassTimer untimed;
  const auto timeOne = [&](std::size_t i) {
    // A round is the sort the shape reads and its P2G, which adds to the sums the sort has just emptied
    // (release_blocks.comp), so every round ends as one transferToGrid would.
    const TransferPasses& transfer = transfers_[i];
    return gl::msToFinish([&] {
      state.grid().sortParticles(particles, transfer.sortFor(), state.bindings(), untimed);
      transfer.particleToGrid(state, untimed);
    });
  };
  const std::vector<double> fastestMs = fastestOfRounds(transfers_.size(), kTransferShapeRounds, timeOne);
  TransferShapeChoice choice;
  choice.forced = transferShapeForced_;
  for (std::size_t i = 0; i < transfers_.size(); ++i) {
    choice.msPerTransfer.emplace_back(transfers_[i].shape(), fastestMs[i]);
  }
  chosen_ = productChosen_ = fastestEntry(choice.msPerTransfer);
  choice.shape = choice.productShape = transfers_[chosen_].shape();
  choice.particles = particles;
  if (implicitSolver_) {
    // The product is timed from the start x₀ the grid update makes of a transfer (every shape's leaves the same
    // grid, to the bit), sorted for tiles too, which the product's tiles read. That grid update pushes the rigid
    // bodies as the step's will, adds the energy its collisions move to the ledger and starts the solve's sums in the
    // bodies' records: the bodies' entries and records and the ledger are put back as they were.
    transferToGrid(state, particles, BlockGrid::SortFor::Tiles, untimed);
    const RigidBodies::Saved bodies = bodies_ ? bodies_->save(state) : RigidBodies::Saved();
    const std::string energy = state.energyRecords();
    state.grid().run(updateGrid_, BlockGrid::SortFor::Tiles, state.bindings(), untimed);
    choice.msPerProduct =
        implicitSolver_->timeProducts(state, particles, maxWorkGroupsX_, transfers_, kTransferShapeRounds);
    productChosen_ = fastestEntry(choice.msPerProduct);
    choice.productShape = transfers_[productChosen_].shape();
    state.bindings().completeWrites();
    if (bodies_) bodies_->restore(state, bodies);
    state.writeEnergyRecords(energy);
  }
  // The chosen shape runs last, so that the grid is its own transfer's (the same sums in any shape).
  transferToGrid(state, particles, untimed);
  transferChoice_ = std::move(choice);
  return true;
}

SolveReport StepPipeline::step(GpuState& state, std::size_t particles, gl::PassTimer& timer, DomainShare* share) const {
  const gl::BufferBindings& buffers = state.bindings();
  sortAndTransfer(state, particles, sortFor(), timer);
  if (share) share->sumSharedNodes(state.grid());  // the nodes' whole sums, where other shares' particles reach too
  if (bodies_) {
    bodies_->afterTransfer(state, share, timer);
    bodies_->beforeGridUpdate(state, share, timer);
  }
  state.grid().run(updateGrid_, sortFor(), buffers, timer);
  if (bodies_) bodies_->afterGridUpdate(state, sortFor(), share, timer);
  SolveReport solve;
  if (implicitSolver_) {
    solve = implicitSolver_->solve(state, particles, maxWorkGroupsX_, transfers_[productChosen_], timer);
    if (bodies_) bodies_->afterSolve(state, timer);
  }
  gridToParticle_.runOver(particles, maxWorkGroupsX_, buffers, timer);
  if (bodies_) bodies_->afterGridToParticle(state, share, timer);
  buffers.completeWrites();  // for what reads the particles next without binding from here: pictures, surfaces
  return solve;
}

void StepPipeline::auditEnergy(GpuState& state, std::size_t particles, bool gridVelocities, gl::PassTimer& timer) const {
  auditEnergy_.set("gridVelocities", gridVelocities ? 1u : 0u).runOver(particles, maxWorkGroupsX_, state.bindings(), timer);
  state.bindings().completeWrites();
}

void StepPipeline::computeVolumes(GpuState& state, std::size_t particles, gl::PassTimer& timer) const {
  computeVolumes_.runOver(particles, maxWorkGroupsX_, state.bindings(), timer);
  state.bindings().completeWrites();
}

}  // namespace firn
