#pragma once
// The semi-implicit solve of a step (Stomakhin et al. 2013 §6, eq. 9; docs/algorithm.md "Semi-implicit steps"):
// between the grid update, which leaves the explicit velocities v* on the grid, and G2P, it replaces them with the
// solution of (M + β Δt² H) v = M v* by the conjugate residual method, preconditioned with M⁻¹, matrix-free on the
// GPU (common/solver.glsl). The host dispatches the iterations and looks at the residual every few of them; the GPU
// stops doing work once it is below the tolerance.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec4.hpp>

#include "gl/ShaderLibrary.h"
#include "scene/Scene.h"
#include "sim/ComputePass.h"
#include "sim/GpuState.h"

namespace firn {

// How a step's solve ended.
struct SolveReport {
  int iterations = 0;   // conjugate residual iterations taken
  double residual = 0;  // the relative residual at the end, ‖r‖ / ‖M v*‖ in the M⁻¹ norm (NaN if it became non-finite)
  bool converged = true;  // whether it reached the tolerance within max_iterations
};

// A solve that ends above this many times its tolerance is a failure the watchdog reports (exit 3): the velocities
// are off by more than a hundredth of the tolerance's reference, and the step is no longer the one asked for.
constexpr double kSolverFailureFactor = 100;

// The first solve that failed, and in which step.
struct SolverFailure {
  std::uint64_t step = 0;
  SolveReport report;
};

// How a Hessian product takes the stress's change: its differential ∂²Ψ/∂F² : δF (the solve's), or, for tests,
// the central difference (P(F + δF) − P(F − δF)) / 2 of the stress the explicit force comes from.
enum class HessianProduct { Differential, ForceDifference };

class ImplicitSolver {
 public:
  // The iterations between two looks at the residual: each look waits for the GPU, and the iterations dispatched
  // after convergence cost nothing.
  static constexpr int checkInterval = 4;

  // `options` are the step's shader options (stepShaderOptions), FIRN_SEMI_IMPLICIT among them.
  ImplicitSolver(const Scene& scene, const gl::ShaderLibrary& library, const gl::ShaderOptions& options);

  // Replaces v* on the grid with the solution. The state's buffers must be bound (StepPipeline binds them).
  SolveReport solve(const GpuState& state, std::size_t particles, int maxWorkGroupsX, PassTimer& timer) const;

  // Test hooks (Simulation::hessianProduct): the per-particle preparation and one Hessian product of the solve's
  // vector z (SolverNode::preconditioned), leaving its sums in the product buffer.
  void prepare(std::size_t particles, int maxWorkGroupsX, PassTimer& timer) const;
  void productOfPreconditioned(const GpuState& state, HessianProduct product, PassTimer& timer) const;

 private:
  // The end of the solve in the registers read, if it is there: the first iteration whose residual met the tolerance.
  bool findEnd(const std::vector<glm::vec4>& registers, SolveReport& report) const;
  void reduce(const GpuState& state, unsigned registerIndex, unsigned components, PassTimer& timer) const;

  double toleranceSquared_;
  int maxIterations_;
  gl::ShaderOptions options_;
  mutable std::optional<ComputePass> forceDifferenceProduct_;  // built when a test first asks for it
  ComputePass prepare_;
  ComputePass begin_;
  ComputePass product_;
  ComputePass residual_;
  ComputePass apply_;
  ComputePass direction_;
  ComputePass update_;
  ComputePass reduce_;
  ComputePass finish_;
};

}  // namespace firn
