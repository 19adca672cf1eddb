#include "sim/SolverState.h"

#include "gpu/GpuLayout.h"

namespace firn {

SolverState::SolverState(std::size_t particleCapacity, std::size_t rigidBodies)
    : particles_(gl::Buffer(particleCapacity * sizeof(gpu::SolverParticle)).labelled("solver: particle stiffness")),
      rigidBodies_(rigidBodies) {}

void SolverState::allocatePool(std::size_t blocks) {
  nodes_ = gl::Buffer(blocks * gpu::BLOCK_NODES * sizeof(gpu::SolverNode)).labelled("solver: node vectors");
  status_ =
      gl::Buffer(sizeof(gpu::SolverStatus) + (blocks + rigidBodies_) * sizeof(glm::vec4)).labelled("solver: status");
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

void SolverState::publish(gl::BufferBindings& bindings) const {
  bindings.storage(FIRN_BINDING_SOLVER_NODES, nodes_);
  bindings.storage(FIRN_BINDING_SOLVER_PARTICLES, particles_);
  bindings.storage(FIRN_BINDING_SOLVER_STATUS, status_);
  bindings.storage(FIRN_BINDING_SOLVER_PRECONDITIONER, preconditioners_);
}

}  // namespace firn
