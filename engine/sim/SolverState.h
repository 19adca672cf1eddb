#pragma once
// The semi-implicit solve's state on the GPU (common/solver.glsl): the conjugate residual method's vectors per node of
// the grid's pool, the block preconditioner per node, each particle's stiffness, and the solve's status (the
// iterations' dispatches, the dot products' registers). It owns those buffers, published at the solver bindings of the
// GPU contract (FIRN_SOLVER_BINDINGS_FIRST to _END); ImplicitSolver runs the passes over them.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "gl/Buffer.h"
#include "gl/BufferBindings.h"

namespace firn {

class SolverState {
 public:
  SolverState(std::size_t particleCapacity, std::size_t rigidBodies);

  // Vectors for a pool of `blocks` blocks (the grid's), zero: no product summed. The status holds a partial sum's slot
  // per block and per rigid body.
  void allocatePool(std::size_t blocks);
  std::size_t poolBytes() const;

  // The status: its header holds the iterations' indirect dispatches (gpu::SolverStatus).
  const gl::Buffer& status() const { return status_; }
  // Register `index` (gpu::SolverStatus::registers): an iteration's dot products.
  glm::vec4 readRegister(std::size_t index) const;
  // gpu::SolverStatus::solveEnd.x: 1 + the register at which the GPU ended the solve, 0 while it runs.
  std::uint32_t readEnd() const;
  void publish(gl::BufferBindings& bindings) const;

 private:
  friend class SimulationProbe;  // the solver's tests (tests/support/SimulationProbe.h) read and write its nodes

  gl::Buffer nodes_;            // SolverNode per node of the pool
  gl::Buffer status_;           // SolverStatus, then a vec4 per slot of the pool
  gl::Buffer particles_;        // SolverParticle per particle
  gl::Buffer preconditioners_;  // SolverPreconditioner per node of the pool
  std::size_t rigidBodies_;     // each with a partial sum's slot in the status (its six unknowns: GpuState's records)
};

}  // namespace firn
