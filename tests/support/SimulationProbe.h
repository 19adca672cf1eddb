#pragma once
// What the tests reach inside a Simulation from outside the production classes (SimulationProbe is a friend of
// Simulation, ImplicitSolver and SolverState, and builds the test-only programs itself): a particle's velocity
// overwritten (with a NaN, to exercise the watchdog); and for the semi-implicit solve's tests the Hessian product
// β Δt² H u (kg·m/s; Δt the scene's dt) at every node of the grid the current particles reach, as the solve computes
// it, as its differential before the projection onto the positive semi-definite, or as the central difference of the
// stress the explicit force comes from; and the stiffness blocks β Δt² Hᵢᵢ (kg) the solve's first product sums for
// its block preconditioner. Values come in the order of the dense grid (z, then y, then x).
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "gl/ComputePass.h"
#include "gpu/GpuLayout.h"
#include "sim/Simulation.h"

namespace firn {

// How a product takes the stress's change: ∂²Ψ/∂F² : δF with the stiffness projected onto the positive
// semi-definite (the solve's), the differential as it is (solver_prepare.comp with FIRN_SOLVER_UNPROJECTED_HESSIAN),
// or (P(F + δF) − P(F − δF)) / 2 (solver_product.comp with FIRN_SOLVER_FORCE_DIFFERENCE).
enum class HessianProduct { Differential, Unprojected, ForceDifference };

class SimulationProbe {
 public:
  // A product's sums and the first product's stiffness blocks at each storage address.
  struct SolverSums {
    std::vector<glm::dvec3> products;
    std::vector<glm::dmat3> stiffnessBlocks;
  };

  explicit SimulationProbe(Simulation& simulation);

  void setParticleVelocity(std::size_t particle, const glm::vec3& velocityMPerS);

  // The collider table as the GPU holds it now: the colliders' poses of the last step, the rigid bodies' for the
  // next (integrate_bodies.comp writes them at the end of a step).
  std::vector<gpu::ColliderParams> colliderTable() const;
  // The particles whose stress the last step mirrored into a rigid body, in index order.
  std::vector<std::uint32_t> mirroredParticles() const;

  // The solver's; they throw std::logic_error for a scene whose integrator is explicit.

  struct NodeVector {
    glm::ivec3 node{0};
    glm::dvec3 value{0.0};
  };
  struct NodeMatrix {
    glm::ivec3 node{0};
    glm::dmat3 value{0.0};
  };

  // The product for the grid velocities `velocityAtNode(node position)` (m/s) on the current state.
  std::vector<NodeVector> hessianProduct(const std::function<glm::dvec3(const glm::dvec3&)>& velocityAtNode,
                                         HessianProduct product);
  std::vector<NodeMatrix> stiffnessBlocks();

 private:
  // The step's uniforms, the sort and P2G, the bins' order by index and each particle's stiffness, on the current
  // state.
  void prepare(HessianProduct product);
  // The sums at the first `addresses` storage addresses, in kg·m/s (products) and kg (blocks), cleared.
  SolverSums takeSums(std::size_t addresses);

  // The solve and its test-only programs, built when first asked for.
  const ImplicitSolver& solver();
  // The step's transfers by tiles (its first, when every shape is given), whose products the probes run.
  const TransferPasses& tileTransfers();

  Simulation& simulation_;
  gl::ComputePass unprojectedPrepare_;
  gl::ComputePass forceDifferenceProduct_;
};

}  // namespace firn
