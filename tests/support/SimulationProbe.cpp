#include "SimulationProbe.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "gpu/GpuLayout.h"

namespace firn {

namespace {


gl::ComputePass variant(const Scene& scene, const char* shader, const char* define) {
  gl::ShaderOptions options = stepShaderOptions(scene, MaterialPrograms::SceneModels);
  options.defines.emplace_back(define, "1");
  return gl::ComputePass(gl::ShaderLibrary(), shader, options);
}

double fixed64ToDouble(std::uint32_t low, std::int32_t high) {
  return double(std::int64_t((std::uint64_t(std::uint32_t(high)) << 32) | low));
}

}  // namespace

SimulationProbe::SimulationProbe(Simulation& simulation) : simulation_(simulation) {}

void SimulationProbe::setParticleVelocity(std::size_t particle, const glm::vec3& velocityMPerS) {
  simulation_.state_.particles().writeVelocity(particle, velocityMPerS);
}

std::vector<gpu::ColliderParams> SimulationProbe::colliderTable() const {
  const Scene& scene = simulation_.scene();
  return simulation_.state_.readColliders(0, scene.colliders.size() + scene.rigidBodies.size());
}

std::vector<std::uint32_t> SimulationProbe::mirroredParticles() const {
  return simulation_.state_.grid().mirroredParticles();
}

const ImplicitSolver& SimulationProbe::solver() {
  const ImplicitSolver* solver = simulation_.pipeline_.implicitSolver();
  if (solver == nullptr) {
    throw std::logic_error(sceneFileName(simulation_.scene()) + ": the solver's probes need a semi-implicit scene");
  }
  if (!unprojectedPrepare_) {
    unprojectedPrepare_ = variant(simulation_.scene(), "sim/solver_prepare.comp", "FIRN_SOLVER_UNPROJECTED_HESSIAN");
    forceDifferenceProduct_ = variant(simulation_.scene(), "sim/solver_product.comp", "FIRN_SOLVER_FORCE_DIFFERENCE");
  }
  return *solver;
}

const TransferPasses& SimulationProbe::tileTransfers() {
  (void)solver();
  const TransferPasses& first = simulation_.pipeline_.transfers().front();
  if (first.shape().kind != TransferShape::Kind::Tiles) {
    throw std::logic_error(sceneFileName(simulation_.scene()) +
                           ": the solver's probes need the tiles among the shapes");
  }
  return first;
}

void SimulationProbe::prepare(HessianProduct product) {
  Simulation& s = simulation_;
  GpuState& state = s.state_;
  state.writeStepUniforms(stepUniforms(s.scene_, s.fixedPoint_, s.scene_.time.dtS, s.timeS_, s.particleCount_, s.steps_));
  // The probe's products are the tiles' (the step's first transfers): the sort files the tiles for them whatever shape
  // the run chose.
  s.pipeline_.transferToGrid(state, s.particleCount_, BlockGrid::SortFor::Tiles, s.passTimer_);
  const gl::BufferBindings& buffers = state.bindings();
  const ImplicitSolver& implicitSolver = solver();
  const gl::ComputePass& pass = product == HessianProduct::Unprojected ? unprojectedPrepare_ : implicitSolver.prepare_;
  pass.runOver(s.particleCount_, s.gl_.maxComputeWorkGroupCountX, buffers, s.passTimer_);
  state.bindings().completeWrites();
}

std::vector<SimulationProbe::NodeVector> SimulationProbe::hessianProduct(
    const std::function<glm::dvec3(const glm::dvec3&)>& velocityAtNode, HessianProduct product) {
  prepare(product);
  GpuState& state = simulation_.state_;
  const GridSpec& grid = simulation_.scene_.grid;
  const std::vector<glm::ivec3> nodes = state.grid().activeNodes();
  // The velocities go where the iterations' products take theirs: the solve's vector z.
  gl::Buffer& solverNodes = state.solver()->nodes_;
  std::vector<gpu::SolverNode> stored = solverNodes.read<gpu::SolverNode>(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    stored[i].preconditioned = glm::vec4(glm::vec3(velocityAtNode(grid.originM + glm::dvec3(nodes[i]) * grid.cellSizeM)), 0);
  }
  solverNodes.upload(0, stored.size() * sizeof(gpu::SolverNode), stored.data());
  // The tiles' product, whose dispatch is the transfers' own.
  const gl::ComputePass& pass = product == HessianProduct::ForceDifference
                                    ? forceDifferenceProduct_
                                    : tileTransfers().productPass(TransferPasses::Product::Iteration);
  pass.runIndirect(state.grid().blockTable(), offsetof(gpu::BlockTableHeader, tileDispatch), state.bindings(),
                   simulation_.passTimer_);
  state.bindings().completeWrites();
  return inGridOrder<NodeVector>(nodes, takeSums(nodes.size()).products);
}

std::vector<SimulationProbe::NodeMatrix> SimulationProbe::stiffnessBlocks() {
  prepare(HessianProduct::Differential);
  GpuState& state = simulation_.state_;
  const std::vector<glm::ivec3> nodes = state.grid().activeNodes();
  tileTransfers().productPass(TransferPasses::Product::First)
      .runIndirect(state.grid().blockTable(), offsetof(gpu::BlockTableHeader, tileDispatch), state.bindings(),
                   simulation_.passTimer_);
  state.bindings().completeWrites();
  return inGridOrder<NodeMatrix>(nodes, takeSums(nodes.size()).stiffnessBlocks);
}

SimulationProbe::SolverSums SimulationProbe::takeSums(std::size_t addresses) {
  // The 64-bit sums' unit: 2^−k_H of the momentum unit (products) or of the reference mass (blocks).
  const FixedPointScale& fixedPoint = simulation_.fixedPoint_;
  const double productPerUnit = std::ldexp(fixedPoint.momentumUnitKgMPerS, -fixedPoint.solverFractionBits);
  const double blockPerUnit = std::ldexp(fixedPoint.referenceMassKg, -fixedPoint.solverFractionBits);
  gl::Buffer& solverNodes = simulation_.state_.solver()->nodes_;
  std::vector<gpu::SolverNode> nodes = solverNodes.read<gpu::SolverNode>(addresses);
  SolverSums sums;
  sums.products.reserve(nodes.size());
  sums.stiffnessBlocks.reserve(nodes.size());
  for (gpu::SolverNode& node : nodes) {
    glm::dvec3 product, diagonal, offDiagonal;  // offDiagonal: yz, zx, xy
    for (int c = 0; c < 3; ++c) {
      product[c] = fixed64ToDouble(node.productLow[c], node.productHigh[c]) * productPerUnit;
      diagonal[c] = fixed64ToDouble(node.diagonalLow[c], node.diagonalHigh[c]) * blockPerUnit;
      offDiagonal[c] = fixed64ToDouble(node.offDiagonalLow[c], node.offDiagonalHigh[c]) * blockPerUnit;
    }
    sums.products.push_back(product);
    sums.stiffnessBlocks.emplace_back(diagonal.x, offDiagonal.z, offDiagonal.y, offDiagonal.z, diagonal.y,
                                      offDiagonal.x, offDiagonal.y, offDiagonal.x, diagonal.z);
    node.productLow = node.diagonalLow = node.offDiagonalLow = glm::uvec4(0);
    node.productHigh = node.diagonalHigh = node.offDiagonalHigh = glm::ivec4(0);
  }
  solverNodes.upload(0, nodes.size() * sizeof(gpu::SolverNode), nodes.data());
  return sums;
}

}  // namespace firn
