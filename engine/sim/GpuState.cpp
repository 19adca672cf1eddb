#include "sim/GpuState.h"

#include <cstring>

#include <algorithm>
#include <stdexcept>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include "Error.h"
#include "io/Text.h"

namespace firn {

namespace {

std::string mebibytes(double bytes) { return format("%.4g MiB", bytes / (1024.0 * 1024.0)); }

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
  layout.rigidBodies = scene.rigidBodies.size();
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

namespace {

// The layout, once its block map and its largest particle buffer are known to fit a shader storage block.
const GpuStateLayout& checkedLayout(const GpuStateLayout& layout, const gl::ContextInfo& gl) {
  layout.checkBlockMapFits(gl);
  const double maxBytes = double(gl.maxStorageBlockBytes);
  const std::size_t n = layout.particleCapacity;
  const double particleBytes = double(n) * double(layout.largestParticleBufferBytesPerParticle());
  if (particleBytes > maxBytes) {
    throw InputError(layout.sceneFile + ": bodies: " + std::to_string(n) + " particles need " + mebibytes(particleBytes) +
                     " per particle buffer, more than the " + mebibytes(maxBytes) +
                     " this driver allows; use fewer particles_per_cell");
  }
  return layout;
}

}  // namespace

GpuState::GpuState(const GpuStateLayout& layout, const MaterialTable& materials,
                   const std::vector<gpu::ColliderParams>& colliders, const std::vector<gpu::BodyRecord>& bodyRecords,
                   const std::vector<float>& colliderFields, const gl::ContextInfo& gl,
                   const gl::ShaderOptions& options)
    : layout_(checkedLayout(layout, gl)),
      particles_(layout_.particleCapacity, layout_.deformationGradient, layout_.affine),
      grid_(layout_, gl::ShaderLibrary(), options, gl) {
  if (layout_.semiImplicit) solver_.emplace(layout_.particleCapacity, layout_.rigidBodies);
  materials_ = gl::Buffer::fromVector(materials.entries).labelled("materials");
  colliders_ = gl::Buffer::fromVector(colliders).labelled("colliders");
  if (colliderFields.size() > std::size_t(gl.maxTextureBufferTexels)) {
    throw InputError(layout_.sceneFile + ": colliders: the distance fields and contact probes hold " +
                     std::to_string(colliderFields.size()) + " floats, more than the " +
                     std::to_string(gl.maxTextureBufferTexels) + " texels " + gl.renderer +
                     " allows a buffer texture; lower the mesh colliders' and bodies' \"resolution\"");
  }
  colliderFields_ = gl::BufferTexture(colliderFields);
  // The bodies' contact slots, empty, then a record per body (one, unused, without bodies: the semi-implicit passes
  // declare the block whether or not the scene has bodies, and a bound buffer is never empty).
  if (bodyRecords.size() != std::max<std::size_t>(layout_.rigidBodies, 1)) {
    throw std::logic_error("GpuState: " + std::to_string(bodyRecords.size()) + " body records for " +
                           std::to_string(layout_.rigidBodies) + " rigid bodies");
  }
  bodies_ = gl::Buffer(bodyRecordsOffset() + bodyRecords.size() * sizeof(gpu::BodyRecord))
                .labelled("rigid bodies: contacts and records");
  writeBodyRecords(bodyRecords);
  stepUniforms_ = gl::Buffer(sizeof(gpu::StepUniforms)).labelled("step uniforms");
  // The watchdog's status, then the energy ledger and a load per entry of the collider table, empty (gpu_contract.h,
  // EnergyLedger, ObjectLoad).
  const gpu::WatchdogStatus clearStatus{0, -1, 0, 0, 0, -1, 0, 0, -1, 0, 0.0f, 0};
  objectCount_ = colliders.size();
  std::string contents(sizeof clearStatus + energyBytes(), '\0');
  std::memcpy(contents.data(), &clearStatus, sizeof clearStatus);
  watchdog_ = gl::Buffer(contents.size(), contents.data()).labelled("watchdog, energy ledger and object loads");
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
  grid_.allocatePool(capacity);
  if (solver_) solver_->allocatePool(capacity);
  publish();
}

void GpuState::growParticles(std::size_t capacity, const gl::ContextInfo& gl) {
  if (capacity <= layout_.particleCapacity) return;
  GpuStateLayout layout = layout_;
  layout.particleCapacity = capacity;
  checkedLayout(layout, gl);
  ParticleBuffers grown(capacity, layout.deformationGradient, layout.affine);
  const std::vector<gl::Buffer*> from = particles_.stateBuffers();
  const std::vector<gl::Buffer*> to = grown.stateBuffers();
  for (std::size_t i = 0; i < from.size(); ++i) to[i]->copyFrom(*from[i], from[i]->bytes());
  particles_ = std::move(grown);
  layout_ = layout;
  grid_.allocateParticles(capacity);
  if (solver_) {  // per step only: nothing to keep
    solver_.emplace(capacity, layout_.rigidBodies);
    solver_->allocatePool(grid_.usage().capacity);
  }
  if (!saved_.empty()) {
    // The saved state's buffers as large as the live ones, the saved contents kept.
    const std::vector<gl::Buffer*> live = stateBuffers();
    for (std::size_t i = 0; i < live.size(); ++i) {
      gl::Buffer larger(live[i]->bytes());
      larger.copyFrom(saved_[i], saved_[i].bytes());
      saved_[i] = std::move(larger);
    }
  }
  publish();
}

void GpuState::publish() {
  bindings_.unpublishAll();
  particles_.publish(bindings_);
  grid_.publish(bindings_);
  if (solver_) solver_->publish(bindings_);
  bindings_.storage(FIRN_BINDING_MATERIALS, materials_);
  bindings_.storage(FIRN_BINDING_COLLIDERS, colliders_);
  bindings_.texture(FIRN_TEXTURE_UNIT_COLLIDER_FIELDS, colliderFields_);
  bindings_.storage(FIRN_BINDING_WATCHDOG, watchdog_);
  bindings_.storage(FIRN_BINDING_BODIES, bodies_);
  bindings_.uniform(FIRN_BINDING_STEP_UNIFORMS, stepUniforms_);
}

void GpuState::resizeBlockPool(std::size_t capacity, const gl::ContextInfo& gl) {
  layout_.blockCapacity = capacity;
  allocateBlockPool(gl);
}

BlockUsage GpuState::blockUsage() const {
  BlockUsage usage = grid_.usage();
  if (solver_) usage.poolBytes += solver_->poolBytes();
  return usage;
}

void GpuState::writeStepUniforms(const gpu::StepUniforms& uniforms) {
  stepUniforms_.upload(0, sizeof uniforms, &uniforms);
}

void GpuState::writeColliders(const std::vector<gpu::ColliderParams>& colliders, std::size_t first) {
  colliders_.upload(first * sizeof(gpu::ColliderParams), colliders.size() * sizeof(gpu::ColliderParams),
                    colliders.data());
}

void GpuState::writeMaterials(const MaterialTable& materials) {
  materials_.upload(0, materials.entries.size() * sizeof(gpu::MaterialParams), materials.entries.data());
}

std::vector<gpu::ColliderParams> GpuState::readColliders(std::size_t first, std::size_t count) const {
  return colliders_.read<gpu::ColliderParams>(count, first);
}

gpu::WatchdogStatus GpuState::watchdog() const { return watchdog_.read<gpu::WatchdogStatus>(1)[0]; }

std::size_t GpuState::energyBytes() const { return sizeof(gpu::EnergyLedger) + objectCount_ * sizeof(gpu::ObjectLoad); }

gpu::EnergyLedger GpuState::energyLedger() const {
  gpu::EnergyLedger ledger{};
  watchdog_.download(sizeof(gpu::WatchdogStatus), sizeof ledger, &ledger);
  return ledger;
}

std::vector<gpu::ObjectLoad> GpuState::objectLoads() const {
  return watchdog_.read<gpu::ObjectLoad>(objectCount_,
                                         (sizeof(gpu::WatchdogStatus) + sizeof(gpu::EnergyLedger)) / sizeof(gpu::ObjectLoad));
}

std::string GpuState::energyRecords() const {
  std::string bytes(energyBytes(), '\0');
  watchdog_.download(sizeof(gpu::WatchdogStatus), bytes.size(), bytes.data());
  return bytes;
}

void GpuState::writeEnergyRecords(const std::string& bytes) {
  const std::string empty(energyBytes(), '\0');
  const std::string& contents = bytes.empty() ? empty : bytes;
  watchdog_.upload(sizeof(gpu::WatchdogStatus), contents.size(), contents.data());
}

double GpuState::fastestSignalMPerS() const {
  std::uint32_t bits = 0;
  watchdog_.download(offsetof(gpu::WatchdogStatus, maxSpeedBits), sizeof bits, &bits);  // prepare_grid resets it
  return glm::uintBitsToFloat(bits);
}

// The particles' buffers, then the watchdog, then with rigid bodies the collider table (the bodies' poses and
// velocities) and the bodies' contacts and records (their dynamics; the last step's contacts start the next's): the
// order of a checkpoint's sections.
template <class Self>
auto GpuState::stateBuffersOf(Self& self) {
  auto buffers = self.particles_.stateBuffers();
  buffers.push_back(&self.watchdog_);
  if (self.layout_.rigidBodies > 0) {
    buffers.push_back(&self.colliders_);
    buffers.push_back(&self.bodies_);
  }
  return buffers;
}

std::size_t GpuState::bodyRecordsOffset() { return std::size_t(gpu::CONTACT_SLOTS) * sizeof(gpu::BodyContact); }

void GpuState::writeBodyRecords(const std::vector<gpu::BodyRecord>& records, std::size_t first) {
  bodies_.upload(bodyRecordsOffset() + first * sizeof(gpu::BodyRecord), records.size() * sizeof(gpu::BodyRecord),
                 records.data());
}

std::vector<gpu::BodyRecord> GpuState::readBodyRecords(std::size_t first, std::size_t count) const {
  std::vector<gpu::BodyRecord> records(count);
  bodies_.download(bodyRecordsOffset() + first * sizeof(gpu::BodyRecord), count * sizeof(gpu::BodyRecord),
                   records.data());
  return records;
}

std::vector<const gl::Buffer*> GpuState::stateBuffers() const { return stateBuffersOf(*this); }

std::vector<gl::Buffer*> GpuState::stateBuffers() { return stateBuffersOf(*this); }

std::vector<std::string> GpuState::stateBytes() const {
  std::vector<std::string> bytes;
  for (const gl::Buffer* buffer : stateBuffers()) {
    std::string contents(buffer->bytes(), '\0');
    buffer->download(0, contents.size(), contents.data());
    bytes.push_back(std::move(contents));
  }
  return bytes;
}

void GpuState::checkStateBytes(const std::vector<std::string>& bytes, const std::string& source,
                               std::size_t particleCapacity) const {
  const std::vector<const gl::Buffer*> buffers = stateBuffers();
  if (bytes.size() != buffers.size()) {
    throw InputError(source + ": the checkpoint was written for another scene (or another version of this one); "
                     "resume it with the scene it came from");
  }
  const std::size_t particleArrays = particles_.stateBuffers().size();
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    const std::size_t needed = i < particleArrays && particleCapacity > 0
                                   ? buffers[i]->bytes() / layout_.particleCapacity * particleCapacity
                                   : buffers[i]->bytes();
    if (bytes[i].size() != needed) {
      throw InputError(source + ": the checkpoint's buffer " + std::to_string(i) + " has " +
                       std::to_string(bytes[i].size()) + " bytes, the scene needs " + std::to_string(needed));
    }
  }
}

void GpuState::loadStateBytes(const std::vector<std::string>& bytes) {
  const std::vector<gl::Buffer*> buffers = stateBuffers();
  for (std::size_t i = 0; i < buffers.size(); ++i) buffers[i]->upload(0, bytes[i].size(), bytes[i].data());
}

void GpuState::save() {
  const std::vector<gl::Buffer*> buffers = stateBuffers();
  if (saved_.empty()) {
    for (const gl::Buffer* buffer : buffers) saved_.emplace_back(buffer->bytes());
  }
  for (std::size_t i = 0; i < buffers.size(); ++i) saved_[i].copyFrom(*buffers[i], buffers[i]->bytes());
}

StorageRecordBytes GpuState::storageRecordBytes() const {
  StorageRecordBytes records;
  records.perParticle.assign(FIRN_SOLVER_BINDINGS_END, 0);
  records.perNode.assign(FIRN_SOLVER_BINDINGS_END, 0);
  const std::size_t particles = particleCapacity();
  const std::size_t nodes = grid_.capacity() * std::size_t(gpu::BLOCK_NODES);
  const auto recordOf = [&](unsigned binding, std::size_t count) {
    const gl::Buffer* buffer = bindings_.storageAt(binding);
    return buffer != nullptr && *buffer && count > 0 ? buffer->bytes() / count : 0;
  };
  for (const unsigned binding : {FIRN_BINDING_POSITION_MASS, FIRN_BINDING_VELOCITY_VOLUME,
                                 FIRN_BINDING_ELASTIC_DEFORMATION, FIRN_BINDING_KIRCHHOFF_STRESS, FIRN_BINDING_AFFINE,
                                 FIRN_BINDING_PLASTIC_STATE, FIRN_BINDING_SORTED_PARTICLES,
                                 FIRN_BINDING_PARTICLE_RANKS, FIRN_BINDING_SOLVER_PARTICLES}) {
    records.perParticle[binding] = recordOf(binding, particles);
  }
  for (const unsigned binding : {FIRN_BINDING_GRID_MOMENTUM_MASS, FIRN_BINDING_GRID_IMPULSE, FIRN_BINDING_BINS,
                                 FIRN_BINDING_SOLVER_NODES, FIRN_BINDING_SOLVER_PRECONDITIONER}) {
    records.perNode[binding] = recordOf(binding, nodes);
  }
  return records;
}

void GpuState::restore() {
  if (saved_.empty()) throw std::logic_error("restoreState: no state was saved");
  const std::vector<gl::Buffer*> buffers = stateBuffers();
  for (std::size_t i = 0; i < buffers.size(); ++i) buffers[i]->copyFrom(saved_[i], buffers[i]->bytes());
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

}  // namespace firn
