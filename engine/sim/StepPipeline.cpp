#include "sim/StepPipeline.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "Error.h"

namespace firn {

namespace {

constexpr GLbitfield kStorage = GL_SHADER_STORAGE_BARRIER_BIT;
// A pass whose output sizes the next dispatch (glDispatchComputeIndirect) also needs the command barrier.
constexpr GLbitfield kStorageAndCommands = GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT;

}  // namespace

gl::ShaderOptions stepShaderOptions(const Scene& scene, MaterialPrograms programs) {
  gl::ShaderOptions options;
  options.defines.emplace_back("FIRN_WALL_CELLS", std::to_string(GridSpec::wallCells));
  options.defines.emplace_back(scene.solver.kernel == Kernel::Cubic ? "FIRN_KERNEL_CUBIC" : "FIRN_KERNEL_QUADRATIC", "1");
  options.defines.emplace_back(scene.solver.transfer == Transfer::Apic ? "FIRN_TRANSFER_APIC" : "FIRN_TRANSFER_PIC_FLIP",
                               "1");
  if (!scene.colliders.empty()) options.defines.emplace_back("FIRN_HAS_COLLIDERS", "1");
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

bool needsDeformationGradient(const Scene& scene, MaterialPrograms programs) {
  if (programs == MaterialPrograms::EveryModel) return true;
  return std::any_of(scene.materials.begin(), scene.materials.end(),
                     [](const Material& material) { return material.needsDeformationGradient(); });
}

gpu::StepUniforms stepUniforms(const Scene& scene, const FixedPointScale& fixedPoint, double dtS, double timeS,
                               std::size_t particles, std::uint64_t step) {
  gpu::StepUniforms uniforms{};
  const double h = scene.grid.cellSizeM;
  uniforms.gridOriginCellSize = glm::vec4(glm::vec3(scene.grid.originM), float(h));
  uniforms.gridNodes = glm::ivec4(scene.grid.cells + 1, 0);
  uniforms.gravityDt = glm::vec4(glm::vec3(scene.gravityMPerS2), float(dtS));
  // Adaptive steps shrink with speed, so the momentum unit m_ref·h/Δt follows the step taken: a node's velocity
  // in cells per step, which the CFL factor keeps below 1, is what the fixed-point bound assumes.
  const double momentumUnit =
      scene.time.adaptive ? fixedPoint.referenceMassKg * h / dtS : fixedPoint.momentumUnitKgMPerS;
  uniforms.fixedPoint = glm::vec4(float(fixedPoint.referenceMassKg), float(momentumUnit),
                                  float(fixedPoint.unitsPerValue()), float(fixedPoint.resolution()));
  // APIC's D_p⁻¹ (Jiang et al. 2015): 4/h² for quadratic, 3/h² for cubic B-splines.
  const double inverseInertia = (scene.solver.kernel == Kernel::Cubic ? 3.0 : 4.0) / (h * h);
  uniforms.transfer = glm::vec4(float(scene.solver.flipRatio), float(timeS), float(inverseInertia), 0);
  uniforms.counts = glm::uvec4(particles, scene.colliders.size(), static_cast<std::uint32_t>(step), 0);
  if (scene.solver.semiImplicit()) {
    const double unitsPerValue = std::ldexp(1.0, fixedPoint.solverFractionBits);
    uniforms.solver = glm::vec4(float(scene.solver.implicitRatio), float(scene.solver.tolerance * scene.solver.tolerance),
                                float(unitsPerValue), float(1.0 / unitsPerValue));
  }
  return uniforms;
}

StepPipeline::StepPipeline(const Scene& scene, MaterialPrograms programs, const gl::ContextInfo& gl)
    : maxWorkGroupsX_(gl.maxComputeWorkGroupCountX) {
  if (scene.solver.atomics == Atomics::Float && !gl.hasFloatAtomics) {
    throw InputError("solver.atomics: \"float\" needs GL_NV_shader_atomic_float, which " + gl.renderer +
                     " does not offer; use \"fixed\"");
  }
  using Dispatch = ComputePass::Dispatch;
  const gl::ShaderOptions options = stepShaderOptions(scene, programs);
  const gl::ShaderLibrary library;
  prepareBlocks_ = ComputePass(library, "sim/prepare_blocks.comp", options, Dispatch::Once);
  releaseBlocks_ = ComputePass(library, "sim/release_blocks.comp", options, Dispatch::Indirect);
  markBlocks_ = ComputePass(library, "sim/mark_blocks.comp", options, Dispatch::Particles);
  countBlocks_ = ComputePass(library, "sim/count_blocks.comp", options, Dispatch::Once);
  binCount_ = ComputePass(library, "sim/bin_count.comp", options, Dispatch::Particles);
  binScan_ = ComputePass(library, "sim/bin_scan.comp", options, Dispatch::Indirect);
  blockOffsets_ = ComputePass(library, "sim/block_offsets.comp", options, Dispatch::Once);
  binPlace_ = ComputePass(library, "sim/bin_place.comp", options, Dispatch::Particles);
  orderTiles_ = ComputePass(library, "sim/order_tiles.comp", options, Dispatch::Indirect);
  particleToGrid_ = ComputePass(library, "sim/p2g.comp", options, Dispatch::Indirect);
  updateGrid_ = ComputePass(library, "sim/update_grid.comp", options, Dispatch::Indirect);
  gridToParticle_ = ComputePass(library, "sim/g2p.comp", options, Dispatch::Particles);
  computeVolumes_ = ComputePass(library, "sim/compute_volumes.comp", options, Dispatch::Particles);
  if (scene.solver.semiImplicit()) implicitSolver_.emplace(scene, library, options);
}

// The blocks the particles' stencils reach claim slots of the pool (last step's are released first), and the
// particles are sorted by block and base node (common/blocks.glsl).
void StepPipeline::sortParticles(GpuState& state, std::size_t particles, PassTimer& timer) const {
  const gl::Buffer& table = state.blockTableBuffer();
  prepareBlocks_.runOnce(timer);
  glMemoryBarrier(kStorageAndCommands);
  releaseBlocks_.runIndirect(table, offsetof(gpu::BlockTableHeader, releaseDispatch), timer);
  glMemoryBarrier(kStorage);
  markBlocks_.runOverParticles(particles, maxWorkGroupsX_, timer);
  glMemoryBarrier(kStorage);
  countBlocks_.runOnce(timer);
  glMemoryBarrier(kStorageAndCommands);
  binCount_.runOverParticles(particles, maxWorkGroupsX_, timer);
  glMemoryBarrier(kStorage);
  binScan_.runIndirect(table, offsetof(gpu::BlockTableHeader, blockRunDispatch), timer);
  glMemoryBarrier(kStorage);
  blockOffsets_.runOnce(timer);
  glMemoryBarrier(kStorage);
  binPlace_.runOverParticles(particles, maxWorkGroupsX_, timer);
  orderTiles_.runIndirect(table, offsetof(gpu::BlockTableHeader, blockDispatch), timer);
  glMemoryBarrier(kStorageAndCommands);
}

void StepPipeline::transferToGrid(GpuState& state, std::size_t particles, PassTimer& timer) const {
  state.bindAll();
  sortParticles(state, particles, timer);
  particleToGrid_.runIndirect(state.blockTableBuffer(), offsetof(gpu::BlockTableHeader, tileDispatch), timer);
  glMemoryBarrier(kStorage);
}

SolveReport StepPipeline::step(GpuState& state, std::size_t particles, PassTimer& timer) const {
  const std::size_t blockDispatch = offsetof(gpu::BlockTableHeader, blockDispatch);
  transferToGrid(state, particles, timer);
  updateGrid_.runIndirect(state.blockTableBuffer(), blockDispatch, timer);
  glMemoryBarrier(kStorage);
  SolveReport solve;
  if (implicitSolver_) solve = implicitSolver_->solve(state, particles, maxWorkGroupsX_, timer);
  gridToParticle_.runOverParticles(particles, maxWorkGroupsX_, timer);
  glMemoryBarrier(kStorage);
  return solve;
}

void StepPipeline::computeVolumes(GpuState& state, std::size_t particles, PassTimer& timer) const {
  state.bindAll();
  computeVolumes_.runOverParticles(particles, maxWorkGroupsX_, timer);
  glMemoryBarrier(kStorage);
}

}  // namespace firn
