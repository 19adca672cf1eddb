#pragma once
// The semi-implicit solve of a step (Stomakhin et al. 2013 §6, eq. 9; docs/algorithm.md "Semi-implicit steps"):
// between the grid update, which leaves the explicit velocities v* on the grid, and G2P, it replaces them with the
// solution of (M + β Δt² H) v = M v* by the conjugate residual method with the block Jacobi preconditioner (each
// node's 3×3 block of M + β Δt² H), matrix-free on the GPU (common/solver.glsl). The host dispatches the iterations
// and looks at the residual every few of them; the GPU stops doing work once it is below the tolerance.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec4.hpp>

#include "gl/ShaderLibrary.h"
#include "scene/Scene.h"
#include "gl/ComputePass.h"
#include "sim/GpuState.h"
#include "sim/SolveReport.h"

namespace firn {

// How a Hessian product takes the stress's change: its differential ∂²Ψ/∂F² : δF with the stiffness projected onto
// the positive semi-definite (the solve's), or, for tests, the differential as it is, or the central difference
// (P(F + δF) − P(F − δF)) / 2 of the stress the explicit force comes from.
enum class HessianProduct { Differential, Unprojected, ForceDifference };

class ImplicitSolver {
 public:
  // The iterations between two looks at the residual: each look waits for the GPU, and the iterations dispatched
  // after convergence cost nothing.
  static constexpr int checkInterval = 4;

  // `options` are the step's shader options (stepShaderOptions), FIRN_SEMI_IMPLICIT among them.
  ImplicitSolver(const Scene& scene, const gl::ShaderLibrary& library, const gl::ShaderOptions& options);

  // Replaces v* on the grid with the solution. The state's buffers must be bound (StepPipeline binds them).
  SolveReport solve(const GpuState& state, std::size_t particles, int maxWorkGroupsX, gl::PassTimer& timer) const;

  // Test hooks (Simulation::hessianProduct, Simulation::stiffnessBlocks): the preparation for a product of that kind
  // (the bins' order by index and each particle's stiffness), and the product of the solve's vector z
  // (SolverNode::preconditioned), leaving its sums in the solver's nodes.
  void prepare(const GpuState& state, std::size_t particles, int maxWorkGroupsX, gl::PassTimer& timer,
               HessianProduct product = HessianProduct::Differential) const;
  void productOfPreconditioned(const GpuState& state, HessianProduct product, gl::PassTimer& timer) const;
  // And the first product of a step, which also sums each node's stiffness block (SolverNode::diagonalLow …).
  void firstProduct(const GpuState& state, gl::PassTimer& timer) const;

 private:
  // The solve's end after `iterations`: the residual register it ended at, relative to the reference.
  static SolveReport report(const GpuState& state, int iterations);
  void reduce(const GpuState& state, unsigned registerIndex, unsigned components, gl::PassTimer& timer) const;

  int maxIterations_;
  gl::ShaderOptions options_;
  // Built when a test first asks for them.
  mutable std::optional<gl::ComputePass> unprojectedPrepare_;
  mutable std::optional<gl::ComputePass> forceDifferenceProduct_;
  gl::ComputePass orderBins_;
  gl::ComputePass prepare_;
  gl::ComputePass begin_;
  gl::ComputePass firstProduct_;  // FIRN_SOLVER_FIRST_PRODUCT: of the start, with the stiffness blocks
  gl::ComputePass product_;
  gl::ComputePass residual_;
  gl::ComputePass apply_;
  gl::ComputePass step_;
  gl::ComputePass reduce_;
  gl::ComputePass finish_;
};

}  // namespace firn
