#include "run/Budget.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <glm/common.hpp>

#include "Error.h"
#include "gpu/GpuLayout.h"
#include "sim/DomainShare.h"
#include "io/Text.h"
#include "scene/FieldLattice.h"
#include "sim/GpuState.h"
#include "voxelizer/ProcessMemory.h"

namespace firn {
namespace {

std::string bytes(double value) {
  return value >= double(1 << 30) ? format("%.3g GiB", value / double(1 << 30)) : format("%.4g MiB", value / double(1 << 20));
}

std::string describeBody(const Body& body) {
  const std::string perCell = " at " + format("%.3g", body.particlesPerCell) + " particles per cell";
  switch (body.shape) {
    case BodyShape::Sphere: return "a sphere" + perCell;
    case BodyShape::Box: return "a box" + perCell;
    case BodyShape::Mesh: return "the mesh " + body.path + perCell;
    case BodyShape::Points: return "the cloud " + body.path;
  }
  return "a body";
}

// The most particles under each limit, and which is the tightest.
struct Limit {
  double particles;
  std::string what;
};

// The blocks of the grid the bodies reach at the start, from their bounding boxes widened by a stencil (at
// most what the domain holds): an upper bound of what Simulation's pool starts from.
double blocksReached(const Scene& scene) {
  const double blockM = gpu::BLOCK_WIDTH * scene.grid.cellSizeM;
  const double stencilM = 2 * scene.grid.cellSizeM;
  double blocks = 0;
  for (const Body& body : scene.bodies) {
    const glm::dvec3 first = glm::floor((body.boundsMinM() - stencilM - scene.grid.originM) / blockM);
    const glm::dvec3 last = glm::floor((body.boundsMaxM() + stencilM - scene.grid.originM) / blockM);
    const glm::dvec3 perAxis = last - first + 1.0;
    blocks += perAxis.x * perAxis.y * perAxis.z;
  }
  const glm::dvec3 domainBlocks((scene.grid.cells + 1 + gpu::BLOCK_WIDTH - 1) / gpu::BLOCK_WIDTH);
  return std::min(blocks, domainBlocks.x * domainBlocks.y * domainBlocks.z);
}

// The grid's GPU memory at the start: the block map and a pool of four times the blocks reached (at most what
// the driver's buffers hold), as Simulation makes it.
double gridBytes(const Scene& scene, const GpuStateLayout& layout, const gl::ContextInfo& gl) {
  const double poolBlocks = std::min(std::max(4 * blocksReached(scene), 256.0),
                                     double(GpuStateLayout::maxPoolBlocks(gl.maxStorageBlockBytes, layout.semiImplicit)));
  return double(layout.blockMapBytes()) + poolBlocks * double(layout.poolBytesPerBlock());
}

// The mesh colliders' and rigid bodies' distance fields take their memory before any particle: a field that
// leaves no room is refused here, naming the largest field's resolution (the key that sizes it).
void checkFieldsFit(const Scene& scene, const std::vector<FieldLattice>& fields, double fieldsBytes, double roomBytes,
                    const std::string& room) {
  if (fields.empty() || fieldsBytes < roomBytes) return;
  const FieldLattice& largest = *std::max_element(
      fields.begin(), fields.end(), [](const FieldLattice& a, const FieldLattice& b) { return a.bytes() < b.bytes(); });
  throw InputError(sceneFileName(scene) + ": " + largest.object + ".resolution: the distance field of " + largest.path +
                   ", " + format("%.0f", largest.samples.x) + " × " + format("%.0f", largest.samples.y) + " × " +
                   format("%.0f", largest.samples.z) + " samples " + format("%.3g", largest.spacingM) + " m apart (" +
                   bytes(largest.bytes()) + " as 32-bit floats), with the scene's " + std::to_string(fields.size()) +
                   " distance fields in all (" + bytes(fieldsBytes) + "), does not fit " + room +
                   "; lower its resolution, make the mesh smaller or use a coarser cell_size");
}

Limit tightestLimit(const Scene& scene, const gl::ContextInfo& gl, int shares) {
  // F is counted whatever the materials: the estimate is of the larger layout.
  const GpuStateLayout layout = GpuStateLayout::forScene(scene, 0, 0, true);
  layout.checkBlockMapFits(gl);
  const double gpuBytesPerParticle = double(layout.particleBytesPerParticle());
  const double largestBufferBytesPerParticle = double(layout.largestParticleBufferBytesPerParticle());
  const double grid = gridBytes(scene, layout, gl);
  // The distance fields live on the GPU beside the grid, and on the host while they are baked.
  const std::vector<FieldLattice> fields = fieldLattices(scene);
  double fieldsBytes = 0;
  for (const FieldLattice& field : fields) fieldsBytes += field.bytes();
  const std::string fieldsText = fields.empty() ? std::string() : ", " + bytes(fieldsBytes) + " for the distance fields";
  std::vector<Limit> limits;
  limits.push_back({double(std::numeric_limits<std::int32_t>::max()), "the GPU's 32-bit particle indices"});
  // Over several processes each GPU holds about its share of the particles and a quarter more (its buffers' room to
  // take particles in, sim/DomainShare.h); each host samples them all.
  const double perGpu = shares > 1 ? double(shares) / (1.0 + 1.0 / double(kShareSpareFraction)) : 1.0;
  const std::string ofShares =
      shares > 1 ? " on each of " + std::to_string(shares) + " processes, each holding about 1/" + std::to_string(shares) +
                       " of the particles and a quarter more"
                 : std::string();
  limits.push_back({perGpu * double(gl.maxStorageBlockBytes) / largestBufferBytesPerParticle,
                    "the " + bytes(double(gl.maxStorageBlockBytes)) + " " + gl.renderer +
                        " allows per particle buffer (" + format("%.0f", largestBufferBytesPerParticle) +
                        " bytes per particle)" + ofShares});
  if (gl.availableMemoryBytes > 0) {
    const std::string gpuMemory = "the " + bytes(double(gl.availableMemoryBytes)) + " of GPU memory " + gl.renderer + " has free";
    checkFieldsFit(scene, fields, fieldsBytes, double(gl.availableMemoryBytes) - grid,
                   gpuMemory + " after " + bytes(grid) + " for the grid");
    limits.push_back({perGpu * (double(gl.availableMemoryBytes) - grid - fieldsBytes) / gpuBytesPerParticle,
                      gpuMemory + " (" + format("%.0f", gpuBytesPerParticle) + " bytes per particle in all, after " +
                          bytes(grid) + " for the grid" + fieldsText + ")" + ofShares});
  }
  const double hostBytesPerParticle = kHostBytesPerParticle + (gl.buffersInHostMemory ? gpuBytesPerParticle : 0);
  const double allocatable = double(voxelizer::allocatableBytes());
  const double hostGrid = gl.buffersInHostMemory ? grid : 0;
  // Baked on the host; where the driver keeps its buffers in host memory, the GPU's copy is there too.
  const double hostFieldsBytes = (gl.buffersInHostMemory ? 2 : 1) * fieldsBytes;
  const std::string hostMemory = "the " + bytes(allocatable) + " of memory this process can still allocate";
  checkFieldsFit(scene, fields, hostFieldsBytes, allocatable - hostGrid,
                 hostMemory + (gl.buffersInHostMemory ? " after " + bytes(hostGrid) + " for the grid" : std::string()));
  limits.push_back({(allocatable - hostGrid - hostFieldsBytes) / hostBytesPerParticle,
                    hostMemory + " (about " + format("%.0f", hostBytesPerParticle) +
                        " bytes per particle while sampling and uploading" +
                        (fields.empty() ? std::string() : ", after " + bytes(hostFieldsBytes) + " for the distance fields") +
                        (gl.buffersInHostMemory ? ", after " + bytes(hostGrid) + " for the grid, " + gl.renderer +
                                                      "'s buffers included, which it keeps in host memory)"
                                                : std::string(")"))});
  return *std::min_element(limits.begin(), limits.end(),
                           [](const Limit& a, const Limit& b) { return a.particles < b.particles; });
}

// What to change: the largest body's particles per cell (or cloud) scaled to the room the others leave.
std::string suggestion(const Scene& scene, const std::vector<BodyEstimate>& estimates, double room) {
  std::size_t largest = 0;
  double total = 0;
  for (std::size_t b = 0; b < estimates.size(); ++b) {
    total += estimates[b].particles;
    if (estimates[b].particles > estimates[largest].particles) largest = b;
  }
  const double othersRoom = room - (total - estimates[largest].particles);
  const Body& body = scene.bodies[largest];
  const std::string name = "bodies[" + std::to_string(largest) + "]";
  if (!(othersRoom > 0)) return "the other bodies alone take that room: remove bodies or lower their particles_per_cell";
  // The estimates are good to a few per cent (a lattice count differs from V/s³ by the surface's share), so the
  // suggestion keeps that much in hand.
  constexpr double estimateMargin = 0.97;
  const double fraction = estimateMargin * othersRoom / estimates[largest].particles;
  if (body.shape == BodyShape::Points) {
    return "give " + name + " a cloud of at most " + withThousands(othersRoom) + " points";
  }
  // Rounded down to 3 significant digits, so that the suggestion does fit.
  const double perCell = body.particlesPerCell * fraction;
  const double unit = std::pow(10.0, std::floor(std::log10(perCell)) - 2);
  return "particles_per_cell " + format("%.3g", std::floor(perCell / unit) * unit) + " on " + name +
         " would fit, or a smaller body or a coarser cell_size";
}

}  // namespace

ParticleBudget checkParticleBudget(const Scene& scene, const gl::ContextInfo& gl, double reservedParticles,
                                   int shares) {
  ParticleBudget budget;
  budget.bodies = estimateBodies(scene);
  budget.reservedParticles = reservedParticles;
  const Limit limit = tightestLimit(scene, gl, shares);
  const double room = std::max(0.0, std::floor(limit.particles - reservedParticles));
  budget.maxParticles = static_cast<std::size_t>(room);
  budget.limit = limit.what;
  double estimated = 0;
  for (const BodyEstimate& estimate : budget.bodies) estimated += estimate.particles;
  if (estimated <= room) return budget;

  std::string message = sceneFileName(scene) + ": bodies: about " + withThousands(estimated) + " particles (";
  for (std::size_t b = 0; b < budget.bodies.size(); ++b) {
    message += (b > 0 ? "; " : "") + std::string("bodies[") + std::to_string(b) + "], " +
               describeBody(scene.bodies[b]) + ": " + withThousands(budget.bodies[b].particles);
  }
  message += ")";
  if (reservedParticles > 0) message += " and room for " + withThousands(reservedParticles) + " more (the viewer's snowballs)";
  throw InputError(message + " need more than the " + withThousands(room) + " that fit " + limit.what + "; " +
                   suggestion(scene, budget.bodies, room));
}

std::vector<ParticleSeed> sampleWithinBudget(const Scene& scene, const gl::ContextInfo& gl, double reservedParticles,
                                             const std::function<void(std::size_t body, double fraction)>& progress,
                                             int shares) {
  return sampleWithinBudget(scene, checkParticleBudget(scene, gl, reservedParticles, shares), progress);
}

std::vector<ParticleSeed> sampleWithinBudget(const Scene& scene, const ParticleBudget& budget,
                                             const std::function<void(std::size_t body, double fraction)>& progress) {
  SamplingLimits limits;
  limits.maxParticles = budget.maxParticles;
  limits.reason = budget.limit;
  limits.progress = progress;
  // A little over the estimate, which is good to a few per cent for all but thin meshes.
  constexpr double reserveMargin = 1.05;
  double estimated = 0;
  for (const BodyEstimate& estimate : budget.bodies) estimated += estimate.particles;
  limits.expectedParticles = static_cast<std::size_t>(reserveMargin * estimated);
  return sampleBodies(scene, limits);
}

}  // namespace firn
