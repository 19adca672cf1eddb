#include "sim/Simulation.h"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "Error.h"
#include "gl/Debug.h"
#include "sim/Materials.h"

namespace firn {

namespace {

constexpr GLuint kParticleGroupSize = 128;  // local_size_x of the particle passes
// Empty cell bounds: any cell lowers the minimum and raises the maximum.
constexpr glm::ivec4 kNoCellMin(std::numeric_limits<int>::max());
constexpr glm::ivec4 kNoCellMax(std::numeric_limits<int>::min());

std::string formatNumber(double value) {
  std::ostringstream out;
  out.precision(4);
  out << value;
  return out.str();
}

std::string mebibytes(double bytes) { return formatNumber(bytes / (1024.0 * 1024.0)) + " MiB"; }

const char* channelName(std::uint32_t channel) {
  static const char* const names[] = {"mass", "momentum x", "momentum y", "momentum z",
                                      "impulse x", "impulse y", "impulse z"};
  return channel < 7 ? names[channel] : "unknown";
}

gpu::Mat3x4 identityMat3() {
  return {{glm::vec4(1, 0, 0, 0), glm::vec4(0, 1, 0, 0), glm::vec4(0, 0, 1, 0)}};
}

}  // namespace

namespace {

// The particles present from the start; the emitters' others go to `pending`, in order of release.
std::vector<ParticleSeed> splitByRelease(const std::vector<ParticleSeed>& particles, std::vector<ParticleSeed>& pending) {
  std::vector<ParticleSeed> initial;
  for (const ParticleSeed& seed : particles) (seed.releaseTimeS > 0 ? pending : initial).push_back(seed);
  std::stable_sort(pending.begin(), pending.end(),
                   [](const ParticleSeed& a, const ParticleSeed& b) { return a.releaseTimeS < b.releaseTimeS; });
  return initial;
}

}  // namespace

Simulation::Simulation(const Scene& scene, const std::vector<ParticleSeed>& seeds, const gl::ContextInfo& gl,
                       std::size_t particleCapacity, MaterialPrograms programs)
    : scene_(scene), materialPrograms_(programs), particleCapacity_(std::max(particleCapacity, seeds.size())),
      gridNodes_(scene.grid.cells + 1),
      maxWorkGroupsX_(gl.maxComputeWorkGroupCountX) {
  if (seeds.empty()) throw InputError("bodies: the scene has no particles");
  const std::vector<ParticleSeed> particles = splitByRelease(seeds, pendingParticles_);
  particleCount_ = particles.size();
  if (scene_.solver.atomics == Atomics::Float && !gl.hasFloatAtomics) {
    throw InputError("solver.atomics: \"float\" needs GL_NV_shader_atomic_float, which " + gl.renderer +
                     " does not offer; use \"fixed\"");
  }
  const double nodes = double(gridNodes_.x) * gridNodes_.y * gridNodes_.z;
  const double gridBufferBytes = nodes * sizeof(glm::ivec4);
  if (gridBufferBytes > double(gl.maxStorageBlockBytes)) {
    throw InputError("grid.cells: " + std::to_string(scene_.grid.cells.x) + "×" + std::to_string(scene_.grid.cells.y) +
                     "×" + std::to_string(scene_.grid.cells.z) + " cells need " + mebibytes(gridBufferBytes) +
                     " per grid buffer, but " + gl.renderer + " allows " + mebibytes(double(gl.maxStorageBlockBytes)) +
                     " per shader storage block; use fewer cells");
  }
  const double particleBytes = double(particleCapacity_) * sizeof(gpu::Mat3x4);
  if (particleBytes > double(gl.maxStorageBlockBytes)) {
    throw InputError("bodies: " + std::to_string(particleCapacity_) + " particles need " + mebibytes(particleBytes) +
                     " per particle buffer, more than the " + mebibytes(double(gl.maxStorageBlockBytes)) +
                     " this driver allows; use fewer particles_per_cell");
  }

  fixedPoint_ = fixedPointScaleFor(scene_, seeds);

  buildPrograms();
  uploadMaterialsAndColliders();
  allocateParticles();
  writeParticles(0, particles, scene_.solver.particleVolume == ParticleVolume::MaterialDensity);
  gridMomentumMass_ = gl::Buffer(static_cast<std::size_t>(gridBufferBytes));
  if (scene_.solver.transfer == Transfer::PicFlip) gridImpulse_ = gl::Buffer(static_cast<std::size_t>(gridBufferBytes));
  stepUniforms_ = gl::Buffer(sizeof(gpu::StepUniforms));
  if (binsParticles()) {
    gpu::BlockTableHeader header{};
    header.blocksPerAxis = glm::ivec4((gridNodes_ + gpu::kBlockCells - 1) / gpu::kBlockCells, 0);
    const std::size_t blocks = std::size_t(header.blocksPerAxis.x) * header.blocksPerAxis.y * header.blocksPerAxis.z;
    blocks_ = gl::Buffer(sizeof header + blocks * sizeof(glm::uvec2));
    blocks_.upload(0, sizeof header, &header);
    blockOrder_ = gl::Buffer(blocks * sizeof(std::uint32_t));
  }
  // What a checkpoint must match: the grid, the step, the materials and every seed, field by field (the struct
  // has padding, whose bytes are not defined).
  const MaterialTable table = buildMaterialTable(scene_);
  sceneFingerprint_ = fingerprint(&gridNodes_, sizeof gridNodes_);
  for (const double value : {scene_.grid.cellSizeM, scene_.time.dtS, double(particleCapacity_)}) {
    sceneFingerprint_ = fingerprint(&value, sizeof value, sceneFingerprint_);
  }
  sceneFingerprint_ = fingerprint(table.entries.data(), table.entries.size() * sizeof(gpu::MaterialParams), sceneFingerprint_);
  for (const ParticleSeed& seed : seeds) {
    sceneFingerprint_ = fingerprint(&seed.positionM, sizeof seed.positionM, sceneFingerprint_);
    sceneFingerprint_ = fingerprint(&seed.velocityMPerS, sizeof seed.velocityMPerS, sceneFingerprint_);
    sceneFingerprint_ = fingerprint(&seed.massKg, sizeof seed.massKg, sceneFingerprint_);
    sceneFingerprint_ = fingerprint(&seed.releaseTimeS, sizeof seed.releaseTimeS, sceneFingerprint_);
  }
  const gpu::WatchdogStatus clearWatchdog{0, -1, 0, 0, 0, -1, 0, 0, -1, 0, 0.0f, 0};
  const double fastestWaveMPerS = stiffestBody(scene_).waveSpeedMPerS;
  for (const ParticleSeed& seed : seeds) {
    fastestSpeedMPerS_ = std::max(fastestSpeedMPerS_, double(glm::length(seed.velocityMPerS)) + fastestWaveMPerS);
  }
  watchdog_ = gl::Buffer(sizeof clearWatchdog, &clearWatchdog);
  activeRegion_ = gl::Buffer(sizeof(gpu::ActiveRegionData));

  std::vector<glm::vec3> positions;
  positions.reserve(particles.size());
  for (const ParticleSeed& seed : particles) positions.push_back(seed.positionM);
  seedActiveRegion(positions);

  // Initial volumes (Stomakhin 2013 §6 step 2): one P2G of mass, then V0 = m / ρ from the grid density, unless
  // the scene takes them from the materials' densities (written above).
  if (scene_.solver.particleVolume == ParticleVolume::GridDensity) {
    writeStepUniforms(scene_.time.dtS);
    scatterToGrid();
    runOverParticles(computeVolumes_);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
}

void Simulation::buildPrograms() {
  gl::ShaderOptions options;
  options.defines = gpu::bindingDefines();
  options.defines.emplace_back("FIRN_PARTICLE_GROUP_SIZE", std::to_string(kParticleGroupSize));
  options.defines.emplace_back("FIRN_WALL_CELLS", std::to_string(GridSpec::wallCells));
  options.defines.emplace_back(scene_.solver.kernel == Kernel::Cubic ? "FIRN_KERNEL_CUBIC" : "FIRN_KERNEL_QUADRATIC", "1");
  options.defines.emplace_back(scene_.solver.transfer == Transfer::Apic ? "FIRN_TRANSFER_APIC" : "FIRN_TRANSFER_PIC_FLIP", "1");
  if (!scene_.colliders.empty()) options.defines.emplace_back("FIRN_HAS_COLLIDERS", "1");
  // Only the material models present are compiled in, and F only where one of them needs it.
  for (const auto& [model, define] : {std::pair{MaterialModel::Snow, "FIRN_MATERIAL_SNOW"},
                                      std::pair{MaterialModel::FixedCorotated, "FIRN_MATERIAL_FIXED_COROTATED"},
                                      std::pair{MaterialModel::NeoHookean, "FIRN_MATERIAL_NEO_HOOKEAN"},
                                      std::pair{MaterialModel::Water, "FIRN_MATERIAL_WATER"},
                                      std::pair{MaterialModel::DruckerPrager, "FIRN_MATERIAL_DRUCKER_PRAGER"}}) {
    const bool present = materialPrograms_ == MaterialPrograms::EveryModel ||
                         std::any_of(scene_.materials.begin(), scene_.materials.end(),
                                     // A copy: C++17 cannot capture a structured binding (clang refuses).
                                     [model = model](const Material& material) { return material.model == model; });
    if (present) options.defines.emplace_back(define, "1");
  }
  if (needsDeformationGradient()) options.defines.emplace_back("FIRN_HAS_DEFORMATION_GRADIENT", "1");
  if (scene_.time.adaptive) options.defines.emplace_back("FIRN_ADAPTIVE_DT", "1");
  if (scene_.solver.atomics == Atomics::Float) {
    options.defines.emplace_back("FIRN_FLOAT_ATOMICS", "1");
    options.extensions.push_back("GL_NV_shader_atomic_float");
  }
  if (binsParticles()) {
    options.defines.emplace_back("FIRN_P2G_BLOCKS", "1");
    options.defines.emplace_back("FIRN_BLOCK_CELLS", std::to_string(gpu::kBlockCells));
    options.defines.emplace_back("FIRN_BLOCK_COLORS", std::to_string(gpu::kBlockColors));
    options.defines.emplace_back("FIRN_MAX_BIN_PARTICLES", std::to_string(gpu::kMaxBinParticles));
    options.defines.emplace_back("FIRN_BIN_OVERFLOW_CHANNEL", std::to_string(gpu::kBinOverflowChannel));
  }
  const gl::ShaderLibrary library;
  prepareGrid_ = gl::Program::compute(library, "sim/prepare_grid.comp", options);
  clearGrid_ = gl::Program::compute(library, "sim/clear_grid.comp", options);
  if (binsParticles()) {
    binCount_ = gl::Program::compute(library, "sim/bin_count.comp", options);
    binScan_ = gl::Program::compute(library, "sim/bin_scan.comp", options);
    binPlace_ = gl::Program::compute(library, "sim/bin_place.comp", options);
    particleToGridBlocks_ = gl::Program::compute(library, "sim/p2g_blocks.comp", options);
  } else {
    particleToGrid_ = gl::Program::compute(library, "sim/p2g.comp", options);
  }
  updateGrid_ = gl::Program::compute(library, "sim/update_grid.comp", options);
  gridToParticle_ = gl::Program::compute(library, "sim/g2p.comp", options);
  computeVolumes_ = gl::Program::compute(library, "sim/compute_volumes.comp", options);
}

bool Simulation::needsDeformationGradient() const {
  if (materialPrograms_ == MaterialPrograms::EveryModel) return true;
  return std::any_of(scene_.materials.begin(), scene_.materials.end(),
                     [](const Material& material) { return material.needsDeformationGradient(); });
}

void Simulation::allocateParticles() {
  const std::size_t n = particleCapacity_;
  positionMass_ = gl::Buffer(n * sizeof(glm::vec4));
  velocityVolume_ = gl::Buffer(n * sizeof(glm::vec4));
  plasticState_ = gl::Buffer(n * sizeof(gpu::ParticlePlasticState));
  if (needsDeformationGradient()) elasticDeformation_ = gl::Buffer(n * sizeof(gpu::Mat3x4));
  kirchhoffStress_ = gl::Buffer(n * sizeof(gpu::Mat3x4));
  if (scene_.solver.transfer == Transfer::Apic) affine_ = gl::Buffer(n * sizeof(gpu::Mat3x4));
  if (binsParticles()) {
    particleSlots_ = gl::Buffer(n * sizeof(std::uint32_t));
    blockParticles_ = gl::Buffer(n * sizeof(std::uint32_t));
  }
  particleBody_.reserve(n);
  particleMaterial_.reserve(n);
}

// Writes particles [first, first + particles.size()) as new: undeformed, unstressed, no affine velocity.
void Simulation::writeParticles(std::size_t first, const std::vector<ParticleSeed>& particles, bool volumeFromDensity) {
  const std::size_t n = particles.size();
  std::vector<glm::vec4> positionMass;
  std::vector<glm::vec4> velocityVolume;
  std::vector<gpu::ParticlePlasticState> plastic;
  positionMass.reserve(n);
  velocityVolume.reserve(n);
  plastic.reserve(n);
  for (const ParticleSeed& seed : particles) {
    positionMass.emplace_back(seed.positionM, seed.massKg);
    // Otherwise V0 comes from compute_volumes.comp.
    const double volumeM3 =
        volumeFromDensity ? seed.massKg / scene_.materials.at(std::size_t(seed.materialIndex)).densityKgPerM3 : 0.0;
    velocityVolume.emplace_back(seed.velocityMPerS, float(volumeM3));
    const std::uint32_t materialEntry = seed.bodyIndex >= 0 ? bodyMaterialEntry_.at(std::size_t(seed.bodyIndex))
                                                            : static_cast<std::uint32_t>(seed.materialIndex);
    // Sand's hardening state q starts at 0; J_P (snow) and J (water) start at 1.
    const bool sand = scene_.materials.at(std::size_t(seed.materialIndex)).model == MaterialModel::DruckerPrager;
    plastic.push_back({sand ? 0.0f : 1.0f, materialEntry, 0.0f, 0.0f});
    particleBody_.push_back(seed.bodyIndex);
    particleMaterial_.push_back(seed.materialIndex);
  }
  positionMass_.upload(first * sizeof(glm::vec4), n * sizeof(glm::vec4), positionMass.data());
  velocityVolume_.upload(first * sizeof(glm::vec4), n * sizeof(glm::vec4), velocityVolume.data());
  plasticState_.upload(first * sizeof(gpu::ParticlePlasticState), n * sizeof(gpu::ParticlePlasticState), plastic.data());
  // Snow starts undeformed: F_E = I, so its stress is zero.
  const std::vector<gpu::Mat3x4> identity(n, identityMat3());
  if (elasticDeformation_) {
    elasticDeformation_.upload(first * sizeof(gpu::Mat3x4), n * sizeof(gpu::Mat3x4), identity.data());
  }
  const std::vector<gpu::Mat3x4> zero(n, gpu::Mat3x4{});
  kirchhoffStress_.upload(first * sizeof(gpu::Mat3x4), n * sizeof(gpu::Mat3x4), zero.data());
  if (affine_) affine_.upload(first * sizeof(gpu::Mat3x4), n * sizeof(gpu::Mat3x4), zero.data());
}

void Simulation::addParticles(const std::vector<ParticleSeed>& particles) {
  if (particles.empty()) return;
  if (particles.size() > particleCapacity_ - particleCount_) {
    throw std::length_error("addParticles: " + std::to_string(particles.size()) + " particles do not fit: " +
                            std::to_string(particleCount_) + " of " + std::to_string(particleCapacity_) + " in use");
  }
  for (const ParticleSeed& seed : particles) {
    // The fixed-point bounds were derived for masses up to m_ref (design.md, "Fixed-point atomics").
    if (double(seed.massKg) > fixedPoint_.referenceMassKg) {
      throw std::invalid_argument("addParticles: a particle of " + formatNumber(seed.massKg) +
                                  " kg exceeds the fixed-point reference mass " +
                                  formatNumber(fixedPoint_.referenceMassKg) + " kg");
    }
  }
  writeParticles(particleCount_, particles, true);
  particleCount_ += particles.size();
  std::vector<glm::vec3> positions;
  positions.reserve(particles.size());
  for (const ParticleSeed& seed : particles) positions.push_back(seed.positionM);
  noteAddedParticles(positions);
}

void Simulation::uploadMaterialsAndColliders() {
  const MaterialTable table = buildMaterialTable(scene_);
  materials_ = gl::Buffer::fromVector(table.entries);
  bodyMaterialEntry_ = table.bodyEntry;

  // One zeroed element stands in when there are none, so the binding is always a valid buffer.
  std::vector<gpu::ColliderParams> colliders(std::max<std::size_t>(scene_.colliders.size(), 1), gpu::ColliderParams{});
  for (std::size_t i = 0; i < scene_.colliders.size(); ++i) {
    const Collider& c = scene_.colliders[i];
    gpu::ColliderParams& out = colliders[i];
    switch (c.shape) {
      case ColliderShape::Plane:
        out.geometryA = glm::vec4(glm::vec3(c.pointM), 0);
        out.geometryB = glm::vec4(glm::vec3(glm::normalize(c.normal)), 0);
        out.shapeBoundary.x = int(gpu::ColliderShapeCode::Plane);
        break;
      case ColliderShape::Sphere:
        out.geometryA = glm::vec4(glm::vec3(c.centerM), float(c.radiusM));
        out.shapeBoundary.x = int(gpu::ColliderShapeCode::Sphere);
        break;
      case ColliderShape::Box:
        out.geometryA = glm::vec4(glm::vec3(c.minM), 0);
        out.geometryB = glm::vec4(glm::vec3(c.maxM), 0);
        out.shapeBoundary.x = int(gpu::ColliderShapeCode::Box);
        break;
    }
    out.velocityFriction = glm::vec4(glm::vec3(c.velocityMPerS), float(c.friction));
    out.shapeBoundary.y = c.boundary == Boundary::Sticky ? int(gpu::BoundaryCode::Sticky)
                          : c.boundary == Boundary::Slip ? int(gpu::BoundaryCode::Slip)
                                                         : int(gpu::BoundaryCode::Separate);
  }
  colliders_ = gl::Buffer::fromVector(colliders);
}

void Simulation::accumulateCells(const std::vector<glm::vec3>& positions, glm::ivec4& cellMin, glm::ivec4& cellMax) const {
  const glm::vec3 origin(scene_.grid.originM);
  const float cellSize = float(scene_.grid.cellSizeM);
  for (const glm::vec3& x : positions) {
    const glm::ivec4 cell(glm::ivec3(glm::floor((x - origin) / cellSize)), 0);
    cellMin = glm::min(cellMin, cell);
    cellMax = glm::max(cellMax, cell);
  }
}

// The bounds the next prepare_grid reads, as if the last G2P had seen exactly these particles.
void Simulation::seedActiveRegion(const std::vector<glm::vec3>& positions) {
  gpu::ActiveRegionData region{};
  region.particleCellMin = kNoCellMin;
  region.particleCellMax = kNoCellMax;
  accumulateCells(positions, region.particleCellMin, region.particleCellMax);
  region.addedCellMin = addedCellMin_ = kNoCellMin;
  region.addedCellMax = addedCellMax_ = kNoCellMax;
  activeRegion_.upload(0, sizeof region, &region);
}

// Particles added between steps: their cells go to the region's `added…` bounds, which the next prepare_grid
// merges with what G2P accumulated (an upload, no readback).
void Simulation::noteAddedParticles(const std::vector<glm::vec3>& positions) {
  accumulateCells(positions, addedCellMin_, addedCellMax_);
  const glm::ivec4 added[2] = {addedCellMin_, addedCellMax_};
  // The last prepare_grid reset these bounds on the GPU: its write must land before this one.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  activeRegion_.upload(gpu::kAddedCellsOffset, sizeof added, added);
}

void Simulation::writeStepUniforms(double dtS) {
  gpu::StepUniforms uniforms{};
  const double h = scene_.grid.cellSizeM;
  uniforms.gridOriginCellSize = glm::vec4(glm::vec3(scene_.grid.originM), float(h));
  uniforms.gridNodes = glm::ivec4(gridNodes_, 0);
  uniforms.gravityDt = glm::vec4(glm::vec3(scene_.gravityMPerS2), float(dtS));
  // Adaptive steps shrink with speed, so the momentum unit m_ref·h/Δt follows the step taken: a node's velocity
  // in cells per step, which the CFL factor keeps below 1, is what the fixed-point bound assumes.
  const double momentumUnit =
      scene_.time.adaptive ? fixedPoint_.referenceMassKg * h / dtS : fixedPoint_.momentumUnitKgMPerS;
  uniforms.fixedPoint = glm::vec4(float(fixedPoint_.referenceMassKg), float(momentumUnit),
                                  float(fixedPoint_.unitsPerValue()), float(fixedPoint_.resolution()));
  // APIC's D_p⁻¹ (Jiang et al. 2015): 4/h² for quadratic, 3/h² for cubic B-splines.
  const double inverseInertia = (scene_.solver.kernel == Kernel::Cubic ? 3.0 : 4.0) / (h * h);
  uniforms.transfer = glm::vec4(float(scene_.solver.flipRatio), float(timeS_), float(inverseInertia), 0);
  uniforms.counts = glm::uvec4(particleCount_, scene_.colliders.size(), static_cast<std::uint32_t>(steps_), 0);
  stepUniforms_.upload(0, sizeof uniforms, &uniforms);
}

void Simulation::bindAll() const {
  stepUniforms_.bindUniform(gpu::StepUniformsBlock);
  positionMass_.bindStorage(gpu::PositionMass);
  velocityVolume_.bindStorage(gpu::VelocityVolume);
  if (elasticDeformation_) elasticDeformation_.bindStorage(gpu::ElasticDeformation);
  kirchhoffStress_.bindStorage(gpu::KirchhoffStress);
  if (affine_) affine_.bindStorage(gpu::Affine);
  plasticState_.bindStorage(gpu::PlasticState);
  gridMomentumMass_.bindStorage(gpu::GridMomentumMass);
  if (gridImpulse_) gridImpulse_.bindStorage(gpu::GridImpulse);
  materials_.bindStorage(gpu::Materials);
  colliders_.bindStorage(gpu::Colliders);
  activeRegion_.bindStorage(gpu::ActiveRegion);
  watchdog_.bindStorage(gpu::Watchdog);
  if (blocks_) {
    blocks_.bindStorage(gpu::Blocks);
    particleSlots_.bindStorage(gpu::ParticleSlots);
    blockParticles_.bindStorage(gpu::BlockParticles);
    blockOrder_.bindStorage(gpu::BlockOrder);
  }
}

void Simulation::bindParticleBuffers() const {
  positionMass_.bindStorage(gpu::PositionMass);
  velocityVolume_.bindStorage(gpu::VelocityVolume);
  kirchhoffStress_.bindStorage(gpu::KirchhoffStress);
  plasticState_.bindStorage(gpu::PlasticState);
}

void Simulation::setPassTiming(bool enabled) {
  timingPasses_ = enabled;
  passTimes_.clear();
}

void Simulation::beginPass() {
  if (!timingPasses_) return;
  glFinish();
  passTimer_.begin();
  passWallStart_ = std::chrono::steady_clock::now();
}

void Simulation::endPass(const gl::Program& program) {
  gl::checkPass(program.name().c_str());
  if (!timingPasses_) return;
  passTimer_.end();
  glFinish();
  const double wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - passWallStart_).count();
  auto entry = std::find_if(passTimes_.begin(), passTimes_.end(),
                            [&](const PassTime& time) { return time.pass == program.name(); });
  if (entry == passTimes_.end()) entry = passTimes_.insert(passTimes_.end(), PassTime{program.name()});
  entry->totalMs += double(passTimer_.elapsedNanoseconds()) * 1e-6;
  entry->totalWallMs += wallMs;
  ++entry->dispatches;
}

void Simulation::runOnce(const gl::Program& program) {
  program.use();
  beginPass();
  glDispatchCompute(1, 1, 1);
  endPass(program);
}

void Simulation::runOverGrid(const gl::Program& program) {
  program.use();
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, activeRegion_.id());
  beginPass();
  glDispatchComputeIndirect(static_cast<GLintptr>(gpu::kGridDispatchOffset));
  endPass(program);
}

