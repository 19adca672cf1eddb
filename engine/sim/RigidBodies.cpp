#include "sim/RigidBodies.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>

#include <glm/gtc/quaternion.hpp>

#include "sim/FixedPoint.h"

namespace firn {

namespace {

ObjectPose poseOf(const gpu::ColliderParams& entry) {
  ObjectPose pose;
  // The entry's pose is at the time of its pivotTime.w, the end of the last step (or t = 0): now.
  pose.positionM = glm::dvec3(glm::vec3(entry.pivotTime));
  pose.orientation = glm::dquat(entry.rotation.w, entry.rotation.x, entry.rotation.y, entry.rotation.z);
  pose.velocityMPerS = glm::dvec3(glm::vec3(entry.velocity));
  pose.angularVelocityRadPerS = glm::dvec3(glm::vec3(entry.angularVelocity));
  return pose;
}

// The body passes' bodiesCountedElsewhere (common/bodies.glsl): every share moves the bodies alike, and one counts
// the energy that moves.
unsigned countedElsewhere(const DomainShare* share) { return share && !share->countsCommonWork() ? 1u : 0u; }

// Sums 64-bit fixed-point words, (low, high) per component, over the shares, each as one integer: in place.
void sumWordsOverShares(DomainShare& share, const std::vector<std::pair<glm::uvec4*, glm::ivec4*>>& words) {
  std::vector<std::int64_t> values;
  for (const auto& [low, high] : words) {
    for (int c = 0; c < 4; ++c) values.push_back(joinFixed64((*low)[c], (*high)[c]));
  }
  share.sumExactly(values);
  for (std::size_t k = 0; k < words.size(); ++k) {
    for (int c = 0; c < 4; ++c) {
      const std::uint64_t value = std::uint64_t(values[4 * k + std::size_t(c)]);
      (*words[k].first)[c] = std::uint32_t(value);
      (*words[k].second)[c] = std::int32_t(std::uint32_t(value >> 32));
    }
  }
}

}  // namespace

bool mirrorsStressIntoBodies(const Scene& scene) {
  return !scene.rigidBodies.empty() && !scene.solver.semiImplicit() &&
         std::any_of(scene.materials.begin(), scene.materials.end(),
                     [](const Material& material) { return material.model == MaterialModel::Water; });
}

RigidBodies::RigidBodies(const Scene& scene, const gl::ShaderLibrary& library, const gl::ShaderOptions& options,
                         int maxWorkGroupsX)
    : count_(scene.rigidBodies.size()),
      first_(scene.colliders.size()),
      semiImplicit_(scene.solver.semiImplicit()),
      mirrorsStress_(mirrorsStressIntoBodies(scene)),
      maxWorkGroupsX_(maxWorkGroupsX),
      predictBodies_(library, "sim/predict_bodies.comp", options),
      integrateBodies_(library, "sim/integrate_bodies.comp", options) {
  // The semi-implicit step's bodies are unknowns of its solve (ImplicitSolver), and it mirrors no stress into them:
  // the images' push is explicit and as stiff as the snow (docs/algorithm.md, Rigid bodies in the semi-implicit step).
  if (mirrorsStress_) {
    listMirrorBlocks_ = gl::ComputePass(library, "sim/list_mirror_blocks.comp", options);
    listMirrored_ = gl::ComputePass(library, "sim/list_mirrored.comp", options);
    mirrorStress_ = gl::ComputePass(library, "sim/mirror_stress.comp", options);
  }
  // The explicit step's coupled solve, and with two bodies or more their contacts with each other met within it (the
  // semi-implicit step's bodies meet each other after its solve).
  if (count_ > 1) meetBodies_ = gl::ComputePass(library, "sim/meet_bodies.comp", options);
  if (!semiImplicit_) {
    solveCoupling_ = gl::ComputePass(library, "sim/solve_coupling.comp", options);
    coupleNodes_ = BlockGrid::StepPass(library, "sim/couple_nodes.comp", options,
                                       offsetof(gpu::BlockTableHeader, blockDispatch));
  }
}

void RigidBodies::afterTransfer(GpuState& state, DomainShare* share, gl::PassTimer& timer) const {
  if (!mirrorsStress_) return;
  const gl::BufferBindings& buffers = state.bindings();
  const gl::Buffer& blockTable = state.grid().blockTable();
  listMirrorBlocks_.runIndirect(blockTable, offsetof(gpu::BlockTableHeader, blockRunDispatch), buffers, timer);
  listMirrored_.runIndirect(blockTable, offsetof(gpu::BlockTableHeader, mirrorBlocks), buffers, timer);
  const auto scatterImages = [&](GLuint measuringWork) {
    mirrorStress_.set("measuringWork", measuringWork);
    mirrorStress_.runIndirect(blockTable, offsetof(gpu::BlockTableHeader, mirrorDispatch), buffers, timer);
  };
  // The pushes' work on the nodes (mirror_stress.comp): half at their velocity before and half after, where the
  // pushes change it. The second half reads the nodes' whole sums: every share's pushes at the nodes it shares.
  scatterImages(1u);
  scatterImages(0u);
  if (share) share->sumSharedChanges(state.grid());
  scatterImages(1u);
  // The images' push, which the bodies take before the grid update.
  if (share) sumOverShares(state, *share, Sums::Push);
}

void RigidBodies::beforeGridUpdate(GpuState& state, DomainShare* share, gl::PassTimer& timer) const {
  // The bodies take gravity and the images' push before the nodes meet them (eq. 39, 39a), and in the semi-implicit
  // step the last step's impulses of their contacts with each other.
  predictBodies_.set("bodiesCountedElsewhere", countedElsewhere(share));
  predictBodies_.runOver(count_, maxWorkGroupsX_, state.bindings(), timer);
}

void RigidBodies::afterGridUpdate(GpuState& state, BlockGrid::SortFor sortFor, DomainShare* share,
                                  gl::PassTimer& timer) const {
  if (semiImplicit_) return;
  // Each body and the nodes it holds, solved together, the bodies' contacts with each other, then those nodes take
  // the bodies' motion.
  if (share) sumOverShares(state, *share, Sums::Coupling);
  solveCoupling_.runOver(count_, maxWorkGroupsX_, state.bindings(), timer);
  meetBodies(state, share, timer);
  state.grid().run(coupleNodes_, sortFor, state.bindings(), timer);
}

void RigidBodies::afterSolve(GpuState& state, gl::PassTimer& timer) const { meetBodies(state, nullptr, timer); }

void RigidBodies::meetBodies(GpuState& state, DomainShare* share, gl::PassTimer& timer) const {
  if (count_ < 2) return;
  meetBodies_.set("bodiesCountedElsewhere", countedElsewhere(share));
  meetBodies_.runOver(1, maxWorkGroupsX_, state.bindings(), timer);  // one invocation: they meet
}

void RigidBodies::afterGridToParticle(GpuState& state, DomainShare* share, gl::PassTimer& timer) const {
  if (share) sumOverShares(state, *share, Sums::Push);
  integrateBodies_.set("bodiesCountedElsewhere", countedElsewhere(share));
  integrateBodies_.runOver(1, maxWorkGroupsX_, state.bindings(), timer);  // one invocation for all: they meet
}

void RigidBodies::sumOverShares(GpuState& state, DomainShare& share, Sums sums) const {
  state.bindings().completeWrites();  // the passes' atomics, before the host reads them
  // The push's sums are in the bodies' entries of the collider table, the coupled solve's in their records.
  if (sums == Sums::Push) {
    std::vector<gpu::ColliderParams> entries = state.readColliders(first_, count_);
    std::vector<std::pair<glm::uvec4*, glm::ivec4*>> words;
    for (gpu::ColliderParams& body : entries) {
      words.emplace_back(&body.impulseLow, &body.impulseHigh);
      words.emplace_back(&body.angularLow, &body.angularHigh);
    }
    sumWordsOverShares(share, words);
    state.writeColliders(entries, first_);
  } else {
    std::vector<gpu::BodyRecord> records = state.readBodyRecords(0, count_);
    std::vector<std::pair<glm::uvec4*, glm::ivec4*>> words;
    for (gpu::BodyRecord& body : records) {
      for (int w = 0; w < COUPLING_WORDS; ++w) words.emplace_back(&body.blockLow[w], &body.blockHigh[w]);
    }
    sumWordsOverShares(share, words);
    state.writeBodyRecords(records);
  }
}

RigidBodies::Saved RigidBodies::save(const GpuState& state) const {
  return {state.readColliders(first_, count_), state.readBodyRecords(0, count_)};
}

void RigidBodies::restore(GpuState& state, const Saved& saved) const {
  state.writeColliders(saved.entries, first_);
  state.writeBodyRecords(saved.records);
}

std::vector<ObjectPose> RigidBodies::poses(const GpuState& state) const {
  std::vector<ObjectPose> poses;
  for (const gpu::ColliderParams& entry : state.readColliders(first_, count_)) poses.push_back(poseOf(entry));
  return poses;
}

std::vector<std::optional<ObjectPose>> RigidBodies::posesInPlay(const GpuState& state) const {
  std::vector<std::optional<ObjectPose>> inPlay;
  for (const gpu::ColliderParams& entry : state.readColliders(first_, count_)) {
    inPlay.push_back(entry.shapeBoundary.w != 0 ? std::optional<ObjectPose>(poseOf(entry)) : std::nullopt);
  }
  return inPlay;
}

void RigidBodies::write(GpuState& state, std::size_t index, const gpu::ColliderParams& entry,
                        const gpu::BodyRecord& record) const {
  state.writeColliders({entry}, first_ + index);
  state.writeBodyRecords({record}, index);
}

}  // namespace firn
