#pragma once
// One transfer shape's passes (sim/TransferShape.h): the object a step is given for its transfers. It knows the sort
// its passes read, runs particle to grid, and in a semi-implicit step the Hessian product β Δt² H z (its first, which
// also sums the stiffness blocks, and the iterations'). A step holds one for each shape its run may take, times them
// on the run's own particles and keeps the fastest for P2G and, apart, for the product (StepPipeline).
#include <cstddef>

#include "gl/ComputePass.h"
#include "gl/PassTimer.h"
#include "gl/ShaderLibrary.h"
#include "sim/BlockGrid.h"
#include "sim/GpuState.h"
#include "sim/TransferShape.h"

namespace firn {

class TransferPasses {
 public:
  // `options` are the step's shader options; the product's passes are built for a semi-implicit step only.
  TransferPasses(const TransferShape& shape, const gl::ShaderLibrary& library, const gl::ShaderOptions& options,
                 bool semiImplicit);

  const TransferShape& shape() const { return shape_; }
  // What the sort must leave for this shape's passes: the tiles in order of fill for the tiles (BlockGrid).
  BlockGrid::SortFor sortFor() const;

  // P2G: tiles take the transfers' dispatch from the block table, blocks a work group per active block.
  void particleToGrid(const GpuState& state, gl::PassTimer& timer) const;

  // Which of the product's passes: the start's (FIRN_SOLVER_FIRST_PRODUCT, with the stiffness blocks) or an
  // iteration's.
  enum class Product { First, Iteration };
  // The product inside the solve, dispatched from the solve's status (whose dispatches an ended solve empties).
  void productInSolve(Product product, const GpuState& state, gl::PassTimer& timer) const;
  // An iteration's product dispatched from the block table, over the whole step's grid: for the product of the
  // solution after the solve has ended (solver_solution.comp).
  void productOverGrid(const GpuState& state, gl::PassTimer& timer) const;
  // The product's program (the solver's tests run it on vectors of their own).
  const gl::ComputePass& productPass(Product product) const {
    return product == Product::First ? firstProduct_ : iterationProduct_;
  }

 private:
  TransferShape shape_;
  gl::ComputePass particleToGrid_;
  gl::ComputePass firstProduct_;      // semi-implicit steps
  gl::ComputePass iterationProduct_;  // semi-implicit steps
};

}  // namespace firn