void Simulation::runOverParticles(const gl::Program& program) {
  program.use();
  beginPass();
  const GLuint groups = static_cast<GLuint>((particleCount_ + kParticleGroupSize - 1) / kParticleGroupSize);
  const GLuint maxX = static_cast<GLuint>(maxWorkGroupsX_);
  // More groups than one dimension allows are laid out in rows; the shader folds y back into the index.
  if (groups <= maxX) {
    glDispatchCompute(groups, 1, 1);
  } else {
    glDispatchCompute(maxX, (groups + maxX - 1) / maxX, 1);
  }
  endPass(program);
}

// Steps 1–2 of Stomakhin 2013 §6: the grid box for this step, cleared, then particle to grid.
void Simulation::scatterToGrid() {
  bindAll();
  runOnce(prepareGrid_);
  addedCellMin_ = kNoCellMin;  // consumed (and reset on the GPU) by prepare_grid
  addedCellMax_ = kNoCellMax;
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  runOverGrid(clearGrid_);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  if (binsParticles()) {
    scatterInBlocks();
  } else {
    runOverParticles(particleToGrid_);
  }
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

// P2G without atomics (shaders/common/blocks.glsl): bin the particles by block, then scatter the blocks one
// colour at a time, each colour's blocks far enough apart that none shares a node with another.
void Simulation::scatterInBlocks() {
  runOverParticles(binCount_);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  runOnce(binScan_);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  runOverParticles(binPlace_);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  particleToGridBlocks_.use();
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, blocks_.id());
  for (int color = 0; color < gpu::kBlockColors; ++color) {
    particleToGridBlocks_.set("blockColor", color);
    beginPass();
    glDispatchComputeIndirect(static_cast<GLintptr>(color * gpu::kBlockColorStride));
    endPass(particleToGridBlocks_);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
}

void Simulation::releaseDueParticles() {
  std::vector<ParticleSeed> due;
  // The tolerance lets a particle due at a frame time join at that frame's first step despite rounding.
  const double nowS = timeS_ + 1e-9 * scene_.time.dtS;
  while (nextPending_ < pendingParticles_.size() && pendingParticles_[nextPending_].releaseTimeS <= nowS) {
    due.push_back(pendingParticles_[nextPending_++]);
  }
  addParticles(due);
}

void Simulation::step(double dtS) {
  releaseDueParticles();
  writeStepUniforms(dtS);
  scatterToGrid();  // prepare_grid → clear_grid → p2g
  runOverGrid(updateGrid_);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  runOverParticles(gridToParticle_);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  timeS_ += dtS;
  ++steps_;
}

// Adaptive stepping (time.adaptive): each step is the largest that the CFL condition on the fastest signal,
// max over particles of |v| + c (the particle's speed plus its material's wave speed in its present, hardened
// state), allows, times time.cfl, and no larger than time.dt. That maximum comes from the GPU (an atomicMax in
// G2P), one 4-byte read per step; gravity may add |g| dt during the step. Before the first step it is the seeds'
// fastest speed plus the stiffest material's wave speed at rest.
double Simulation::adaptiveDtS() const {
  const double h = scene_.grid.cellSizeM;
  const double cfl = scene_.time.cfl * adaptiveStepScale_;
  const double speedMPerS = fastestSpeedMPerS_ + glm::length(scene_.gravityMPerS2) * scene_.time.dtS;
  double dtS = scene_.time.dtS * adaptiveStepScale_;
  if (speedMPerS > 0) dtS = std::min(dtS, cfl * h / speedMPerS);
  return dtS;
}

void Simulation::saveState() {
  if (saved_.buffers.empty()) {
    for (gl::Buffer* buffer : stateBuffers(*this)) saved_.buffers.emplace_back(buffer, gl::Buffer(buffer->bytes()));
  }
  for (auto& [live, copy] : saved_.buffers) copy.copyFrom(*live, live->bytes());
  saved_.timeS = timeS_;
  saved_.steps = steps_;
  saved_.particleCount = particleCount_;
  saved_.nextPending = nextPending_;
  saved_.fastestSpeedMPerS = fastestSpeedMPerS_;
}

Checkpoint Simulation::checkpoint(int frame) const {
  Checkpoint checkpoint;
  checkpoint.sceneFingerprint = sceneFingerprint_;
  checkpoint.frame = frame;
  checkpoint.timeS = timeS_;
  checkpoint.steps = steps_;
  checkpoint.particleCount = particleCount_;
  checkpoint.releasedEmitterParticles = nextPending_;
  checkpoint.fastestSpeedMPerS = fastestSpeedMPerS_;
  for (const gl::Buffer* buffer : stateBuffers(*this)) {
    std::string bytes(buffer->bytes(), '\0');
    buffer->download(0, bytes.size(), bytes.data());
    checkpoint.buffers.push_back(std::move(bytes));
  }
  return checkpoint;
}

void Simulation::resume(const Checkpoint& checkpoint, const std::filesystem::path& source) {
  const std::vector<gl::Buffer*> buffers = stateBuffers(*this);
  if (checkpoint.sceneFingerprint != sceneFingerprint_ || checkpoint.buffers.size() != buffers.size()) {
    throw InputError(source.string() + ": the checkpoint was written for another scene (or another version of this "
                     "one); resume it with the scene it came from");
  }
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    if (checkpoint.buffers[i].size() != buffers[i]->bytes()) {
      throw InputError(source.string() + ": the checkpoint's buffer " + std::to_string(i) + " has " +
                       std::to_string(checkpoint.buffers[i].size()) + " bytes, the scene needs " +
                       std::to_string(buffers[i]->bytes()));
    }
  }
  if (checkpoint.particleCount > particleCapacity_ || checkpoint.releasedEmitterParticles > pendingParticles_.size()) {
    throw InputError(source.string() + ": the checkpoint holds more particles than the scene makes");
  }
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    buffers[i]->upload(0, checkpoint.buffers[i].size(), checkpoint.buffers[i].data());
  }
  timeS_ = checkpoint.timeS;
  steps_ = checkpoint.steps;
  fastestSpeedMPerS_ = checkpoint.fastestSpeedMPerS;
  // The particles present: the first ones, then the emitters' in the order they were released.
  for (; nextPending_ < checkpoint.releasedEmitterParticles; ++nextPending_) {
    particleBody_.push_back(pendingParticles_[nextPending_].bodyIndex);
    particleMaterial_.push_back(pendingParticles_[nextPending_].materialIndex);
  }
  particleCount_ = checkpoint.particleCount;
  addedCellMin_ = kNoCellMin;  // written between steps, when nothing was pending
  addedCellMax_ = kNoCellMax;
}

