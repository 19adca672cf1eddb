#include "sim/GpuState.h"

#include <limits>
#include <sstream>
#include <stdexcept>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include "Error.h"

namespace firn {

namespace {

// Empty cell bounds: any cell lowers the minimum and raises the maximum.
constexpr glm::ivec4 kNoCellMin(std::numeric_limits<int>::max());
constexpr glm::ivec4 kNoCellMax(std::numeric_limits<int>::min());

std::string mebibytes(double bytes) {
  std::ostringstream out;
  out.precision(4);
  out << bytes / (1024.0 * 1024.0) << " MiB";
  return out.str();
}

gpu::Mat3x4 identityMat3() { return {{glm::vec4(1, 0, 0, 0), glm::vec4(0, 1, 0, 0), glm::vec4(0, 0, 1, 0)}}; }

}  // namespace

GpuStateLayout GpuStateLayout::forScene(const Scene& scene, std::size_t particleCapacity, bool deformationGradient) {
  GpuStateLayout layout;
  layout.grid = scene.grid;
  layout.particleCapacity = particleCapacity;
  layout.deformationGradient = deformationGradient;
  layout.affine = scene.solver.transfer == Transfer::Apic;
  layout.impulse = scene.solver.transfer == Transfer::PicFlip;
  layout.blockBins = scene.solver.atomics == Atomics::None;
  return layout;
}

GpuState::GpuState(const GpuStateLayout& layout, const MaterialTable& materials,
                   const std::vector<gpu::ColliderParams>& colliders, const gl::ContextInfo& gl)
    : layout_(layout) {
  const glm::ivec3 nodes = gridNodes();
  const double gridBufferBytes = double(nodes.x) * nodes.y * nodes.z * sizeof(glm::ivec4);
  const double maxBytes = double(gl.maxStorageBlockBytes);
  if (gridBufferBytes > maxBytes) {
    const glm::ivec3 cells = layout_.grid.cells;
    throw InputError("grid.cells: " + std::to_string(cells.x) + "×" + std::to_string(cells.y) + "×" +
                     std::to_string(cells.z) + " cells need " + mebibytes(gridBufferBytes) + " per grid buffer, but " +
                     gl.renderer + " allows " + mebibytes(maxBytes) + " per shader storage block; use fewer cells");
  }
  const std::size_t n = layout_.particleCapacity;
  const double particleBytes = double(n) * sizeof(gpu::Mat3x4);
  if (particleBytes > maxBytes) {
    throw InputError("bodies: " + std::to_string(n) + " particles need " + mebibytes(particleBytes) +
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
  if (layout_.blockBins) {
    particleSlots_ = gl::Buffer(n * sizeof(std::uint32_t));
    blockParticles_ = gl::Buffer(n * sizeof(std::uint32_t));
  }
  gridMomentumMass_ = gl::Buffer(static_cast<std::size_t>(gridBufferBytes));
  if (layout_.impulse) gridImpulse_ = gl::Buffer(static_cast<std::size_t>(gridBufferBytes));
  stepUniforms_ = gl::Buffer(sizeof(gpu::StepUniforms));
  if (layout_.blockBins) {
    gpu::BlockTableHeader header{};
    header.blocksPerAxis = glm::ivec4((nodes + gpu::BLOCK_CELLS - 1) / gpu::BLOCK_CELLS, 0);
    const std::size_t blocks = std::size_t(header.blocksPerAxis.x) * header.blocksPerAxis.y * header.blocksPerAxis.z;
    blocks_ = gl::Buffer(sizeof header + blocks * sizeof(glm::uvec2));
    blocks_.upload(0, sizeof header, &header);
    blockOrder_ = gl::Buffer(blocks * sizeof(std::uint32_t));
  }
  const gpu::WatchdogStatus clearWatchdog{0, -1, 0, 0, 0, -1, 0, 0, -1, 0, 0.0f, 0};
  watchdog_ = gl::Buffer(sizeof clearWatchdog, &clearWatchdog);
  activeRegion_ = gl::Buffer(sizeof(gpu::ActiveRegionData));
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
  activeRegion_.bindStorage(FIRN_BINDING_ACTIVE_REGION);
  watchdog_.bindStorage(FIRN_BINDING_WATCHDOG);
  if (blocks_) {
    blocks_.bindStorage(FIRN_BINDING_BLOCKS);
    particleSlots_.bindStorage(FIRN_BINDING_PARTICLE_SLOTS);
    blockParticles_.bindStorage(FIRN_BINDING_BLOCK_PARTICLES);
    blockOrder_.bindStorage(FIRN_BINDING_BLOCK_ORDER);
  }
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

void GpuState::accumulateCells(const std::vector<glm::vec3>& positions, glm::ivec4& cellMin, glm::ivec4& cellMax) const {
  const glm::vec3 origin(layout_.grid.originM);
  const float cellSize = float(layout_.grid.cellSizeM);
  for (const glm::vec3& x : positions) {
    const glm::ivec4 cell(glm::ivec3(glm::floor((x - origin) / cellSize)), 0);
    cellMin = glm::min(cellMin, cell);
    cellMax = glm::max(cellMax, cell);
  }
}

void GpuState::seedActiveRegion(const std::vector<glm::vec3>& positions) {
  gpu::ActiveRegionData region{};
  region.particleCellMin = kNoCellMin;
  region.particleCellMax = kNoCellMax;
  accumulateCells(positions, region.particleCellMin, region.particleCellMax);
  region.addedCellMin = addedCellMin_ = kNoCellMin;
  region.addedCellMax = addedCellMax_ = kNoCellMax;
  activeRegion_.upload(0, sizeof region, &region);
}

void GpuState::addParticleCells(const std::vector<glm::vec3>& positions) {
  accumulateCells(positions, addedCellMin_, addedCellMax_);
  const glm::ivec4 added[2] = {addedCellMin_, addedCellMax_};
  // The last prepare_grid reset these bounds on the GPU: its write must land before this one.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  activeRegion_.upload(offsetof(gpu::ActiveRegionData, addedCellMin), sizeof added, added);
}

void GpuState::consumeAddedCells() {
  addedCellMin_ = kNoCellMin;
  addedCellMax_ = kNoCellMax;
}

gpu::ActiveRegionData GpuState::activeRegion() const { return activeRegion_.read<gpu::ActiveRegionData>(1)[0]; }

gpu::WatchdogStatus GpuState::watchdog() const { return watchdog_.read<gpu::WatchdogStatus>(1)[0]; }

double GpuState::fastestSignalMPerS() const {
  std::uint32_t bits = 0;
  watchdog_.download(offsetof(gpu::WatchdogStatus, maxSpeedBits), sizeof bits, &bits);  // prepare_grid resets it
  return glm::uintBitsToFloat(bits);
}

std::vector<glm::ivec4> GpuState::readGrid(std::size_t firstNode, std::size_t count) const {
  return gridMomentumMass_.read<glm::ivec4>(count, firstNode);
}

template <class Self>
auto GpuState::stateBuffers(Self& self) {
  std::vector<decltype(&self.positionMass_)> buffers;
  for (auto* buffer : {&self.positionMass_, &self.velocityVolume_, &self.elasticDeformation_, &self.kirchhoffStress_,
                       &self.affine_, &self.plasticState_, &self.activeRegion_, &self.watchdog_}) {
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
  consumeAddedCells();  // written between steps, when nothing was pending
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
  consumeAddedCells();  // saved between steps, when nothing was pending
}

}  // namespace firn
