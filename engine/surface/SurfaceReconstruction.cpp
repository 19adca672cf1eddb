#include "surface/SurfaceReconstruction.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "Error.h"
#include "gl/ShaderLibrary.h"
#include "gpu/Materials.h"
#include "io/Text.h"
#include "surface/MarchingCubes.h"
#include "surface/SurfaceLayout.h"

namespace firn::surface {

namespace {

// The storage binding points a reconstruction pass uses at once: the particles' (0–5) and its own (20–31).
// Per node: the volume fraction (int), the colour and velocity sums (SurfaceNodeSums), the cell (uint) and the
// counts (uvec2).
constexpr std::size_t kDensityBytesPerNode = sizeof(std::int32_t);
constexpr std::size_t kNodeSumBytesPerNode = sizeof(gpu::SurfaceNodeSums);
constexpr std::size_t kCellBytesPerNode = sizeof(std::uint32_t);
constexpr std::size_t kCountBytesPerNode = 2 * sizeof(std::uint32_t);
constexpr std::size_t kIndexBytesPerTriangle = 3 * sizeof(std::uint32_t);
// Buffers grow by half again what a frame needs, so that a mesh growing slowly is not reallocated every frame.
constexpr double kGrowth = 1.5;

std::string sceneFile(const Scene& scene) {
  return scene.sourcePath.empty() ? std::string(kBuiltInSceneName) : scene.sourcePath.string();
}

std::string mebibytes(double bytes) { return formatApproximately(std::round(bytes / (1 << 20) * 10) / 10) + " MiB"; }

// Zeroes the first `bytes` of a buffer (glClearBufferSubData, GL 4.3), not its whole capacity.
void zeroPrefix(const gl::Buffer& buffer, std::size_t bytes) {
  if (bytes == 0) return;
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer.id());
  glClearBufferSubData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, 0, static_cast<GLsizeiptr>(bytes), GL_RED_INTEGER,
                       GL_UNSIGNED_INT, nullptr);
}

// A buffer of at least `bytes`, reallocated (without its contents) when it is smaller; `label` names it in debuggers.
void ensureCapacity(gl::Buffer& buffer, std::size_t bytes, const char* label) {
  if (buffer.bytes() < bytes || !buffer) {
    buffer = gl::Buffer(std::max<std::size_t>(std::size_t(double(bytes) * kGrowth), 16)).labelled(label);
  }
}

}  // namespace

KernelRange checkKernelRange(const Scene& scene, const std::vector<ParticleSeed>& seeds) {
  KernelRange range;
  range.cellM = scene.grid.cellSizeM / scene.surface.resolution;
  range.smallestM = std::numeric_limits<double>::infinity();
  for (const ParticleSeed& seed : seeds) {
    const double volumeM3 = double(seed.massKg) / scene.materials.at(std::size_t(seed.materialIndex)).densityKgPerM3;
    const double radiusM = scene.surface.smoothing * std::cbrt(volumeM3);
    range.smallestM = std::min(range.smallestM, radiusM);
    range.largestM = std::max(range.largestM, radiusM);
  }
  if (seeds.empty()) range.smallestM = range.largestM = range.cellM;
  const std::string file = sceneFile(scene);
  const auto number = [](double value) { return formatApproximately(value); };
  // A kernel narrower than a cell leaves particles between the nodes: the surface breaks into beads.
  if (range.smallestM < range.cellM) {
    throw InputError(file + ": surface.resolution: the smallest particles' kernel (radius " + number(range.smallestM) +
                     " m, surface.smoothing " + number(scene.surface.smoothing) +
                     " times their spacing) is narrower than a reconstruction cell (grid.cell_size / "
                     "surface.resolution = " + number(range.cellM) + " m); raise surface.resolution to at least " +
                     number(std::ceil(scene.grid.cellSizeM / range.smallestM * 100) / 100) + ", or surface.smoothing");
  }
  if (range.largestM > gpu::MAX_KERNEL_RADIUS_CELLS * range.cellM) {
    throw InputError(file + ": surface.resolution: the largest particles' kernel (radius " + number(range.largestM) +
                     " m, surface.smoothing " + number(scene.surface.smoothing) + " times their spacing) spans " +
                     number(range.largestM / range.cellM) + " reconstruction cells (grid.cell_size / surface.resolution = " +
                     number(range.cellM) + " m); at most " + number(gpu::MAX_KERNEL_RADIUS_CELLS) +
                     ": lower surface.resolution to at most " +
                     number(std::floor(gpu::MAX_KERNEL_RADIUS_CELLS * scene.grid.cellSizeM / range.largestM * 100) / 100) +
                     ", or surface.smoothing");
  }
  return range;
}