void Simulation::restoreState() {
  if (saved_.buffers.empty()) throw std::logic_error("restoreState: no state was saved");
  for (auto& [live, copy] : saved_.buffers) live->copyFrom(copy, live->bytes());
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  timeS_ = saved_.timeS;
  steps_ = saved_.steps;
  particleCount_ = saved_.particleCount;
  particleBody_.resize(particleCount_);
  particleMaterial_.resize(particleCount_);
  nextPending_ = saved_.nextPending;
  fastestSpeedMPerS_ = saved_.fastestSpeedMPerS;
  addedCellMin_ = kNoCellMin;  // saved between steps, when nothing was pending
  addedCellMax_ = kNoCellMax;
}

void Simulation::readFastestSpeed() {
  constexpr std::size_t offset = offsetof(gpu::WatchdogStatus, maxSpeedBits);
  std::uint32_t bits = 0;
  watchdog_.download(offset, sizeof bits, &bits);  // prepare_grid resets it for the next step
  fastestSpeedMPerS_ = glm::uintBitsToFloat(bits);
}

int Simulation::advanceTo(double timeS) {
  if (scene_.time.adaptive) {
    int steps = 0;
    while (timeS - timeS_ > 1e-12 * timeS) {
      const double remainingS = timeS - timeS_;
      double dtS = adaptiveDtS();
      // Land on the frame exactly, without a sliver of a last step: the last two steps share what is left.
      if (remainingS <= dtS) {
        dtS = remainingS;
      } else if (remainingS < 2 * dtS) {
        dtS = remainingS / 2;
      }
      step(dtS);
      readFastestSpeed();
      ++steps;
    }
    timeS_ = timeS;
    return steps;
  }
  const double remainingS = timeS - timeS_;
  if (remainingS <= 0) return 0;
  // Equal steps, none larger than dt; the tolerance keeps an exact multiple from taking one step more.
  const int steps = std::max(1, static_cast<int>(std::ceil(remainingS / scene_.time.dtS - 1e-9)));
  const double dtS = remainingS / steps;
  for (int i = 0; i < steps; ++i) step(dtS);
  timeS_ = timeS;
  return steps;
}

