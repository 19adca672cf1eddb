#pragma once
// The simulation's state on the GPU: the particle buffers (sized for a capacity, live up to a count), the
// block-sparse grid (a pool of blocks, the block map over the domain, the bins that sort the particles), the
// material and collider tables, the watchdog and the step's uniform block — which of them exist depends on what
// the scene needs — and the copies that save and restore the state.
#include <algorithm>
#include <cstddef>
#include <string>
#include <tuple>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec4.hpp>

#include "gl/Buffer.h"
#include "gl/Context.h"
#include "scene/Scene.h"
#include "sim/GpuLayout.h"
#include "sim/SceneUpload.h"

namespace firn {

// Particle state read back from the GPU.
struct ParticleSnapshot {
  std::vector<glm::vec4> positionMass;    // x (m), mass (kg)
  std::vector<glm::vec4> velocityVolume;  // v (m/s), V0 (m³)
  std::vector<float> plasticJ;            // J_P
  std::size_t size() const { return positionMass.size(); }
};

// Which buffers a scene needs, and how large.
struct GpuStateLayout {
  std::string sceneFile;  // how messages name the scene (sceneFileName)
  GridSpec grid;
  std::size_t particleCapacity = 0;
  std::size_t blockCapacity = 0;    // slots of the block pool
  bool deformationGradient = true;  // F: every model but water
  bool affine = false;              // APIC's C
  bool impulse = true;              // the grid's impulse storage: PIC/FLIP or semi-implicit
  bool semiImplicit = false;        // the solve's vectors per node and stiffness per particle

  static GpuStateLayout forScene(const Scene& scene, std::size_t particleCapacity, std::size_t blockCapacity,
                                 bool deformationGradient);
  // Blocks of BLOCK_WIDTH³ nodes over the domain, per axis.
  glm::ivec3 blocksPerAxis() const;

  // Each buffer must fit one shader storage block. The largest particle buffers hold a 3×4 float matrix per
  // particle (F, τ, C), or the semi-implicit solve's SolverParticle (144 bytes).
  std::size_t largestParticleBufferBytesPerParticle() const;
  // All of this layout's particle buffers together, per particle.
  std::size_t particleBytesPerParticle() const;
  // The most blocks a pool may hold where the driver allows `maxStorageBlockBytes` per buffer: the largest pool
  // buffer holds an ivec4 per node, or the semi-implicit solve's SolverNode (192 bytes).
  static std::size_t maxPoolBlocks(long long maxStorageBlockBytes, bool semiImplicit);
  // The pool's buffers per block, and the block map's bytes over the domain.
  std::size_t poolBytesPerBlock() const;
  std::size_t blockMapBytes() const;
  // Throws InputError naming grid.cells when the block map exceeds what the driver allows per buffer.
  void checkBlockMapFits(const gl::ContextInfo& gl) const;
};

// The blocks of the grid's pool that particles' stencils reached.
struct BlockUsage {
  std::size_t lastStep = 0;    // claimed in the last step
  std::size_t mostInAStep = 0; // the most claimed in any step since the pool was made (may exceed the capacity)
  std::size_t capacity = 0;
  std::size_t poolBytes = 0;   // the pool's GPU memory: nodes, bins and the block table
  std::size_t mapBytes = 0;    // the block map's: 4 bytes per block of the domain
};

// One node of the grid as stored after P2G: its index per axis and its sums (fixed point or float bits).
struct StoredNode {
  glm::ivec3 node{0};
  glm::ivec4 sums{0};
};

// Values at `nodes`, paired as {node, value} and sorted in the order of the dense grid (z, then y, then x).
template <typename Result, typename Value>
std::vector<Result> inGridOrder(const std::vector<glm::ivec3>& nodes, const std::vector<Value>& values) {
  std::vector<Result> result;
  result.reserve(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) result.push_back({nodes[i], values[i]});
  std::sort(result.begin(), result.end(), [](const Result& a, const Result& b) {
    return std::tie(a.node.z, a.node.y, a.node.x) < std::tie(b.node.z, b.node.y, b.node.x);
  });
  return result;
}

// A Hessian product's sums and the first product's stiffness blocks at each storage address (GpuState::takeSolverSums).
struct SolverSums {
  std::vector<glm::dvec3> products;
  std::vector<glm::dmat3> stiffnessBlocks;
};

class GpuState {
 public:
  // Throws InputError when a buffer would exceed what the driver allows per shader storage block.
  GpuState(const GpuStateLayout& layout, const MaterialTable& materials,
           const std::vector<gpu::ColliderParams>& colliders, const gl::ContextInfo& gl);

  std::size_t particleCapacity() const { return layout_.particleCapacity; }
  glm::ivec3 gridNodes() const { return layout_.grid.cells + 1; }