struct SurfaceReconstruction::Passes {
  Passes(const gl::ShaderLibrary& library, const gl::ShaderOptions& options, int maxWorkGroupsX)
      : measureBounds(library, "surface/measure_bounds.comp", options),
        splatDensity(library, "surface/splat_density.comp", options),
        classifyCells(library, "surface/classify_cells.comp", options),
        emitMesh(library, "surface/emit_mesh.comp", options),
        scan(library, options, maxWorkGroupsX) {}

  gl::ComputePass measureBounds;
  gl::ComputePass splatDensity;
  gl::ComputePass classifyCells;
  gl::ComputePass emitMesh;
  PrefixScan scan;
};

SurfaceReconstruction::SurfaceReconstruction(const Scene& scene, const std::vector<ParticleSeed>& seeds,
                                             const gl::ContextInfo& gl)
    : spec_(scene.surface), latticeOriginM_(scene.grid.originM),
      nodeSpacingM_(checkKernelRange(scene, seeds).cellM), sceneFile_(sceneFile(scene)),
      maxBufferBytes_(gl.maxStorageBlockBytes), maxWorkGroupsX_(gl.maxComputeWorkGroupCountX) {
  const gl::ShaderLibrary library(gl::embeddedShaderFiles());
  passes_ = std::make_unique<Passes>(library, gl::ShaderOptions{}, maxWorkGroupsX_);
  cases_ = gl::Buffer::fromVector(packedMarchingCubesCases()).labelled("surface: marching-cubes cases");
  std::vector<glm::vec4> inverseDensities;
  for (const std::size_t material : buildMaterialTable(scene).entryMaterial) {
    inverseDensities.emplace_back(float(1.0 / scene.materials[material].densityKgPerM3), 0.0f, 0.0f, 0.0f);
  }
  if (inverseDensities.empty()) inverseDensities.emplace_back(0.0f);
  materials_ = gl::Buffer::fromVector(inverseDensities).labelled("surface: inverse densities");
  uniforms_ = gl::Buffer(sizeof(gpu::SurfaceUniforms)).labelled("surface uniforms");
  header_ = gl::Buffer(sizeof(gpu::SurfaceHeader)).labelled("surface: header");
  // Published even when a frame sums neither colours nor velocities, so that no pass declares a buffer with nothing
  // bound.
  nodeSums_ = gl::Buffer(kNodeSumBytesPerNode).labelled("surface: node sums");
}

SurfaceReconstruction::~SurfaceReconstruction() = default;

glm::dvec3 SurfaceReconstruction::boundsMinM() const {
  return latticeOriginM_ + glm::dvec3(firstNode_) * nodeSpacingM_;
}

glm::dvec3 SurfaceReconstruction::boundsMaxM() const {
  return latticeOriginM_ + glm::dvec3(firstNode_ + glm::max(stats_.gridNodes - 1, glm::ivec3(0))) * nodeSpacingM_;
}

std::size_t SurfaceReconstruction::nodeCount() const {
  return std::size_t(stats_.gridNodes.x) * std::size_t(stats_.gridNodes.y) * std::size_t(stats_.gridNodes.z);
}

void SurfaceReconstruction::resizeGrid(const glm::ivec3& nodes, bool withNodeSums) {
  const std::size_t count = std::size_t(nodes.x) * std::size_t(nodes.y) * std::size_t(nodes.z);
  const std::size_t largestBytes = count * (withNodeSums ? kNodeSumBytesPerNode : kCountBytesPerNode);
  if (count > std::size_t(std::numeric_limits<std::int32_t>::max()) || double(largestBytes) > double(maxBufferBytes_)) {
    throw InputError(sceneFile_ + ": surface.resolution: at t = " + formatApproximately(timeS_) +
                     " s the particles' kernels span " + std::to_string(nodes.x) + " × " + std::to_string(nodes.y) +
                     " × " + std::to_string(nodes.z) + " reconstruction nodes " + formatApproximately(nodeSpacingM_) +
                     " m apart, whose " + (withNodeSums ? "colour and velocity sums" : "counts") + " need " +
                     mebibytes(double(largestBytes)) + ", more than the driver's largest storage buffer (" +
                     mebibytes(double(maxBufferBytes_)) + "); lower surface.resolution");
  }
  ensureCapacity(density_, count * kDensityBytesPerNode, "surface: density");
  if (withNodeSums) ensureCapacity(nodeSums_, count * kNodeSumBytesPerNode, "surface: node sums");
  ensureCapacity(cells_, count * kCellBytesPerNode, "surface: cells");
  ensureCapacity(counts_, (count + 1) * kCountBytesPerNode, "surface: counts");  // + 1: the scan's total
  stats_.gridNodes = nodes;
  stats_.gridBytes = count * (kDensityBytesPerNode + kCellBytesPerNode + kCountBytesPerNode +
                              (withNodeSums ? kNodeSumBytesPerNode : 0));
}

