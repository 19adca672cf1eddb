#pragma once
// The P2G sums recomputed on the CPU, for measuring what the GPU's atomics lose (fixed point against float,
// docs/numerics.md "Fixed-point atomics"). Each contribution is computed in float as p2g.comp computes it, with the
// weights of shaders/common/bspline.glsl (the one copy, compiled here as C++), and the contributions are added
// in double: what the GPU's sums differ by is then how its atomics add, not how its weights are evaluated.
//
// Sums are nondimensional, as the GPU stores them (grid.glsl): mass in units of m_ref, momentum in units of
// m_ref·h/Δt. The reference holds mass and Σ w m v: the P2G of a state just built, with no stress and C = 0.
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/Scene.h"
#include "sim/FixedPoint.h"
#include "sim/Simulation.h"

namespace firn::bench {

struct ReferenceNodeSums {
  double massUnits = 0;            // Σ w m / m_ref (every term positive: also the size of what was added)
  glm::dvec3 momentumUnits{0.0};   // Σ w m v / (m_ref h / Δt)
  double momentumScaleUnits = 0;   // Σ |w m v| / (m_ref h / Δt): the size of what was added, whatever cancels
  std::uint32_t contributions = 0; // particles that added a nonzero weight
};

// By linear node index x + nx (y + ny z), nx and ny the nodes per axis.
using ReferenceGrid = std::unordered_map<std::size_t, ReferenceNodeSums>;

ReferenceGrid referenceParticleToGrid(const Scene& scene, const FixedPointScale& scale, const ParticleSnapshot& particles);

struct NodeSumError {
  ReferenceNodeSums reference;
  double massErrorUnits = 0;      // |GPU − reference|
  double momentumErrorUnits = 0;  // |GPU − reference|, the Euclidean norm of the vector difference
};

// Every node the reference or the GPU (Simulation::readGridAfterTransfer) put something at.
std::vector<NodeSumError> compareWithReference(const std::vector<GridNodeSums>& gpuNodes, const ReferenceGrid& reference,
                                               const Scene& scene, const FixedPointScale& scale);

// Relative errors are per node, against the size of what was added there (ReferenceNodeSums): mass error over
// the node's mass, momentum error over Σ |w m v|, so a node where momenta cancel is not divided by zero. The
// statistics cover the nodes holding at least one particle's mass (m_ref): lighter nodes are the fringes of
// stencils, whose velocities reach a particle only through weights as small as their mass, and where fixed
// point's absolute resolution is a large fraction of almost nothing. A node given something where nothing was
// added counts too, with an infinite error.
struct SumErrorSummary {
  std::size_t nodes = 0;              // nodes the relative statistics cover
  std::uint32_t maxContributions = 0;
  double massMaxRelative = 0;
  double massRmsRelative = 0;
  double momentumMaxRelative = 0;
  double momentumRmsRelative = 0;
  double massMaxUnits = 0;      // the largest absolute errors, in the units above, over every node
  double momentumMaxUnits = 0;
};
SumErrorSummary summarizeErrors(const std::vector<NodeSumError>& errors);

}  // namespace firn::bench
