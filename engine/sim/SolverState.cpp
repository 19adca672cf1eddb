#include "sim/SolverState.h"

#include "gpu/GpuLayout.h"

namespace firn {

namespace {

double fixed64ToDouble(std::uint32_t low, std::int32_t high) {
  return double(std::int64_t((std::uint64_t(std::uint32_t(high)) << 32) | low));
}

}  // namespace

SolverState::SolverState(std::size_t particleCapacity)
    : particles_(gl::Buffer(particleCapacity * sizeof(gpu::SolverParticle)).labelled("solver: particle stiffness")) {}

void SolverState::allocatePool(std::size_t blocks) {
  nodes_ = gl::Buffer(blocks * gpu::BLOCK_NODES * sizeof(gpu::SolverNode)).labelled("solver: node vectors");
  status_ = gl::Buffer(sizeof(gpu::SolverStatus) + blocks * sizeof(glm::vec4)).labelled("solver: status");
  preconditioners_ =
      gl::Buffer(blocks * gpu::BLOCK_NODES * sizeof(gpu::SolverPreconditioner)).labelled("solver: preconditioner");
}

std::size_t SolverState::poolBytes() const { return nodes_.bytes() + status_.bytes() + preconditioners_.bytes(); }

glm::vec4 SolverState::readRegister(std::size_t index) const {
  return status_.read<glm::vec4>(1, offsetof(gpu::SolverStatus, registers) / sizeof(glm::vec4) + index).front();
}

std::uint32_t SolverState::readEnd() const {
  return status_.read<glm::uvec4>(1, offsetof(gpu::SolverStatus, solveEnd) / sizeof(glm::uvec4)).front().x;
}

void SolverState::writePreconditioned(const std::vector<glm::vec3>& byAddress) {
  std::vector<gpu::SolverNode> nodes = nodes_.read<gpu::SolverNode>(byAddress.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) nodes[i].preconditioned = glm::vec4(byAddress[i], 0);
  nodes_.upload(0, nodes.size() * sizeof(gpu::SolverNode), nodes.data());
}

SolverSums SolverState::takeSums(std::size_t addresses, double productPerUnit, double blockPerUnit) {
  std::vector<gpu::SolverNode> nodes = nodes_.read<gpu::SolverNode>(addresses);
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
  nodes_.upload(0, nodes.size() * sizeof(gpu::SolverNode), nodes.data());
  return sums;
}

void SolverState::publish(gl::BufferBindings& bindings) const {
  bindings.storage(FIRN_BINDING_SOLVER_NODES, nodes_);
  bindings.storage(FIRN_BINDING_SOLVER_PARTICLES, particles_);
  bindings.storage(FIRN_BINDING_SOLVER_STATUS, status_);
  bindings.storage(FIRN_BINDING_SOLVER_PRECONDITIONER, preconditioners_);
}

}  // namespace firn
