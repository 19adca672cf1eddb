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
#include "sim/TransferShape.h"

namespace firn {

class ImplicitSolver {
 public:
  // The iterations between two looks at the residual: each look waits for the GPU, and the iterations dispatched
  // after convergence cost nothing.
  static constexpr int checkInterval = 4;

  // `options` are the step's shader options (stepShaderOptions), FIRN_SEMI_IMPLICIT among them; `shapes` the
  // transfer shapes the run may take (sim/TransferShape.h), for the Hessian product, timed among them (chooseProduct).
  ImplicitSolver(const Scene& scene, const gl::ShaderLibrary& library, const gl::ShaderOptions& options,
                 const std::vector<TransferShape>& shapes);

  // Replaces v* on the grid with the solution, the Hessian products in the chosen shape (the constructor's first
  // until chooseProduct). The state's buffers must be bound (StepPipeline binds them).
  SolveReport solve(const GpuState& state, std::size_t particles, int maxWorkGroupsX, gl::PassTimer& timer) const;
  // Times the step's first Hessian product in each of the constructor's shapes (fastestOfRounds, `rounds` timed),
  // on the grid the grid update has just left (its start x₀), and keeps the fastest. Each product's sums are taken
  // by the residual pass after it, so nothing carries into the next solve. Returns each shape's time (ms).
  std::vector<std::pair<TransferShape, double>> chooseProduct(const GpuState& state, std::size_t particles,
                                                              int maxWorkGroupsX, int rounds);
  const TransferShape& productShape() const { return products_[chosen_].shape; }


 private:
  friend class SimulationProbe;  // the solver's tests (tests/support/SimulationProbe.h) run its passes one by one

  // Each particle's stiffness (solver_prepare.comp).
  void prepare(const GpuState& state, std::size_t particles, int maxWorkGroupsX, gl::PassTimer& timer) const;
  // The solve's end after `iterations`: the residual register it ended at, relative to the reference.
  static SolveReport report(const GpuState& state, int iterations);
  void reduce(const GpuState& state, unsigned registerIndex, unsigned components, gl::PassTimer& timer) const;

  // The Hessian product's passes in one shape: tiles (solver_product.comp) take the transfers' dispatch, blocks
  // (solver_product_block.comp) a work group per active block (productDispatch).
  struct ProductPasses {
    TransferShape shape;
    gl::ComputePass first;  // FIRN_SOLVER_FIRST_PRODUCT: of the start, with the stiffness blocks
    gl::ComputePass iteration;
  };

  int maxIterations_;
  gl::ComputePass prepare_;
  gl::ComputePass begin_;
  std::vector<ProductPasses> products_;  // in the constructor's order of shapes
  std::size_t chosen_ = 0;
  gl::ComputePass residual_;
  gl::ComputePass apply_;
  gl::ComputePass step_;
  gl::ComputePass reduce_;
  gl::ComputePass finish_;
  // With rigid bodies: the solution into z, for a last product of it (solver_solution.comp).
  std::optional<gl::ComputePass> solution_;
};

}  // namespace firn