std::string Simulation::describeNode(std::int32_t node) const {
  const glm::ivec3 index(node % gridNodes_.x, (node / gridNodes_.x) % gridNodes_.y, node / (gridNodes_.x * gridNodes_.y));
  const glm::dvec3 position = scene_.grid.originM + glm::dvec3(index) * scene_.grid.cellSizeM;
  return "grid node (" + std::to_string(index.x) + ", " + std::to_string(index.y) + ", " + std::to_string(index.z) +
         ") at (" + formatNumber(position.x) + ", " + formatNumber(position.y) + ", " + formatNumber(position.z) + ") m";
}

std::string Simulation::describeParticle(std::int32_t particle) const {
  const glm::vec4 position = positionMass_.read<glm::vec4>(1, static_cast<std::size_t>(particle))[0];
  const int body = particleBody_[static_cast<std::size_t>(particle)];
  const int material = particleMaterial_[static_cast<std::size_t>(particle)];
  const std::string origin = body < 0 ? "added while running" : "of bodies[" + std::to_string(body) + "]";
  return "particle " + std::to_string(particle) + " " + origin + " (material \"" +
         scene_.materials[static_cast<std::size_t>(material)].name + "\") near (" + formatNumber(position.x) + ", " +
         formatNumber(position.y) + ", " + formatNumber(position.z) + ") m";
}

