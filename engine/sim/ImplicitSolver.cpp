#include "sim/ImplicitSolver.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "gpu/GpuLayout.h"
#include "sim/StepPipeline.h"

namespace firn {

namespace {

// The registers' components (gpu::SolverStatus): bits of solver_reduce.comp's reduceComponents.
constexpr unsigned kProduct = 1;           // x: (z, A z)
constexpr unsigned kDirectionProduct = 2;  // y: (A p, P⁻¹ A p), formed from (A z, P⁻¹ A z) and (A z, P⁻¹ A p') in w
constexpr unsigned kResidual = 4;          // z: (r, P⁻¹ r)
constexpr unsigned kReference = 8;         // w: (M v*, (M + β Δt² Hᵢᵢ)⁻¹ M v*)

constexpr std::size_t kBlockDispatch = offsetof(gpu::SolverStatus, solveBlockDispatch);
constexpr std::size_t kReduceDispatch = offsetof(gpu::SolverStatus, solveReduceDispatch);

static_assert(SolverSpec::maxIterationsAllowed == gpu::SOLVER_MAX_ITERATIONS, "the scene's limit is the GPU's");

}  // namespace

ImplicitSolver::ImplicitSolver(const Scene& scene, const gl::ShaderLibrary& library, const gl::ShaderOptions& options)
    : maxIterations_(scene.solver.maxIterations) {
  prepare_ = gl::ComputePass(library, "sim/solver_prepare.comp", options);
  begin_ = gl::ComputePass(library, "sim/solver_begin.comp", options);
  residual_ = gl::ComputePass(library, "sim/solver_residual.comp", options);
  apply_ = gl::ComputePass(library, "sim/solver_apply.comp", options);
  step_ = gl::ComputePass(library, "sim/solver_step.comp", options);
  reduce_ = gl::ComputePass(library, "sim/solver_reduce.comp", options);
  finish_ = gl::ComputePass(library, "sim/solver_finish.comp", options);
  if (needsSolutionProduct(scene)) solution_ = gl::ComputePass(library, "sim/solver_solution.comp", options);
  bodyCount_ = scene.rigidBodies.size();
  if (bodyCount_ > 0) {
    bodies_ = BodyPasses{gl::ComputePass(library, "sim/solver_bodies_residual.comp", options),
                         gl::ComputePass(library, "sim/solver_bodies_apply.comp", options),
                         gl::ComputePass(library, "sim/solver_bodies_step.comp", options),
                         gl::ComputePass(library, "sim/solver_bodies_finish.comp", options)};
  }
}

void ImplicitSolver::prepare(const GpuState& state, std::size_t particles, int maxWorkGroupsX,
                             gl::PassTimer& timer) const {
  prepare_.runOver(particles, maxWorkGroupsX, state.bindings(), timer);
}

void ImplicitSolver::reduce(const GpuState& state, unsigned registerIndex, unsigned components, gl::PassTimer& timer) const {
  reduce_.set("reduceRegister", registerIndex)
      .set("reduceComponents", components)
      .runIndirect(state.solver()->status(), kReduceDispatch, state.bindings(), timer);
}

SolveReport ImplicitSolver::report(const GpuState& state, int iterations) {
  // The reference is register 0's; the residual the last one's. The rest stay on the GPU.
  const double reference = state.solver()->readRegister(0).w;
  const double residual = state.solver()->readRegister(std::size_t(iterations)).z;
  SolveReport report;
  report.iterations = iterations;
  if (std::isnan(residual) || std::isnan(reference)) {
    report.residual = std::numeric_limits<double>::quiet_NaN();
  } else {
    // A zero reference (no mass moving) leaves nothing to solve.
    report.residual = reference > 0 ? std::sqrt(std::max(residual, 0.0) / reference) : 0.0;
  }
  return report;
}

std::vector<std::pair<TransferShape, double>> ImplicitSolver::timeProducts(const GpuState& state,
                                                                           std::size_t particles, int maxWorkGroupsX,
                                                                           const std::vector<TransferPasses>& shapes,
                                                                           int rounds) const {
  const gl::Buffer& status = state.solver()->status();
  const gl::BufferBindings& buffers = state.bindings();
  gl::PassTimer untimed;
  begin_.runOnce(buffers, untimed);
  prepare(state, particles, maxWorkGroupsX, untimed);
  const std::vector<double> fastestMs = fastestOfRounds(shapes.size(), rounds, [&](std::size_t i) {
    const double ms =
        gl::msToFinish([&] { shapes[i].productInSolve(TransferPasses::Product::First, state, untimed); });
    residual_.runIndirect(status, kBlockDispatch, buffers, untimed);  // takes the product's sums
    return ms;
  });
  std::vector<std::pair<TransferShape, double>> timed;
  for (std::size_t i = 0; i < shapes.size(); ++i) timed.emplace_back(shapes[i].shape(), fastestMs[i]);
  return timed;
}

SolveReport ImplicitSolver::solve(const GpuState& state, std::size_t particles, int maxWorkGroupsX,
                                  const TransferPasses& product, gl::PassTimer& timer) const {
  const gl::Buffer& status = state.solver()->status();
  const gl::BufferBindings& buffers = state.bindings();
  begin_.runOnce(buffers, timer);
  prepare(state, particles, maxWorkGroupsX, timer);
  // r₀ = S (M v* − A x₀) from the start x₀ with the nodes' stiffness blocks, the block preconditioner, and the
  // reference (M v*, (M + β Δt² Hᵢᵢ)⁻¹ M v*).
  product.productInSolve(TransferPasses::Product::First, state, timer);
  residual_.runIndirect(status, kBlockDispatch, buffers, timer);
  if (bodies_) bodies_->residual.runIndirect(status, kReduceDispatch, buffers, timer);
  reduce(state, 0, kResidual | kReference, timer);

  // Where the GPU ended the solve (solver_reduce.comp): 1 + the register of the residual that met the tolerance.
  std::uint32_t end = 0;
  for (int k = 0; k < maxIterations_ && end == 0; ++k) {
    const unsigned iteration = static_cast<unsigned>(k);
    product.productInSolve(TransferPasses::Product::Iteration, state, timer);
    apply_.set("iteration", iteration).runIndirect(status, kBlockDispatch, buffers, timer);
    if (bodies_) bodies_->apply.set("iteration", iteration).runIndirect(status, kReduceDispatch, buffers, timer);
    reduce(state, iteration, kProduct | kDirectionProduct, timer);
    if (bodies_) bodies_->step.set("iteration", iteration).runIndirect(status, kReduceDispatch, buffers, timer);
    step_.set("iteration", iteration).runIndirect(status, kBlockDispatch, buffers, timer);
    reduce(state, iteration + 1, kResidual, timer);
    if ((k + 1) % checkInterval == 0 || k + 1 == maxIterations_) end = state.solver()->readEnd();
  }
  // Not ended: max_iterations were taken, and the last residual is the solve's.
  const SolveReport solved = report(state, end > 0 ? int(end) - 1 : maxIterations_);
  const gl::Buffer& blockTable = state.grid().blockTable();
  if (bodies_) bodies_->finish.runOver(bodyCount_, maxWorkGroupsX, buffers, timer);
  if (solution_) {
    // The product of the solution, whose held components are the colliders' push that the rigid bodies take back and
    // the moving colliders do work with (solver_finish.comp). The iterations' dispatches may be emptied by now: the block table's are the step's.
    solution_->runIndirect(blockTable, offsetof(gpu::BlockTableHeader, blockDispatch), buffers, timer);
    product.productOverGrid(state, timer);
  }
  finish_.runIndirect(blockTable, offsetof(gpu::BlockTableHeader, blockDispatch), buffers, timer);
  return solved;
}

}  // namespace firn
