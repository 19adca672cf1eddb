#pragma once
// Which buffers of the GPU state a scene needs, and how large: what the parts are sized by, and what the budget
// before sampling (run/Budget.h) counts per particle and per block.
#include <cstddef>
#include <string>

#include <glm/vec3.hpp>

#include "gl/Context.h"
#include "scene/Scene.h"

namespace firn {

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
  std::size_t rigidBodies = 0;      // the collider table's last entries, whose state carries over from step to step

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

}  // namespace firn
