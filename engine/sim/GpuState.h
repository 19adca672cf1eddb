#pragma once
// The simulation's state on the GPU, in named parts that each own their buffers and a binding range of the GPU
// contract: the particles (ParticleBuffers), the block-sparse grid with the passes that sort the particles into it
// (BlockGrid), the semi-implicit solve's vectors (SolverState, when the scene asks for the solve), and the scene's
// tables, the rigid bodies' records, the watchdog and the step's uniform block, which it owns itself. Which of them
// exist depends on what the scene needs. It gathers the parts' buffers into one BufferBindings that every pass binds
// from, and copies the buffers that carry over from step to step for checkpoints and for redoing a frame.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "gl/Buffer.h"
#include "gl/BufferBindings.h"
#include "gl/Context.h"
#include "gl/ShaderLibrary.h"
#include "gpu/GpuLayout.h"
#include "sim/BlockGrid.h"
#include "sim/GpuStateLayout.h"
#include "sim/ParticleBuffers.h"
#include "sim/SceneUpload.h"
#include "sim/SolverState.h"

namespace firn {

// The bytes of one record of each storage binding's buffer: per particle (the particles' state, the sort's indices
// and the solver's stiffness) or per node of the block pool (the grid's sums, the bins, the solver's vectors); 0
// where a binding holds neither (the tables, the block table and map) or nothing is published.
struct StorageRecordBytes {
  std::vector<std::size_t> perParticle;  // by binding point
  std::vector<std::size_t> perNode;
};

class GpuState {
 public:
  // The block grid's passes are built with the step's shader options. Throws InputError when a buffer would exceed
  // what the driver allows per shader storage block.
  GpuState(const GpuStateLayout& layout, const MaterialTable& materials,
           const std::vector<gpu::ColliderParams>& colliders, const std::vector<gpu::BodyRecord>& bodyRecords,
           const std::vector<float>& colliderFields, const gl::ContextInfo& gl, const gl::ShaderOptions& options);

  std::size_t particleCapacity() const { return layout_.particleCapacity; }

  ParticleBuffers& particles() { return particles_; }
  const ParticleBuffers& particles() const { return particles_; }
  BlockGrid& grid() { return grid_; }
  const BlockGrid& grid() const { return grid_; }
  // The semi-implicit solve's state; null for an explicit scene.
  SolverState* solver() { return solver_ ? &*solver_ : nullptr; }
  const SolverState* solver() const { return solver_ ? &*solver_ : nullptr; }
  // Every part's buffers at its binding points: what each pass binds the blocks it declares from.
  const gl::BufferBindings& bindings() const { return bindings_; }
  StorageRecordBytes storageRecordBytes() const;

  // The block pool: its use (the grid's and the solver's buffers), and a new, larger pool (the grid is rebuilt every
  // step, so nothing is copied). Throws InputError when the pool's buffers of `capacity` blocks exceed what the
  // driver allows.
  BlockUsage blockUsage() const;
  // Room for `capacity` particles (more than now): the particles' buffers grown with their contents kept, a saved
  // state's with them. Throws InputError when a particle buffer would exceed what the driver allows.
  void growParticles(std::size_t capacity, const gl::ContextInfo& gl);
  void resizeBlockPool(std::size_t capacity, const gl::ContextInfo& gl);

  void writeStepUniforms(const gpu::StepUniforms& uniforms);
  // Entries of the collider table from `first` on: the colliders' poses for the step to come (buildColliderTable), a
  // launched body's entry (its record: writeBodyRecords). The table keeps its size.
  void writeColliders(const std::vector<gpu::ColliderParams>& colliders, std::size_t first = 0);
  std::vector<gpu::ColliderParams> readColliders(std::size_t first, std::size_t count) const;
  // The material table's entries, as many as it holds (Simulation::setMaterials).
  void writeMaterials(const MaterialTable& materials);
  gpu::WatchdogStatus watchdog() const;
  // The energy audit's ledger, after the status in the watchdog's buffer (sim/EnergyAudit.h), and the collider
  // table's entries' loads after it (gpu::ObjectLoad).
  gpu::EnergyLedger energyLedger() const;
  std::vector<gpu::ObjectLoad> objectLoads() const;
  // Both as bytes, and back (none: emptied, for the next frame).
  std::string energyRecords() const;
  void writeEnergyRecords(const std::string& bytes = "");
  // The rigid bodies' records (gpu::BodyRecord, after the contact slots) from `first` on: a launched body's, and
  // those put back after a pass that was only timed (RigidBodies::restore).
  void writeBodyRecords(const std::vector<gpu::BodyRecord>& records, std::size_t first = 0);
  std::vector<gpu::BodyRecord> readBodyRecords(std::size_t first, std::size_t count) const;
  // The largest |v| + c the last G2P saw (m/s): one 4-byte read.
  double fastestSignalMPerS() const;

  // The buffers whose contents carry over from one step to the next (the grid is rebuilt every step): what a
  // checkpoint holds and what save() copies.
  std::vector<std::string> stateBytes() const;
  // Throws InputError naming `source` when the bytes do not fit this state's buffers, the particles' sized for
  // `particleCapacity` particles (0: this state's capacity; a share of a domain reads one process's checkpoint).
  void checkStateBytes(const std::vector<std::string>& bytes, const std::string& source,
                       std::size_t particleCapacity = 0) const;
  void loadStateBytes(const std::vector<std::string>& bytes);
  void save();
  void restore();  // throws std::logic_error if nothing was saved

 private:
  template <class Self>
  static auto stateBuffersOf(Self& self);
  std::vector<const gl::Buffer*> stateBuffers() const;
  std::vector<gl::Buffer*> stateBuffers();
  // Checks the pool's sizes against the driver, then has the grid and the solver allocate it.
  void allocateBlockPool(const gl::ContextInfo& gl);
  void publish();

  GpuStateLayout layout_;
  ParticleBuffers particles_;
  BlockGrid grid_;
  std::optional<SolverState> solver_;
  gl::Buffer materials_;
  gl::Buffer colliders_;
  gl::BufferTexture colliderFields_;  // the mesh colliders' and bodies' distance fields, the bodies' probes
  gl::Buffer watchdog_;
  // The rigid bodies' contacts of the last step (gpu::BodyContact per slot), then a gpu::BodyRecord per body: its
  // dynamics, the explicit step's coupled inverse, the semi-implicit solve's unknowns (common/body_blocks.glsl).
  gl::Buffer bodies_;
  static std::size_t bodyRecordsOffset();  // the records' first byte: after the contact slots
  std::size_t objectCount_ = 0;  // the collider table's entries, each with a load in the watchdog's buffer
  std::size_t energyBytes() const;
  gl::Buffer stepUniforms_;
  gl::BufferBindings bindings_;
  std::vector<gl::Buffer> saved_;  // save()'s copies, in the order of stateBuffers
};

}  // namespace firn
