#include "P2GReference.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace firn::bench {

namespace shader {
using glm::abs;
using glm::sign;
#include "common/bspline.glsl"
}  // namespace shader

namespace {

// kernel.glsl's particleStencil and stencilWeight, in the shader's float arithmetic and order of operations.
struct Stencil {
  int width = 0;  // nodes per axis: 3 (quadratic) or 4 (cubic)
  glm::ivec3 baseNode{0};
  glm::vec3 weight[4];
};

Stencil particleStencil(const glm::vec3& positionM, const glm::vec3& gridOriginM, float cellsPerM, Kernel kernel) {
  const glm::vec3 positionInCells = (positionM - gridOriginM) * cellsPerM;
  Stencil stencil;
  const bool cubic = kernel == Kernel::Cubic;
  stencil.width = cubic ? 4 : 3;
  stencil.baseNode = cubic ? glm::ivec3(glm::floor(positionInCells)) - 1 : glm::ivec3(glm::floor(positionInCells - 0.5f));
  const auto weight = cubic ? shader::cubicBSpline : shader::quadraticBSpline;
  for (int k = 0; k < stencil.width; ++k) {
    const glm::vec3 offsetInCells = positionInCells - glm::vec3(stencil.baseNode + k);
    stencil.weight[k] = glm::vec3(weight(offsetInCells.x), weight(offsetInCells.y), weight(offsetInCells.z));
  }
  return stencil;
}

}  // namespace

ReferenceGrid referenceParticleToGrid(const Scene& scene, const FixedPointScale& scale, const ParticleSnapshot& particles) {
  const glm::ivec3 nodes = scene.grid.cells + 1;
  // The uniforms the shader reads (Simulation::writeStepUniforms), as the floats it gets.
  const glm::vec3 gridOriginM(scene.grid.originM);
  const float cellsPerM = float(1.0 / scene.grid.cellSizeM);
  const float massUnitsPerKg = float(1.0 / scale.referenceMassKg);
  const float momentumUnitsPerKgMPerS = float(1.0 / scale.momentumUnitKgMPerS);
  ReferenceGrid grid;
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const glm::vec3 x(particles.positionMass[p]);
    const float massKg = particles.positionMass[p].w;
    const float massUnits = massKg * massUnitsPerKg;
    const glm::vec3 momentumUnits = glm::vec3(particles.velocityVolume[p]) * (massKg * momentumUnitsPerKgMPerS);
    const Stencil stencil = particleStencil(x, gridOriginM, cellsPerM, scene.solver.kernel);
    for (int kz = 0; kz < stencil.width; ++kz)
      for (int ky = 0; ky < stencil.width; ++ky)
        for (int kx = 0; kx < stencil.width; ++kx) {
          const float w = stencil.weight[kx].x * stencil.weight[ky].y * stencil.weight[kz].z;
          if (w == 0.0f) continue;  // adds exactly nothing, in either kind of atomics
          const glm::ivec3 node = stencil.baseNode + glm::ivec3(kx, ky, kz);
          ReferenceNodeSums& sums = grid[std::size_t(node.x + nodes.x * (node.y + nodes.y * node.z))];
          const glm::vec3 momentum = w * momentumUnits;
          sums.massUnits += double(w * massUnits);
          sums.momentumUnits += glm::dvec3(momentum);
          sums.momentumScaleUnits += glm::length(glm::dvec3(momentum));
          ++sums.contributions;
        }
  }
  return grid;
}

std::vector<NodeSumError> compareWithReference(const std::vector<GridNodeSums>& gpuNodes, const ReferenceGrid& reference,
                                               const Scene& scene, const FixedPointScale& scale) {
  const glm::ivec3 nodes = scene.grid.cells + 1;
  std::unordered_map<std::size_t, const GridNodeSums*> gpuByIndex;
  for (const GridNodeSums& node : gpuNodes) {
    gpuByIndex[std::size_t(node.node.x + nodes.x * (node.node.y + nodes.y * node.node.z))] = &node;
  }
  const auto errorAt = [&](const ReferenceNodeSums& expected, const GridNodeSums* gpu) {
    NodeSumError error;
    error.reference = expected;
    const double massUnits = gpu != nullptr ? gpu->massKg / scale.referenceMassKg : 0.0;
    const glm::dvec3 momentumUnits = gpu != nullptr ? gpu->momentumKgMPerS / scale.momentumUnitKgMPerS : glm::dvec3(0.0);
    error.massErrorUnits = std::abs(massUnits - expected.massUnits);
    error.momentumErrorUnits = glm::length(momentumUnits - expected.momentumUnits);
    return error;
  };
  std::vector<NodeSumError> errors;
  for (const auto& [index, expected] : reference) {
    const auto gpu = gpuByIndex.find(index);
    errors.push_back(errorAt(expected, gpu != gpuByIndex.end() ? gpu->second : nullptr));
  }
  // Anything the GPU put where no particle contributed is all error.
  for (const auto& [index, gpu] : gpuByIndex) {
    if (reference.count(index) == 0 && (gpu->massKg != 0 || gpu->momentumKgMPerS != glm::dvec3(0.0))) {
      errors.push_back(errorAt(ReferenceNodeSums{}, gpu));
    }
  }
  return errors;
}

SumErrorSummary summarizeErrors(const std::vector<NodeSumError>& errors) {
  const auto relative = [](double error, double size) {
    if (error == 0) return 0.0;
    return size > 0 ? error / size : std::numeric_limits<double>::infinity();
  };
  constexpr double kOneParticleUnits = 1;  // m_ref, in units of m_ref
  SumErrorSummary summary;
  double massSquares = 0, momentumSquares = 0;
  for (const NodeSumError& node : errors) {
    summary.maxContributions = std::max(summary.maxContributions, node.reference.contributions);
    summary.massMaxUnits = std::max(summary.massMaxUnits, node.massErrorUnits);
    summary.momentumMaxUnits = std::max(summary.momentumMaxUnits, node.momentumErrorUnits);
    const double m = node.reference.massUnits;
    if (m < kOneParticleUnits && m > 0) continue;
    const double mass = relative(node.massErrorUnits, m);
    const double momentum = relative(node.momentumErrorUnits, node.reference.momentumScaleUnits);
    summary.massMaxRelative = std::max(summary.massMaxRelative, mass);
    summary.momentumMaxRelative = std::max(summary.momentumMaxRelative, momentum);
    massSquares += mass * mass;
    momentumSquares += momentum * momentum;
    ++summary.nodes;
  }
  if (summary.nodes > 0) {
    summary.massRmsRelative = std::sqrt(massSquares / double(summary.nodes));
    summary.momentumRmsRelative = std::sqrt(momentumSquares / double(summary.nodes));
  }
  return summary;
}

}  // namespace firn::bench