gl::BufferBindings SurfaceReconstruction::bindings(const ParticleView& particles,
                                                   const gl::Buffer* particleColors) const {
  gl::BufferBindings buffers;
  particles.publish(buffers);
  buffers.uniform(FIRN_BINDING_SURFACE_UNIFORMS, uniforms_);
  buffers.uniform(FIRN_BINDING_SURFACE_CASES, cases_);
  buffers.storage(FIRN_BINDING_SURFACE_HEADER, header_);
  buffers.storage(FIRN_BINDING_SURFACE_MATERIALS, materials_);
  buffers.storage(FIRN_BINDING_SURFACE_DENSITY, density_);
  buffers.storage(FIRN_BINDING_SURFACE_SUMS, nodeSums_);
  buffers.storage(FIRN_BINDING_SURFACE_CELLS, cells_);
  buffers.storage(FIRN_BINDING_SURFACE_COUNTS, counts_);
  buffers.storage(FIRN_BINDING_SURFACE_VERTICES, vertices_);
  buffers.storage(FIRN_BINDING_SURFACE_INDICES, indices_);
  buffers.storage(FIRN_BINDING_SURFACE_PARTICLE_COLORS, particleColors != nullptr ? *particleColors : nodeSums_);
  return buffers;
}

void SurfaceReconstruction::reconstruct(const ParticleView& particleView, const gl::Buffer* particleColors,
                                        Velocities velocities) {
  timeS_ = particleView.timeS;
  const std::size_t particles = particleView.count;
  const bool withColors = particleColors != nullptr;
  const bool withVelocities = velocities == Velocities::Sum;
  const bool withNodeSums = withColors || withVelocities;
  stats_ = SurfaceStats{};
  stats_.withColors = withColors;
  stats_.withVelocities = withVelocities;
  gpu::SurfaceUniforms uniforms{};
  uniforms.latticeOriginM = glm::vec3(latticeOriginM_);
  uniforms.nodeSpacingM = float(nodeSpacingM_);
  uniforms.smoothing = float(spec_.smoothing);
  uniforms.isoLevel = float(spec_.iso);
  uniforms.isoUnits = int(std::floor(spec_.iso * gpu::SURFACE_UNITS_PER_VALUE + 0.5));
  uniforms.reconstructedParticles = std::uint32_t(particles);
  uniforms.sumsCarried =
      (withColors ? gpu::SURFACE_SUMS_COLOR : 0u) | (withVelocities ? gpu::SURFACE_SUMS_VELOCITY : 0u);
  uniforms_.upload(0, sizeof uniforms, &uniforms);
  if (particles == 0) return;

  // 1. The box of nodes the kernels reach.
  gpu::SurfaceHeader header{};
  header.kernelNodesMin = glm::ivec4(std::numeric_limits<std::int32_t>::max());
  header.kernelNodesMax = glm::ivec4(std::numeric_limits<std::int32_t>::min());
  header_.upload(0, sizeof header, &header);
  passes_->measureBounds.runOver(particles, maxWorkGroupsX_, bindings(particleView, particleColors), timer_);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  header_.download(0, sizeof header, &header);
  const glm::ivec3 lowest(header.kernelNodesMin), highest(header.kernelNodesMax);
  if (glm::any(glm::greaterThan(lowest, highest))) return;  // no particle has a kernel

  // The grid: one node to spare on every side, so that its outer nodes are outside and the surface closes.
  firstNode_ = lowest - 1;
  const glm::ivec3 nodes = highest - lowest + 3;
  resizeGrid(nodes, withNodeSums);
  const std::size_t nodeCount = std::size_t(nodes.x) * std::size_t(nodes.y) * std::size_t(nodes.z);
  uniforms.firstNode = firstNode_;
  uniforms.nodeCount = std::uint32_t(nodeCount);
  uniforms.boxNodes = nodes;
  uniforms_.upload(0, sizeof uniforms, &uniforms);
  zeroPrefix(density_, nodeCount * kDensityBytesPerNode);
  if (withNodeSums) zeroPrefix(nodeSums_, nodeCount * kNodeSumBytesPerNode);
  zeroPrefix(counts_, (nodeCount + 1) * kCountBytesPerNode);
  const gl::BufferBindings fieldBuffers = bindings(particleView, particleColors);

  // 2. The field; 3. the cells; 4. where each node writes.
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  passes_->splatDensity.runOver(particles, maxWorkGroupsX_, fieldBuffers, timer_);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  passes_->classifyCells.runOver(nodeCount, maxWorkGroupsX_, fieldBuffers, timer_);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  passes_->scan.run(counts_, nodeCount + 1, fieldBuffers, timer_);
  glm::uvec2 totals(0u);
  counts_.download(nodeCount * kCountBytesPerNode, sizeof totals, &totals);
  stats_.vertices = totals.x;
  stats_.triangles = totals.y;
  const std::size_t vertexBytes = stats_.vertices * sizeof(gpu::SurfaceVertex);
  const std::size_t indexBytes = stats_.triangles * kIndexBytesPerTriangle;
  if (double(std::max(vertexBytes, indexBytes)) > double(maxBufferBytes_)) {
    throw InputError(sceneFile_ + ": surface.resolution: at t = " + formatApproximately(timeS_) + " s the mesh has " +
                     std::to_string(stats_.triangles) + " triangles, more than the driver's largest storage buffer (" +
                     mebibytes(double(maxBufferBytes_)) + ") holds; lower surface.resolution");
  }
  ensureCapacity(vertices_, vertexBytes, "surface: vertices");
  ensureCapacity(indices_, indexBytes, "surface: indices");

  // 5. The mesh.
  passes_->emitMesh.runOver(nodeCount, maxWorkGroupsX_, bindings(particleView, particleColors), timer_);
  // Drawn as vertex storage and an element array, or read back.
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_ELEMENT_ARRAY_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

SurfaceMesh SurfaceReconstruction::readMesh() const {
  SurfaceMesh mesh;
  if (stats_.triangles == 0) return mesh;
  const std::vector<gpu::SurfaceVertex> vertices = vertices_.read<gpu::SurfaceVertex>(stats_.vertices);
  mesh.positionsM.reserve(vertices.size());
  mesh.normals.reserve(vertices.size());
  for (const gpu::SurfaceVertex& vertex : vertices) {
    mesh.positionsM.emplace_back(vertex.positionM);
    mesh.normals.emplace_back(vertex.normal);
    if (stats_.withVelocities) mesh.velocitiesMPerS.emplace_back(vertex.velocity);
  }
  mesh.indices = indices_.read<std::uint32_t>(3 * stats_.triangles);
  return mesh;
}

LatticeSamples SurfaceReconstruction::readDensity() const {
  LatticeSamples samples;
  samples.originM = latticeOriginM_;
  samples.spacingM = nodeSpacingM_;
  samples.firstNode = firstNode_;
  samples.nodeCounts = stats_.gridNodes;
  const std::size_t count = nodeCount();
  const std::vector<std::int32_t> units = density_.read<std::int32_t>(count);
  samples.values.reserve(count);
  for (const std::int32_t value : units) samples.values.push_back(float(value) / gpu::SURFACE_UNITS_PER_VALUE);
  return samples;
}

std::vector<glm::vec3> SurfaceReconstruction::readVelocities() const {
  if (!stats_.withVelocities) return {};
  const std::size_t count = nodeCount();
  const std::vector<std::int32_t> densities = density_.read<std::int32_t>(count);
  const std::vector<gpu::SurfaceNodeSums> sums = nodeSums_.read<gpu::SurfaceNodeSums>(count);
  std::vector<glm::vec3> velocities(count, glm::vec3(0.0f));
  // Both sums are in the same fixed-point units, so their ratio is the weighted mean velocity (m/s).
  for (std::size_t i = 0; i < count; ++i) {
    if (densities[i] > 0) velocities[i] = glm::vec3(glm::ivec3(sums[i].velocity)) / float(densities[i]);
  }
  return velocities;
}

}  // namespace firn::surface