void Simulation::checkWatchdog() const {
  const gpu::WatchdogStatus status = watchdog_.read<gpu::WatchdogStatus>(1)[0];
  if (status.overflowCount == 0 && status.nonFiniteCount == 0 && status.cflCount == 0) return;

  const double h = scene_.grid.cellSizeM;
  const double dt = scene_.time.dtS;
  const double stableDt = h / stiffestBody(scene_).waveSpeedMPerS;
  const std::string stiffness = "the elastic wave bound is dt < h / c = " + formatNumber(stableDt) +
                                " s for the stiffest material (scene dt " + formatNumber(dt) + " s)";
  auto when = [&](std::uint32_t step) {
    return "step " + std::to_string(step) + " (t ≈ " + formatNumber(double(step) * dt) + " s)";
  };

  // Listed in the order they happened: the first is the cause, the others often its consequences.
  std::vector<std::pair<std::uint32_t, std::string>> events;
  if (status.overflowCount > 0 && status.overflowChannel == gpu::kBinOverflowChannel) {
    const int blockCells = gpu::kBlockCells * gpu::kBlockCells * gpu::kBlockCells;
    events.emplace_back(status.overflowStep,
                        when(status.overflowStep) + ": a block of " + std::to_string(blockCells) +
                            " cells held more than " + std::to_string(gpu::kMaxBinParticles) +
                            " particles, more than P2G without atomics can scatter in one invocation on llvmpipe "
                            "(which ends a shader's loops after 65,535 iterations). Set solver.atomics to \"fixed\", "
                            "or lower particles_per_cell.");
  } else if (status.overflowCount > 0) {
    events.emplace_back(status.overflowStep,
                        when(status.overflowStep) + ": fixed-point overflow of the P2G " +
                            channelName(status.overflowChannel) + " sum at " + describeNode(status.overflowNode) + " (" +
                            std::to_string(status.overflowCount) + " overflowing additions). A node sum may reach ±" +
                            formatNumber(fixedPoint_.maxNodeValue()) +
                            " reference masses (or that many times a node moving one cell per step); the particles "
                            "moved or compressed far beyond that. Reduce time.dt, lower the body velocities or "
                            "particles_per_cell, or set solver.atomics to \"float\"; " + stiffness + ".");
  }
  if (status.nonFiniteCount > 0) {
    events.emplace_back(status.nonFiniteStep,
                        when(status.nonFiniteStep) + ": " + describeParticle(status.nonFiniteParticle) +
                            " became non-finite (NaN or Inf; " + std::to_string(status.nonFiniteCount) +
                            " particle updates rejected). Reduce time.dt or youngs_modulus; " + stiffness + ".");
  }
  if (status.cflCount > 0) {
    events.emplace_back(status.cflStep,
                        when(status.cflStep) + ": " + describeParticle(status.cflParticle) + " moved " +
                            formatNumber(status.cflCellsPerStep) + " cells in one step (CFL limit 1; " +
                            std::to_string(status.cflCount) + " violations). Reduce time.dt below h / |v| or lower "
                            "the body velocities; " + stiffness + ".");
  }
  std::stable_sort(events.begin(), events.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::string message = "the simulation became unstable:";
  for (const auto& event : events) message += "\n  - " + event.second;
  throw SimulationError(message);
}

ParticleSnapshot Simulation::snapshot() const {
  ParticleSnapshot snapshot;
  snapshot.positionMass = positionMass_.read<glm::vec4>(particleCount_);
  snapshot.velocityVolume = velocityVolume_.read<glm::vec4>(particleCount_);
  const auto plastic = plasticState_.read<gpu::ParticlePlasticState>(particleCount_);
  snapshot.plasticJ.reserve(plastic.size());
  for (const auto& state : plastic) snapshot.plasticJ.push_back(state.plasticJ);
  return snapshot;
}

gpu::ActiveRegionData Simulation::activeRegion() const { return activeRegion_.read<gpu::ActiveRegionData>(1)[0]; }

GridTotals Simulation::transferToGrid() {
  // Added in node order: the same node sums (fixed point's do not depend on the particles' order) give the same
  // totals to the last bit.
  GridTotals totals;
  for (const GridNodeSums& node : readGridAfterTransfer()) {
    totals.massKg += node.massKg;
    totals.momentumKgMPerS += node.momentumKgMPerS;
    ++totals.activeNodes;
  }
  return totals;
}

void Simulation::setParticleVelocity(std::size_t particle, const glm::vec3& velocityMPerS) {
  velocityVolume_.upload(particle * sizeof(glm::vec4), sizeof(glm::vec3), &velocityMPerS);
}

std::vector<GridNodeSums> Simulation::readGridAfterTransfer() {
  const ParticleSnapshot state = snapshot();
  std::vector<glm::vec3> positions;
  positions.reserve(state.size());
  for (const glm::vec4& p : state.positionMass) positions.emplace_back(p);

  seedActiveRegion(positions);
  writeStepUniforms(scene_.time.dtS);
  scatterToGrid();
  const gpu::ActiveRegionData region = activeRegion();
  std::vector<GridNodeSums> nodes;
  if (region.boxSize.w > 0) {
    auto linear = [&](const glm::ivec3& node) {
      return static_cast<std::size_t>(node.x + gridNodes_.x * (node.y + gridNodes_.y * node.z));
    };
    const glm::ivec3 boxFirst(region.boxMin);
    const glm::ivec3 boxLast = boxFirst + glm::ivec3(region.boxSize) - 1;
    const std::size_t spanFirst = linear(boxFirst);
    const std::vector<glm::ivec4> stored = gridMomentumMass_.read<glm::ivec4>(linear(boxLast) - spanFirst + 1, spanFirst);
    nodes.reserve(static_cast<std::size_t>(region.boxSize.w));
    for (int z = boxFirst.z; z <= boxLast.z; ++z)
      for (int y = boxFirst.y; y <= boxLast.y; ++y)
        for (int x = boxFirst.x; x <= boxLast.x; ++x) {
          const glm::ivec4& value = stored[linear(glm::ivec3(x, y, z)) - spanFirst];
          // Nondimensional sums (grid.glsl): integers times 2^−k, or the floats themselves.
          const glm::dvec4 sums = scene_.solver.atomics == Atomics::FixedPoint
                                      ? glm::dvec4(value) * fixedPoint_.resolution()
                                      : glm::dvec4(glm::intBitsToFloat(value));
          nodes.push_back({glm::ivec3(x, y, z), sums.w * fixedPoint_.referenceMassKg,
                           glm::dvec3(sums) * fixedPoint_.momentumUnitKgMPerS});
        }
  }
  seedActiveRegion(positions);  // prepare_grid consumed the bounds the next step needs
  return nodes;
}

}  // namespace firn
