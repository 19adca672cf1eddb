#pragma once
// The simulation's state on the GPU: the particle buffers (sized for a capacity, live up to a count), the grid
// buffers, the material and collider tables, the active region, the watchdog and the step's uniform block — which
// of them exist depends on what the scene needs — and the copies that save and restore the state.
#include <cstddef>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
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
  GridSpec grid;
  std::size_t particleCapacity = 0;
  bool deformationGradient = true;  // F: every model but water
  bool affine = false;              // APIC's C
  bool impulse = true;              // PIC/FLIP's second grid buffer
  bool blockBins = false;           // P2G without atomics

  static GpuStateLayout forScene(const Scene& scene, std::size_t particleCapacity, bool deformationGradient);
};

class GpuState {
 public:
  // Throws InputError when a buffer would exceed what the driver allows per shader storage block.
  GpuState(const GpuStateLayout& layout, const MaterialTable& materials,
           const std::vector<gpu::ColliderParams>& colliders, const gl::ContextInfo& gl);

  std::size_t particleCapacity() const { return layout_.particleCapacity; }
  glm::ivec3 gridNodes() const { return layout_.grid.cells + 1; }

  // Writes particles [first, first + records.size()) as new: undeformed, unstressed, no affine velocity.
  void writeParticles(std::size_t first, const ParticleRecords& records);
  void setParticleVelocity(std::size_t particle, const glm::vec3& velocityMPerS);
  ParticleSnapshot readParticles(std::size_t count) const;
  glm::vec3 particlePosition(std::size_t particle) const;

  // Binds every buffer to its binding point (gpu_contract.h), or only the particle buffers a renderer reads.
  void bindAll() const;
  void bindParticles() const;
  void writeStepUniforms(const gpu::StepUniforms& uniforms);

  // The active region. seedActiveRegion sets the bounds the next prepare_grid reads as if the last G2P had seen
  // exactly these positions; addParticleCells adds particles that join between steps, which prepare_grid merges
  // in (an upload, no readback); consumeAddedCells forgets them once prepare_grid has.
  void seedActiveRegion(const std::vector<glm::vec3>& positions);
  void addParticleCells(const std::vector<glm::vec3>& positions);
  void consumeAddedCells();
  gpu::ActiveRegionData activeRegion() const;
  const gl::Buffer& activeRegionBuffer() const { return activeRegion_; }
  const gl::Buffer& blockTableBuffer() const { return blocks_; }

  gpu::WatchdogStatus watchdog() const;
  // The largest |v| + c the last G2P saw (m/s): one 4-byte read.
  double fastestSignalMPerS() const;

  // The node sums of the active box after P2G, as stored: ivec4 per node (fixed point or float bits), in the
  // order of the dense grid, from `firstNode` (linear index) for `count` nodes.
  std::vector<glm::ivec4> readGrid(std::size_t firstNode, std::size_t count) const;

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
  void accumulateCells(const std::vector<glm::vec3>& positions, glm::ivec4& cellMin, glm::ivec4& cellMax) const;

  GpuStateLayout layout_;
  // Cells of the particles added since the last prepare_grid (consumeAddedCells resets them).
  glm::ivec4 addedCellMin_{0}, addedCellMax_{0};
  std::vector<gl::Buffer> saved_;  // save()'s copies, in the order of stateBuffers

  gl::Buffer positionMass_;
  gl::Buffer velocityVolume_;
  gl::Buffer elasticDeformation_;  // F (F_E for snow and sand); water-only scenes carry J alone
  gl::Buffer kirchhoffStress_;
  gl::Buffer affine_;  // APIC only
  gl::Buffer plasticState_;
  gl::Buffer gridMomentumMass_;
  gl::Buffer gridImpulse_;  // PIC/FLIP only
  gl::Buffer materials_;
  gl::Buffer colliders_;
  gl::Buffer activeRegion_;
  gl::Buffer watchdog_;
  gl::Buffer stepUniforms_;
  gl::Buffer blocks_;          // BlockTableHeader and the bins (solver.atomics "none")
  gl::Buffer particleSlots_;   // "none": each particle's place in its bin
  gl::Buffer blockParticles_;  // "none": particle indices, bin after bin
  gl::Buffer blockOrder_;      // "none": each colour's non-empty blocks
};

}  // namespace firn
