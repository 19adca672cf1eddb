#pragma once
// The semi-implicit solve of a step (Stomakhin et al. 2013 §6, eq. 9; docs/algorithm.md "Semi-implicit steps"):
// between the grid update, which leaves the explicit velocities v* on the grid, and G2P, it replaces them with the
// solution of (M + β Δt² H) v = M v* by the conjugate residual method with the block Jacobi preconditioner (each
// node's 3×3 block of M + β Δt² H), matrix-free on the GPU (common/solver.glsl). The host dispatches the iterations
// and looks at the residual every few of them; the GPU stops doing work once it is below the tolerance.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include <glm/vec4.hpp>

#include "gl/ComputePass.h"
#include "gl/ShaderLibrary.h"
#include "scene/Scene.h"
#include "sim/GpuState.h"
#include "sim/SolveReport.h"
#include "sim/TransferPasses.h"

namespace firn {

class ImplicitSolver {
 public:
  // The iterations between two looks at the residual: each look waits for the GPU, and the iterations dispatched
  // after convergence cost nothing.
  static constexpr int checkInterval = 4;

  // `options` are the step's shader options (stepShaderOptions), FIRN_SEMI_IMPLICIT among them. The Hessian
  // product is the transfer shape's (sim/TransferPasses.h), which the step gives each solve.
  ImplicitSolver(const Scene& scene, const gl::ShaderLibrary& library, const gl::ShaderOptions& options);

  // Replaces v* on the grid with the solution, the Hessian products by `product`. The state's buffers must be bound
  // (StepPipeline binds them).
  SolveReport solve(const GpuState& state, std::size_t particles, int maxWorkGroupsX, const TransferPasses& product,
                    gl::PassTimer& timer) const;
  // Times the step's first Hessian product by each of `shapes` (fastestOfRounds, `rounds` timed), on the grid the
  // grid update has just left (its start x₀). Each product's sums are taken by the residual pass after it, so
  // nothing carries into the next solve but the rigid bodies' sums (RigidBodies::restore puts their records back).
  // Returns each shape's time (ms), in their order.
  std::vector<std::pair<TransferShape, double>> timeProducts(const GpuState& state, std::size_t particles,
                                                             int maxWorkGroupsX,
                                                             const std::vector<TransferPasses>& shapes,
                                                             int rounds) const;


 private:
  friend class SimulationProbe;  // the solver's tests (tests/support/SimulationProbe.h) run its passes one by one

  // Each particle's stiffness (solver_prepare.comp).
  void prepare(const GpuState& state, std::size_t particles, int maxWorkGroupsX, gl::PassTimer& timer) const;
  // The solve's end after `iterations`: the residual register it ended at, relative to the reference.
  static SolveReport report(const GpuState& state, int iterations);
  void reduce(const GpuState& state, unsigned registerIndex, unsigned components, gl::PassTimer& timer) const;

  int maxIterations_;
  gl::ComputePass prepare_;
  gl::ComputePass begin_;
  gl::ComputePass residual_;
  gl::ComputePass apply_;
  gl::ComputePass step_;
  gl::ComputePass reduce_;
  gl::ComputePass finish_;
  // With rigid bodies: the solution into z, for a last product of it (solver_solution.comp).
  std::optional<gl::ComputePass> solution_;
  // With rigid bodies: their six velocities as unknowns of the solve (common/solver_bodies.glsl), started, multiplied
  // and stepped after the nodes' passes of the same name, and given to the bodies' entries at the end.
  struct BodyPasses {
    gl::ComputePass residual;
    gl::ComputePass apply;
    gl::ComputePass step;
    gl::ComputePass finish;
  };
  std::optional<BodyPasses> bodies_;
  std::size_t bodyCount_;
};

}  // namespace firn
