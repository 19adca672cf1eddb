#pragma once
// The snow's surface, rebuilt on the GPU from the particles each frame (docs/surfaces.md): the particles'
// volume fraction smoothed by a kernel of a few particle spacings onto a grid finer than the simulation's, then
// marching cubes into an indexed triangle mesh that stays on the GPU for drawing. Passes, each one shader in
// shaders/surface/:
//   measure_bounds   the box of nodes the particles' kernels reach (one 32-byte read sizes the grid)
//   splat_density    the volume fraction (and the colours, the velocities) at the nodes, fixed point
//   classify_cells   each cell's case; each node's vertices and its cell's triangles, counted
//   scan             the counts' prefix sums: where each node writes (one 8-byte read sizes the mesh)
//   emit_mesh        vertices on the crossed edges, triangles naming them
// Everything is summed in integers and written at places the scan fixes, so the mesh is the same bytes from run
// to run.
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "gl/Buffer.h"
#include "gl/BufferBindings.h"
#include "gl/ComputePass.h"
#include "gl/Context.h"
#include "gpu/ParticleView.h"
#include "io/SurfaceMesh.h"
#include "io/Vdb.h"
#include "scene/Scene.h"
#include "surface/PrefixScan.h"

namespace firn::surface {

// What the last reconstruction made.
struct SurfaceStats {
  glm::ivec3 gridNodes{0};      // per axis
  std::size_t gridBytes = 0;    // the per-node buffers' GPU memory
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  bool withColors = false;      // the vertices' albedo came from the particles' colours (else it is 1)
  bool withVelocities = false;  // the vertices' velocity came from the particles' (else it is 0)
};

// Whether a reconstruction also sums the particles' velocities (three more atomics per node a kernel reaches): the
// caches need them, for motion blur; drawing does not.
enum class Velocities { Skip, Sum };

// The kernel radius the scene's particles get (R = surface.smoothing · V^(1/3), V = m / ρ0), in metres and in
// reconstruction cells (h / surface.resolution). Throws InputError naming the scene file and surface.resolution or
// surface.smoothing when a kernel would be narrower than a cell (particles fall between the nodes and the
// surface breaks up) or wider than MAX_KERNEL_RADIUS_CELLS cells.
struct KernelRange {
  double smallestM = 0;
  double largestM = 0;
  double cellM = 0;
};
KernelRange checkKernelRange(const Scene& scene, const std::vector<ParticleSeed>& seeds);

class SurfaceReconstruction {
 public:
  // Checks the scene's surface settings against its particles (checkKernelRange) and builds the programs.
  SurfaceReconstruction(const Scene& scene, const std::vector<ParticleSeed>& seeds, const gl::ContextInfo& gl);
  ~SurfaceReconstruction();
  SurfaceReconstruction(const SurfaceReconstruction&) = delete;
  SurfaceReconstruction& operator=(const SurfaceReconstruction&) = delete;

  // Rebuilds the surface from the particles as they are now. `particleColors`, when given, holds a vec4 per
  // particle (linear albedo) to carry onto the surface; with Velocities::Sum the vertices and readVelocities() carry
  // the particles' velocities, weighted as the field weighs them. Throws InputError naming surface.resolution when
  // the grid the particles now span would not fit the driver's largest storage buffer.
  void reconstruct(const ParticleView& particles, const gl::Buffer* particleColors = nullptr,
                   Velocities velocities = Velocities::Skip);

  const SurfaceStats& stats() const { return stats_; }
  // The mesh on the GPU: SurfaceVertex (surface/SurfaceLayout.h) per vertex, three uint indices per triangle.
  const gl::Buffer& vertexBuffer() const { return vertices_; }
  const gl::Buffer& indexBuffer() const { return indices_; }
  // The box the grid covered (m): everything the mesh holds lies in it.
  glm::dvec3 boundsMinM() const;
  glm::dvec3 boundsMaxM() const;
  double nodeSpacingM() const { return nodeSpacingM_; }

  // The mesh and the field, read back (for the caches).
  SurfaceMesh readMesh() const;
  LatticeSamples readDensity() const;
  // The snow's velocity at the nodes of readDensity()'s box, in its order: Σ V W v / Σ V W (m/s), 0 where no
  // kernel reaches. Empty unless the last reconstruction summed velocities.
  std::vector<glm::vec3> readVelocities() const;

  // Time each pass, as Simulation::setPassTiming does (for benchmarks; it waits for every pass).
  void setPassTiming(bool enabled) { timer_.setEnabled(enabled); }
  const std::vector<gl::PassTimer::PassTime>& passTimes() const { return timer_.times(); }

 private:
  struct Passes;
  void resizeGrid(const glm::ivec3& nodes, bool withNodeSums);
  std::size_t nodeCount() const;
  // The surface's buffers at its binding range of the GPU contract, the particles' at theirs (the colours' stand-in
  // without colours): what each pass binds from. Made again after the buffers grow.
  gl::BufferBindings bindings(const ParticleView& particles, const gl::Buffer* particleColors) const;

  SurfaceSpec spec_;
  glm::dvec3 latticeOriginM_;
  double nodeSpacingM_;
  std::string sceneFile_;  // for messages
  long long maxBufferBytes_;
  int maxWorkGroupsX_;
  std::unique_ptr<Passes> passes_;
  gl::PassTimer timer_;

  // The surface's part of the GPU state (FIRN_SURFACE_BINDINGS_FIRST to _END, and two uniform blocks).

  gl::Buffer uniforms_;
  gl::Buffer header_;
  gl::Buffer cases_;
  gl::Buffer materials_;
  gl::Buffer density_;
  gl::Buffer nodeSums_;  // SurfaceNodeSums per node: colours and velocities
  gl::Buffer cells_;
  gl::Buffer counts_;
  gl::Buffer vertices_;
  gl::Buffer indices_;
  glm::ivec3 firstNode_{0};
  double timeS_ = 0;  // of the particles last reconstructed
  SurfaceStats stats_;
};

}  // namespace firn::surface
