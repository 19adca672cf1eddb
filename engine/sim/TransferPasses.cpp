#include "sim/TransferPasses.h"

#include <string>

#include "gpu/GpuLayout.h"

namespace firn {

namespace {

// Where the solve's status keeps the product's dispatch in `shape`: over the transfers' tiles, or a work group per
// active block.
std::size_t solveProductDispatch(const TransferShape& shape) {
  return shape.kind == TransferShape::Kind::Tiles ? offsetof(gpu::SolverStatus, solveProductDispatch)
                                                  : offsetof(gpu::SolverStatus, solveBlockDispatch);
}

}  // namespace

TransferPasses::TransferPasses(const TransferShape& shape, const gl::ShaderLibrary& library,
                               const gl::ShaderOptions& options, bool semiImplicit)
    : shape_(shape) {
  const bool tiles = shape.kind == TransferShape::Kind::Tiles;
  const gl::ShaderOptions shapeOptions = shapeShaderOptions(options, shape);
  // Every shape's passes are timed under the tiles' names: a step has one P2G and one kind of product.
  particleToGrid_ = gl::ComputePass(library, tiles ? "sim/p2g.comp" : "sim/p2g_block.comp", shapeOptions,
                                    "sim/p2g.comp");
  if (!semiImplicit) return;
  const std::string product = tiles ? "sim/solver_product.comp" : "sim/solver_product_block.comp";
  gl::ShaderOptions firstOptions = shapeOptions;
  firstOptions.defines.emplace_back("FIRN_SOLVER_FIRST_PRODUCT", "1");
  firstProduct_ = gl::ComputePass(library, product, firstOptions, "sim/solver_product.comp (first product)");
  iterationProduct_ = gl::ComputePass(library, product, shapeOptions, "sim/solver_product.comp");
}

BlockGrid::SortFor TransferPasses::sortFor() const {
  return shape_.kind == TransferShape::Kind::Tiles ? BlockGrid::SortFor::Tiles : BlockGrid::SortFor::Blocks;
}

void TransferPasses::particleToGrid(const GpuState& state, gl::PassTimer& timer) const {
  if (shape_.kind == TransferShape::Kind::Tiles) {
    particleToGrid_.runIndirect(state.grid().blockTable(), blockTableDispatch(shape_), state.bindings(), timer);
  } else {
    state.grid().runOverBlocks(particleToGrid_, state.bindings(), timer);
  }
}

void TransferPasses::productInSolve(Product product, const GpuState& state, gl::PassTimer& timer) const {
  productPass(product).runIndirect(state.solver()->status(), solveProductDispatch(shape_), state.bindings(), timer);
}

void TransferPasses::productOverGrid(const GpuState& state, gl::PassTimer& timer) const {
  iterationProduct_.runIndirect(state.grid().blockTable(), blockTableDispatch(shape_), state.bindings(), timer);
}

}  // namespace firn