  // The block pool: its use, and a new, larger pool (the grid is rebuilt every step, so nothing is copied).
  // Throws InputError when the grid buffers of `capacity` blocks exceed what the driver allows.
  BlockUsage blockUsage() const;
  void resizeBlockPool(std::size_t capacity, const gl::ContextInfo& gl);

  // Writes particles [first, first + records.size()) as new: undeformed, unstressed, no affine velocity.
  void writeParticles(std::size_t first, const ParticleRecords& records);
  void setParticleVelocity(std::size_t particle, const glm::vec3& velocityMPerS);
  ParticleSnapshot readParticles(std::size_t count) const;
  glm::vec3 particlePosition(std::size_t particle) const;

  // Binds every buffer to its binding point (gpu_contract.h), or only the particle buffers a renderer reads.
  void bindAll() const;
  void bindParticles() const;
  void writeStepUniforms(const gpu::StepUniforms& uniforms);

  // The block table: its header holds the per-block passes' indirect dispatches.
  const gl::Buffer& blockTableBuffer() const { return blockTable_; }
  // The semi-implicit solve's status: its header holds the iterations' indirect dispatches.
  const gl::Buffer& solverStatusBuffer() const { return solverStatus_; }
  // The solve's register `index` (gpu::SolverStatus::registers): an iteration's dot products.
  glm::vec4 readSolverRegister(std::size_t index) const;
  // gpu::SolverStatus::solveEnd.x: 1 + the register at which the GPU ended the solve, 0 while it runs.
  std::uint32_t readSolverEnd() const;

  gpu::WatchdogStatus watchdog() const;
  // The largest |v| + c the last G2P saw (m/s): one 4-byte read.
  double fastestSignalMPerS() const;

  // Every node of the active blocks after P2G, as stored, in the order of the dense grid (z, then y, then x).
  std::vector<StoredNode> readGrid() const;
  // The node index per axis of each storage address of the last step's active blocks (slot after slot).
  std::vector<glm::ivec3> activeNodes() const;

  // Test hooks for the semi-implicit solve's products (Simulation::hessianProduct, Simulation::stiffnessBlocks): the
  // solve's vector z at each storage address of activeNodes(); and the sums there, the product's (times
  // `productPerUnit`, kg·m/s) and the first product's stiffness blocks (times `blockPerUnit`, kg), converted to
  // doubles and cleared.
  void writeSolverPreconditioned(const std::vector<glm::vec3>& byAddress);
  SolverSums takeSolverSums(std::size_t addresses, double productPerUnit, double blockPerUnit);

  // The buffers whose contents carry over from one step to the next (the grid is rebuilt every step): what a
  // checkpoint holds and what save() copies.
  std::vector<std::string> stateBytes() const;
  // Throws InputError naming `source` when the bytes do not fit this state's buffers.
  void checkStateBytes(const std::vector<std::string>& bytes, const std::string& source) const;
  void loadStateBytes(const std::vector<std::string>& bytes);
  void save();
  void restore();  // throws std::logic_error if nothing was saved

 private:
  template <class Self>
  static auto stateBuffers(Self& self);
  void allocateBlockPool(const gl::ContextInfo& gl);

  GpuStateLayout layout_;
  std::vector<gl::Buffer> saved_;  // save()'s copies, in the order of stateBuffers

  gl::Buffer positionMass_;
  gl::Buffer velocityVolume_;
  gl::Buffer elasticDeformation_;  // F (F_E for snow and sand); water-only scenes carry J alone
  gl::Buffer kirchhoffStress_;
  gl::Buffer affine_;  // APIC only
  gl::Buffer plasticState_;
  gl::Buffer sortedParticles_;  // particle indices in block, then bin, order
  gl::Buffer particleRanks_;    // each particle's place in its bin
  gl::Buffer gridMomentumMass_;  // per node of the pool
  gl::Buffer gridImpulse_;       // per node of the pool, PIC/FLIP or semi-implicit only
  gl::Buffer blockTable_;        // BlockTableHeader, then a BlockSlot per slot of the pool
  gl::Buffer blockMap_;          // per block of the domain
  gl::Buffer bins_;              // per base node of the pool
  gl::Buffer tileOrder_;          // per row of the pool
  gl::Buffer solverNodes_;        // semi-implicit: per node of the pool
  gl::Buffer solverStatus_;       // semi-implicit: SolverStatus, then a vec4 per slot of the pool
  gl::Buffer solverParticles_;    // semi-implicit: per particle
  gl::Buffer solverPreconditioners_;  // semi-implicit: per node of the pool
  gl::Buffer materials_;
  gl::Buffer colliders_;
  gl::Buffer watchdog_;
  gl::Buffer stepUniforms_;
};

}  // namespace firn
