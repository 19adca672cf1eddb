#pragma once
// The rigid bodies' part of a simulation (docs/algorithm.md, Rigid bodies): their passes, which the step runs at
// named points, and their state on the GPU — each body an entry of the collider table after the scene's colliders
// (its shape, pose and velocities, which the snow's passes meet, and the 64-bit sums of the snow's push they add to)
// and a record in the bodies' own buffer (its dynamics and solves: gpu::BodyRecord) — read back as poses, written
// when a parked body is launched, saved and put back. Over several processes (a DomainShare) each body's sums are
// summed over the shares before a pass reads them, so that every share moves every body alike (docs/distributed.md).
//
// The step's points, in order (StepPipeline::step):
//   afterTransfer        explicit step with a fluid: its stress mirrored into the bodies (eq. 38), once the nodes
//                        hold their whole sums
//   beforeGridUpdate     each body takes gravity and the images' push (predict_bodies.comp), and in the semi-implicit
//                        step the warm start of its contacts with the other bodies
//   afterGridUpdate      explicit step: each body and the nodes it holds solved together (eq. 39), and the bodies'
//                        contacts with each other met with that solve's inertia; the semi-implicit step solves them
//                        with the snow (ImplicitSolver, eq. 39a)
//   afterSolve           semi-implicit step with two bodies or more: the contacts of a body that held nodes in the
//                        solve with one that held none, warm started, each body by its own inertia (meet_bodies.comp)
//   afterGridToParticle  the snow's push, the contacts, the motion (integrate_bodies.comp)
#include <cstddef>
#include <optional>
#include <vector>

#include "gl/ComputePass.h"
#include "gl/PassTimer.h"
#include "gl/ShaderLibrary.h"
#include "gpu/GpuLayout.h"
#include "scene/Scene.h"
#include "scene/SceneObjects.h"
#include "sim/BlockGrid.h"
#include "sim/DomainShare.h"
#include "sim/GpuState.h"

namespace firn {

// Whether a step of `scene` mirrors stress into its rigid bodies (docs/algorithm.md, eq. 38): the explicit step, with
// bodies and a fluid (water) among the materials — only a fluid's stress is mirrored (common/mirror.glsl,
// stressMirrored), and the semi-implicit step solves the bodies with the snow instead (eq. 39a).
bool mirrorsStressIntoBodies(const Scene& scene);

class RigidBodies {
 public:
  // The passes of `scene`'s bodies (it has some), built with the step's `options`.
  RigidBodies(const Scene& scene, const gl::ShaderLibrary& library, const gl::ShaderOptions& options,
              int maxWorkGroupsX);

  void afterTransfer(GpuState& state, DomainShare* share, gl::PassTimer& timer) const;
  void beforeGridUpdate(GpuState& state, DomainShare* share, gl::PassTimer& timer) const;
  void afterGridUpdate(GpuState& state, BlockGrid::SortFor sortFor, DomainShare* share, gl::PassTimer& timer) const;
  void afterSolve(GpuState& state, gl::PassTimer& timer) const;
  void afterGridToParticle(GpuState& state, DomainShare* share, gl::PassTimer& timer) const;

  // The bodies' entries of the collider table and their records as they are, and put back (a pass run outside a
  // step, to time it, must leave the bodies as they were: StepPipeline::chooseTransferShape).
  struct Saved {
    std::vector<gpu::ColliderParams> entries;
    std::vector<gpu::BodyRecord> records;
  };
  Saved save(const GpuState& state) const;
  void restore(GpuState& state, const Saved& saved) const;
  // Each body's frame now, in the scene's order (SceneObjects.h), with its velocity and angular velocity; and the
  // same with none for a parked body (outside the simulation until launched).
  std::vector<ObjectPose> poses(const GpuState& state) const;
  std::vector<std::optional<ObjectPose>> posesInPlay(const GpuState& state) const;
  // Writes body `index`'s entry and record (a launch: sim/SceneUpload.h, rigidBodyEntry and rigidBodyRecord).
  void write(GpuState& state, std::size_t index, const gpu::ColliderParams& entry,
             const gpu::BodyRecord& record) const;

 private:
  // The sums a point of the step reads: the snow's push (impulse and its moment) or the coupled solve's.
  enum class Sums { Push, Coupling };
  // Over several shares: the bodies' `sums` that this share's passes added since they were last cleared, summed
  // over all shares, in integers (the sums one process makes). Every share calls it at the same point.
  void sumOverShares(GpuState& state, DomainShare& share, Sums sums) const;
  // The bodies' contacts with each other, with two bodies or more (meet_bodies.comp).
  void meetBodies(GpuState& state, DomainShare* share, gl::PassTimer& timer) const;

  std::size_t count_ = 0;
  std::size_t first_ = 0;  // the bodies' first entry in the collider table, after the scene's colliders
  bool semiImplicit_ = false;
  bool mirrorsStress_ = false;  // mirrorsStressIntoBodies
  int maxWorkGroupsX_ = 65535;
  gl::ComputePass predictBodies_;
  gl::ComputePass integrateBodies_;
  // The explicit step's images of a fluid's stress (eq. 38), where the scene mirrors it, and coupled solve of the
  // bodies and the nodes they hold (docs/algorithm.md, eq. 39), whose inverse inertias K⁻¹ (gpu::BodyRecord.inverse in
  // the state's body records, of which the explicit step uses this one) the bodies then meet each other with.
  gl::ComputePass listMirrorBlocks_;
  gl::ComputePass listMirrored_;
  gl::ComputePass mirrorStress_;
  gl::ComputePass solveCoupling_;
  gl::ComputePass meetBodies_;  // with two bodies or more
  BlockGrid::StepPass coupleNodes_;
};

}  // namespace firn
