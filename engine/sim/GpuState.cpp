#include "sim/GpuState.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include "Error.h"

namespace firn {

namespace {

std::string mebibytes(double bytes) {
  std::ostringstream out;
  out.precision(4);
  out << bytes / (1024.0 * 1024.0) << " MiB";
  return out.str();
}

gpu::Mat3x4 identityMat3() { return {{glm::vec4(1, 0, 0, 0), glm::vec4(0, 1, 0, 0), glm::vec4(0, 0, 1, 0)}}; }

std::size_t nodeStorageBytes(std::size_t blocks) { return blocks * gpu::BLOCK_NODES * sizeof(glm::ivec4); }

}  // namespace

GpuStateLayout GpuStateLayout::forScene(const Scene& scene, std::size_t particleCapacity, std::size_t blockCapacity,
                                        bool deformationGradient) {
  GpuStateLayout layout;
  layout.sceneFile = sceneFileName(scene);
  layout.grid = scene.grid;
  layout.particleCapacity = particleCapacity;
  layout.blockCapacity = blockCapacity;
  layout.deformationGradient = deformationGradient;
  layout.affine = scene.solver.transfer == Transfer::Apic;
  // The velocity before forces: PIC/FLIP's increment and the semi-implicit solve's start (common/grid.glsl).
  layout.impulse = scene.solver.transfer == Transfer::PicFlip || scene.solver.semiImplicit();
  layout.semiImplicit = scene.solver.semiImplicit();
  return layout;
}

glm::ivec3 GpuStateLayout::blocksPerAxis() const { return (grid.cells + 1 + gpu::BLOCK_WIDTH - 1) / gpu::BLOCK_WIDTH; }

std::size_t GpuStateLayout::largestParticleBufferBytesPerParticle() const {
  return semiImplicit ? std::max(sizeof(gpu::Mat3x4), sizeof(gpu::SolverParticle)) : sizeof(gpu::Mat3x4);
}

std::size_t GpuStateLayout::particleBytesPerParticle() const {
  // As GpuState's constructor allocates them.
  return 2 * sizeof(glm::vec4) + sizeof(gpu::ParticlePlasticState) + (deformationGradient ? sizeof(gpu::Mat3x4) : 0) +
         sizeof(gpu::Mat3x4) + (affine ? sizeof(gpu::Mat3x4) : 0) + (semiImplicit ? sizeof(gpu::SolverParticle) : 0) +
         2 * sizeof(std::uint32_t);
}

std::size_t GpuStateLayout::poolBytesPerBlock() const {
  // As allocateBlockPool allocates them; the solve's status holds a vec4 per slot.
  return nodeStorageBytes(1) * (impulse ? 2 : 1) + gpu::BLOCK_NODES * sizeof(glm::uvec2) +
         gpu::BLOCK_TILES * sizeof(std::uint32_t) + sizeof(gpu::BlockSlot) +
         (semiImplicit ? gpu::BLOCK_NODES * (sizeof(gpu::SolverNode) + sizeof(gpu::SolverPreconditioner)) + sizeof(glm::vec4)
                       : 0);
}

std::size_t GpuStateLayout::blockMapBytes() const {
  const glm::ivec3 blocks = blocksPerAxis();
  return std::size_t(blocks.x) * std::size_t(blocks.y) * std::size_t(blocks.z) * sizeof(std::uint32_t);
}

void GpuStateLayout::checkBlockMapFits(const gl::ContextInfo& gl) const {
  const double maxBytes = double(gl.maxStorageBlockBytes);
  const double mapBytes = double(blockMapBytes());
  if (mapBytes > maxBytes) {
    throw InputError(sceneFile + ": grid.cells: " + std::to_string(grid.cells.x) + "×" + std::to_string(grid.cells.y) +
                     "×" + std::to_string(grid.cells.z) + " cells need a block map of " + mebibytes(mapBytes) +
                     " (4 bytes per " + std::to_string(gpu::BLOCK_NODES) + " nodes), but " + gl.renderer + " allows " +
                     mebibytes(maxBytes) + " per shader storage block; use fewer cells");
  }
}

std::size_t GpuStateLayout::maxPoolBlocks(long long maxStorageBlockBytes, bool semiImplicit) {
  const std::size_t largestPerBlock = semiImplicit ? gpu::BLOCK_NODES * sizeof(gpu::SolverNode) : nodeStorageBytes(1);
  return std::size_t(maxStorageBlockBytes) / largestPerBlock;
}

GpuState::GpuState(const GpuStateLayout& layout, const MaterialTable& materials,
                   const std::vector<gpu::ColliderParams>& colliders, const gl::ContextInfo& gl)
    : layout_(layout) {
  const double maxBytes = double(gl.maxStorageBlockBytes);
  layout_.checkBlockMapFits(gl);
  const std::size_t n = layout_.particleCapacity;
  const double particleBytes = double(n) * double(layout_.largestParticleBufferBytesPerParticle());
  if (particleBytes > maxBytes) {
    throw InputError(layout_.sceneFile + ": bodies: " + std::to_string(n) + " particles need " + mebibytes(particleBytes) +
                     " per particle buffer, more than the " + mebibytes(maxBytes) +
                     " this driver allows; use fewer particles_per_cell");
  }

  materials_ = gl::Buffer::fromVector(materials.entries);
  colliders_ = gl::Buffer::fromVector(colliders);
  positionMass_ = gl::Buffer(n * sizeof(glm::vec4));
  velocityVolume_ = gl::Buffer(n * sizeof(glm::vec4));
  plasticState_ = gl::Buffer(n * sizeof(gpu::ParticlePlasticState));
  if (layout_.deformationGradient) elasticDeformation_ = gl::Buffer(n * sizeof(gpu::Mat3x4));
  kirchhoffStress_ = gl::Buffer(n * sizeof(gpu::Mat3x4));
  if (layout_.affine) affine_ = gl::Buffer(n * sizeof(gpu::Mat3x4));
  if (layout_.semiImplicit) solverParticles_ = gl::Buffer(n * sizeof(gpu::SolverParticle));
  sortedParticles_ = gl::Buffer(n * sizeof(std::uint32_t));
  particleRanks_ = gl::Buffer(n * sizeof(std::uint32_t));
  stepUniforms_ = gl::Buffer(sizeof(gpu::StepUniforms));
  const gpu::WatchdogStatus clearWatchdog{0, -1, 0, 0, 0, -1, 0, 0, -1, 0, 0.0f, 0};
  watchdog_ = gl::Buffer(sizeof clearWatchdog, &clearWatchdog);
  allocateBlockPool(gl);
}

void GpuState::allocateBlockPool(const gl::ContextInfo& gl) {
  const std::size_t capacity = layout_.blockCapacity;
  const double maxBytes = double(gl.maxStorageBlockBytes);
  const double gridBytes = double(nodeStorageBytes(capacity));
  const double solverBytes = layout_.semiImplicit ? double(capacity) * gpu::BLOCK_NODES * sizeof(gpu::SolverNode) : 0;
  if (solverBytes > maxBytes) {
    throw InputError(layout_.sceneFile + ": solver.integrator: the particles reach " + std::to_string(capacity) + " blocks of " +
                     std::to_string(gpu::BLOCK_NODES) + " nodes, whose semi-implicit solve needs " +
                     mebibytes(solverBytes) + " of vectors, more than the " + mebibytes(maxBytes) + " " + gl.renderer +
                     " allows per shader storage block; use fewer particles, a coarser grid.cell_size or \"explicit\"");
  }
  if (gridBytes > maxBytes) {
    throw InputError(layout_.sceneFile + ": grid: the particles reach " + std::to_string(capacity) + " blocks of " +
                     std::to_string(gpu::BLOCK_NODES) + " nodes, whose grid buffer of " + mebibytes(gridBytes) +
                     " is more than the " + mebibytes(maxBytes) + " " + gl.renderer +
                     " allows per shader storage block; use fewer particles or a coarser grid.cell_size");
  }
  // A zero-filled pool: every block free, every slot clean (release_blocks.comp keeps them so).
  gridMomentumMass_ = gl::Buffer(nodeStorageBytes(capacity));
  gridImpulse_ = layout_.impulse ? gl::Buffer(nodeStorageBytes(capacity)) : gl::Buffer();
  bins_ = gl::Buffer(capacity * gpu::BLOCK_NODES * sizeof(glm::uvec2));
  tileOrder_ = gl::Buffer(capacity * gpu::BLOCK_TILES * sizeof(std::uint32_t));
  blockMap_ = gl::Buffer(layout_.blockMapBytes());
  gpu::BlockTableHeader header{};
  header.blockCounts.y = static_cast<std::uint32_t>(capacity);
  blockTable_ = gl::Buffer(sizeof header + capacity * sizeof(gpu::BlockSlot));
  blockTable_.upload(0, sizeof header, &header);
  if (layout_.semiImplicit) {
    solverNodes_ = gl::Buffer(capacity * gpu::BLOCK_NODES * sizeof(gpu::SolverNode));  // zero: no product summed
    solverStatus_ = gl::Buffer(sizeof(gpu::SolverStatus) + capacity * sizeof(glm::vec4));
    solverPreconditioners_ = gl::Buffer(capacity * gpu::BLOCK_NODES * sizeof(gpu::SolverPreconditioner));
  }
}

void GpuState::resizeBlockPool(std::size_t capacity, const gl::ContextInfo& gl) {
  layout_.blockCapacity = capacity;
  allocateBlockPool(gl);
}

BlockUsage GpuState::blockUsage() const {
  const gpu::BlockTableHeader header = blockTable_.read<gpu::BlockTableHeader>(1)[0];
  BlockUsage usage;
  usage.lastStep = std::min<std::size_t>(header.blockCounts.x, layout_.blockCapacity);
  usage.mostInAStep = std::max(header.blockCounts.x, header.blockCounts.w);
  usage.capacity = layout_.blockCapacity;
  usage.poolBytes = gridMomentumMass_.bytes() + gridImpulse_.bytes() + bins_.bytes() + tileOrder_.bytes() +
                    blockTable_.bytes() + solverNodes_.bytes() + solverStatus_.bytes() + solverPreconditioners_.bytes();
  usage.mapBytes = blockMap_.bytes();
  return usage;
}

void GpuState::writeParticles(std::size_t first, const ParticleRecords& records) {
  const std::size_t n = records.size();
  positionMass_.upload(first * sizeof(glm::vec4), n * sizeof(glm::vec4), records.positionMass.data());
  velocityVolume_.upload(first * sizeof(glm::vec4), n * sizeof(glm::vec4), records.velocityVolume.data());
  plasticState_.upload(first * sizeof(gpu::ParticlePlasticState), n * sizeof(gpu::ParticlePlasticState),
                       records.plastic.data());
  // Particles start undeformed: F = I, so their stress is zero.
  const std::vector<gpu::Mat3x4> identity(n, identityMat3());
  if (elasticDeformation_) {
    elasticDeformation_.upload(first * sizeof(gpu::Mat3x4), n * sizeof(gpu::Mat3x4), identity.data());
  }
  const std::vector<gpu::Mat3x4> zero(n, gpu::Mat3x4{});
  kirchhoffStress_.upload(first * sizeof(gpu::Mat3x4), n * sizeof(gpu::Mat3x4), zero.data());
  if (affine_) affine_.upload(first * sizeof(gpu::Mat3x4), n * sizeof(gpu::Mat3x4), zero.data());
}

void GpuState::setParticleVelocity(std::size_t particle, const glm::vec3& velocityMPerS) {
  velocityVolume_.upload(particle * sizeof(glm::vec4), sizeof(glm::vec3), &velocityMPerS);
}

ParticleSnapshot GpuState::readParticles(std::size_t count) const {
  ParticleSnapshot snapshot;
  snapshot.positionMass = positionMass_.read<glm::vec4>(count);
  snapshot.velocityVolume = velocityVolume_.read<glm::vec4>(count);
  const auto plastic = plasticState_.read<gpu::ParticlePlasticState>(count);
  snapshot.plasticJ.reserve(plastic.size());
  for (const auto& state : plastic) snapshot.plasticJ.push_back(state.plasticJ);
  return snapshot;
}

glm::vec3 GpuState::particlePosition(std::size_t particle) const {
  return glm::vec3(positionMass_.read<glm::vec4>(1, particle)[0]);
}

void GpuState::bindAll() const {
  stepUniforms_.bindUniform(FIRN_BINDING_STEP_UNIFORMS);
  positionMass_.bindStorage(FIRN_BINDING_POSITION_MASS);
  velocityVolume_.bindStorage(FIRN_BINDING_VELOCITY_VOLUME);
  if (elasticDeformation_) elasticDeformation_.bindStorage(FIRN_BINDING_ELASTIC_DEFORMATION);
  kirchhoffStress_.bindStorage(FIRN_BINDING_KIRCHHOFF_STRESS);
  if (affine_) affine_.bindStorage(FIRN_BINDING_AFFINE);
  plasticState_.bindStorage(FIRN_BINDING_PLASTIC_STATE);
  gridMomentumMass_.bindStorage(FIRN_BINDING_GRID_MOMENTUM_MASS);
  if (gridImpulse_) gridImpulse_.bindStorage(FIRN_BINDING_GRID_IMPULSE);
  materials_.bindStorage(FIRN_BINDING_MATERIALS);
  colliders_.bindStorage(FIRN_BINDING_COLLIDERS);
  blockTable_.bindStorage(FIRN_BINDING_BLOCK_TABLE);
  watchdog_.bindStorage(FIRN_BINDING_WATCHDOG);
  blockMap_.bindStorage(FIRN_BINDING_BLOCK_MAP);
  bins_.bindStorage(FIRN_BINDING_BINS);
  sortedParticles_.bindStorage(FIRN_BINDING_SORTED_PARTICLES);
  particleRanks_.bindStorage(FIRN_BINDING_PARTICLE_RANKS);
  tileOrder_.bindStorage(FIRN_BINDING_TILE_ORDER);
  if (layout_.semiImplicit) {
    solverNodes_.bindStorage(FIRN_BINDING_SOLVER_NODES);
    solverParticles_.bindStorage(FIRN_BINDING_SOLVER_PARTICLES);
    solverStatus_.bindStorage(FIRN_BINDING_SOLVER_STATUS);
    solverPreconditioners_.bindStorage(FIRN_BINDING_SOLVER_PRECONDITIONER);
  }
}

void GpuState::writeSolverPreconditioned(const std::vector<glm::vec3>& byAddress) {
  std::vector<gpu::SolverNode> nodes = solverNodes_.read<gpu::SolverNode>(byAddress.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) nodes[i].preconditioned = glm::vec4(byAddress[i], 0);
  solverNodes_.upload(0, nodes.size() * sizeof(gpu::SolverNode), nodes.data());
}

namespace {

double fixed64ToDouble(std::uint32_t low, std::int32_t high) {
  return double(std::int64_t((std::uint64_t(std::uint32_t(high)) << 32) | low));
}

}  // namespace

SolverSums GpuState::takeSolverSums(std::size_t addresses, double productPerUnit, double blockPerUnit) {
  std::vector<gpu::SolverNode> nodes = solverNodes_.read<gpu::SolverNode>(addresses);
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
  solverNodes_.upload(0, nodes.size() * sizeof(gpu::SolverNode), nodes.data());
  return sums;
}

glm::vec4 GpuState::readSolverRegister(std::size_t index) const {
  return solverStatus_.read<glm::vec4>(1, offsetof(gpu::SolverStatus, registers) / sizeof(glm::vec4) + index).front();
}

std::uint32_t GpuState::readSolverEnd() const {
  return solverStatus_.read<glm::uvec4>(1, offsetof(gpu::SolverStatus, solveEnd) / sizeof(glm::uvec4)).front().x;
}

void GpuState::bindParticles() const {
  positionMass_.bindStorage(FIRN_BINDING_POSITION_MASS);
  velocityVolume_.bindStorage(FIRN_BINDING_VELOCITY_VOLUME);
  kirchhoffStress_.bindStorage(FIRN_BINDING_KIRCHHOFF_STRESS);
  plasticState_.bindStorage(FIRN_BINDING_PLASTIC_STATE);
}

void GpuState::writeStepUniforms(const gpu::StepUniforms& uniforms) {
  stepUniforms_.upload(0, sizeof uniforms, &uniforms);
}

gpu::WatchdogStatus GpuState::watchdog() const { return watchdog_.read<gpu::WatchdogStatus>(1)[0]; }

double GpuState::fastestSignalMPerS() const {
  std::uint32_t bits = 0;
  watchdog_.download(offsetof(gpu::WatchdogStatus, maxSpeedBits), sizeof bits, &bits);  // prepare_grid resets it
  return glm::uintBitsToFloat(bits);
}

std::vector<glm::ivec3> GpuState::activeNodes() const {
  const BlockUsage usage = blockUsage();
  const std::vector<gpu::BlockSlot> slots = blockTable_.read<gpu::BlockSlot>(usage.lastStep, sizeof(gpu::BlockTableHeader) / sizeof(gpu::BlockSlot));
  const glm::ivec3 blocks = layout_.blocksPerAxis();
  std::vector<glm::ivec3> nodes;
  nodes.reserve(slots.size() * gpu::BLOCK_NODES);
  for (const gpu::BlockSlot& slot : slots) {
    const int index = static_cast<int>(slot.block);
    const glm::ivec3 block(index % blocks.x, (index / blocks.x) % blocks.y, index / (blocks.x * blocks.y));
    for (int local = 0; local < gpu::BLOCK_NODES; ++local) {
      const glm::ivec3 offset(local % gpu::BLOCK_WIDTH, (local / gpu::BLOCK_WIDTH) % gpu::BLOCK_WIDTH,
                              local / (gpu::BLOCK_WIDTH * gpu::BLOCK_WIDTH));
      nodes.push_back(block * gpu::BLOCK_WIDTH + offset);
    }
  }
  return nodes;
}

std::vector<StoredNode> GpuState::readGrid() const {
  const std::vector<glm::ivec3> addresses = activeNodes();
  const std::vector<glm::ivec4> sums = gridMomentumMass_.read<glm::ivec4>(addresses.size());
  return inGridOrder<StoredNode>(addresses, sums);
}

template <class Self>
auto GpuState::stateBuffers(Self& self) {
  std::vector<decltype(&self.positionMass_)> buffers;
  for (auto* buffer : {&self.positionMass_, &self.velocityVolume_, &self.elasticDeformation_, &self.kirchhoffStress_,
                       &self.affine_, &self.plasticState_, &self.watchdog_}) {
    if (*buffer) buffers.push_back(buffer);
  }
  return buffers;
}

std::vector<std::string> GpuState::stateBytes() const {
  std::vector<std::string> bytes;
  for (const gl::Buffer* buffer : stateBuffers(*this)) {
    std::string contents(buffer->bytes(), '\0');
    buffer->download(0, contents.size(), contents.data());
    bytes.push_back(std::move(contents));
  }
  return bytes;
}

void GpuState::checkStateBytes(const std::vector<std::string>& bytes, const std::string& source) const {
  const std::vector<const gl::Buffer*> buffers = stateBuffers(*this);
  if (bytes.size() != buffers.size()) {
    throw InputError(source + ": the checkpoint was written for another scene (or another version of this one); "
                     "resume it with the scene it came from");
  }
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    if (bytes[i].size() != buffers[i]->bytes()) {
      throw InputError(source + ": the checkpoint's buffer " + std::to_string(i) + " has " +
                       std::to_string(bytes[i].size()) + " bytes, the scene needs " +
                       std::to_string(buffers[i]->bytes()));
    }
  }
}

void GpuState::loadStateBytes(const std::vector<std::string>& bytes) {
  const std::vector<gl::Buffer*> buffers = stateBuffers(*this);
  for (std::size_t i = 0; i < buffers.size(); ++i) buffers[i]->upload(0, bytes[i].size(), bytes[i].data());
}

void GpuState::save() {
  const std::vector<gl::Buffer*> buffers = stateBuffers(*this);
  if (saved_.empty()) {
    for (const gl::Buffer* buffer : buffers) saved_.emplace_back(buffer->bytes());
  }
  for (std::size_t i = 0; i < buffers.size(); ++i) saved_[i].copyFrom(*buffers[i], buffers[i]->bytes());
}

void GpuState::restore() {
  if (saved_.empty()) throw std::logic_error("restoreState: no state was saved");
  const std::vector<gl::Buffer*> buffers = stateBuffers(*this);
  for (std::size_t i = 0; i < buffers.size(); ++i) buffers[i]->copyFrom(saved_[i], buffers[i]->bytes());
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

}  // namespace firn
