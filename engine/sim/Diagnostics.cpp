#include "sim/Diagnostics.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <tuple>
#include <utility>

#include <glm/geometric.hpp>

#include "Error.h"
#include "gpu/GpuFunctions.h"
#include "gpu/Materials.h"
#include "sim/RigidBodies.h"
#include "io/Text.h"
#include "scene/ColliderMotion.h"
#include "sim/GpuState.h"

namespace firn {

namespace {

const char* channelName(std::uint32_t channel) {
  static constexpr const char* names[] = {"mass",      "momentum x", "momentum y", "momentum z",           "impulse x",
                                          "impulse y", "impulse z",  "tile",       "semi-implicit product"};
  static_assert(std::size(names) == gpu::CHANNEL_COUNT, "a name for every overflow channel");
  return channel < gpu::CHANNEL_COUNT ? names[channel] : "unknown";
}

}  // namespace

void Diagnostics::setMaterials(const Scene& scene) {
  stableDtS_ = scene.grid.cellSizeM / stiffestBody(scene).waveSpeedMPerS;
  materials_ = scene.materials;
}

Diagnostics::Diagnostics(const Scene& scene, const FixedPointScale& fixedPoint)
    : grid_(scene.grid), dtS_(scene.time.dtS),
      stableDtS_(scene.grid.cellSizeM / stiffestBody(scene).waveSpeedMPerS),
      solver_(scene.solver), maxNodeValue_(fixedPoint.maxNodeValue()),
      kernelWidth_(scene.solver.kernel == Kernel::Cubic ? 4 : 3), materials_(scene.materials), bodies_(scene.bodies),
      imagesBoundTheStep_(mirrorsStressIntoBodies(scene)) {
  double fastestMPerS = 0;
  for (std::size_t c = 0; c < scene.colliders.size(); ++c) {
    const double speed = fastestColliderSpeedMPerS(scene, scene.colliders[c]);
    if (speed <= fastestMPerS) continue;
    fastestMPerS = speed;
    fastestCollider_ = "colliders[" + std::to_string(c) + "] (" + format("%.4g", speed) + " m/s)";
  }
}

void Diagnostics::noteParticles(const std::vector<ParticleSeed>& seeds) {
  if (ids_ != nullptr) return;
  for (const ParticleSeed& seed : seeds) {
    particleBody_.push_back(seed.bodyIndex);
    particleMaterial_.push_back(seed.materialIndex);
  }
}

void Diagnostics::keepParticles(std::size_t count) {
  if (ids_ != nullptr) return;
  particleBody_.resize(count);
  particleMaterial_.resize(count);
}

std::string Diagnostics::describeNode(std::int32_t node) const {
  const glm::ivec3 nodes = grid_.cells + 1;
  const glm::ivec3 index(node % nodes.x, (node / nodes.x) % nodes.y, node / (nodes.x * nodes.y));
  const glm::dvec3 position = grid_.originM + glm::dvec3(index) * grid_.cellSizeM;
  return "grid node (" + std::to_string(index.x) + ", " + std::to_string(index.y) + ", " + std::to_string(index.z) +
         ") at (" + format("%.4g", position.x) + ", " + format("%.4g", position.y) + ", " + format("%.4g", position.z) + ") m";
}

std::string Diagnostics::describeParticle(std::int32_t particle, const GpuState& state) const {
  const glm::vec3 position = state.particles().position(static_cast<std::size_t>(particle));
  const std::size_t note = noteOf(static_cast<std::size_t>(particle));
  const int body = particleBody_[note];
  const int material = particleMaterial_[note];
  const std::string origin = body < 0 ? "added while running" : "of bodies[" + std::to_string(body) + "]";
  return "particle " + std::to_string(note) + " " + origin + " (material \"" +
         materials_[static_cast<std::size_t>(material)].name + "\") near (" + format("%.4g", position.x) + ", " +
         format("%.4g", position.y) + ", " + format("%.4g", position.z) + ") m";
}

std::string Diagnostics::rigidBodyHint(const std::string& bound) const {
  if (!imagesBoundTheStep_) return "";
  return "; the rigid bodies take the water's mirrored stress explicitly, and one much lighter than the water it "
         "presses on can rock apart at steps below " + bound + ": make it heavier or reduce time.dt";
}

// Why an explicit step lost particles: snow that compacted past its critical compression hardens by e^{ξ(1 − J_P)}
// without limit, and once its wave outruns the step the step is unstable although the scene's bound, taken at
// J_P = 1 − θc, held. Named is the snow particle whose hardened wave is fastest, in its last finite state (the
// watchdog rejects a non-finite update), which is often not the first particle to fail. Beyond the scene's bound
// that bound is the cause, and what an unstable step leaves in J_P (≤ 0, even) tells nothing.
std::string Diagnostics::instabilityCause(const GpuState& state) const {
  const std::string generic = "Reduce time.dt or youngs_modulus; the elastic wave bound is dt < h / c = " +
                              format("%.4g", stableDtS_) + " s for the stiffest material (scene dt " +
                              format("%.4g", dtS_) + " s)" + rigidBodyHint("that bound") + ".";
  if (solver_.semiImplicit() || dtS_ > stableDtS_) return generic;
  const std::vector<float> plasticJ = state.particles().read(liveParticles()).plasticJ;
  std::size_t stiffest = plasticJ.size();
  double fastestMPerS = 0;
  for (std::size_t p = 0; p < plasticJ.size(); ++p) {
    const Material& material = materials_[static_cast<std::size_t>(particleMaterial_[noteOf(p)])];
    if (material.model != MaterialModel::Snow || !(plasticJ[p] > 0.0f && plasticJ[p] < 1.0f)) continue;
    const int body = particleBody_[noteOf(p)];
    const double speedMPerS =
        hardenedWaveSpeedMPerS(material, plasticJ[p], body >= 0 ? bodies_[std::size_t(body)].lambdaScale : 1.0,
                               body >= 0 ? bodies_[std::size_t(body)].muScale : 1.0);
    if (speedMPerS > fastestMPerS) std::tie(stiffest, fastestMPerS) = std::pair(p, speedMPerS);
  }
  const double boundS = grid_.cellSizeM / fastestMPerS;
  if (stiffest == plasticJ.size() || !(boundS < dtS_)) return generic;
  const Material& material = materials_[static_cast<std::size_t>(particleMaterial_[noteOf(stiffest)])];
  return "Snow had compacted beyond what the step can take: " +
         describeParticle(static_cast<std::int32_t>(stiffest), state) + " reached J_P = " +
         format("%.3g", plasticJ[stiffest]) + ", and hardening e^(xi (1 - J_P)) = " +
         format("%.3g", gpu::snowHardening(double(material.hardening), double(plasticJ[stiffest]))) + " (hardening " +
         format("%.3g", material.hardening) + ") made its wave speed " + format("%.4g", fastestMPerS) +
         " m/s, whose bound h / c = " + format("%.4g", boundS) + " s is below time.dt = " + format("%.4g", dtS_) +
         " s (the scene's bound, " + format("%.4g", stableDtS_) + " s, holds down to J_P = 1 - critical_compression). "
         "Set time.adaptive (its steps follow the hardened wave speed), lower the impact's speed or the hardening, "
         "or reduce time.dt" + rigidBodyHint("the scene's bound") + ".";
}

std::string Diagnostics::energyCarrier(const GpuState& state) const {
  const ParticleSnapshot particles = state.particles().read(liveParticles());
  std::vector<double> kineticJ(materials_.size(), 0.0);
  double totalJ = 0, fastestMPerS = -1;
  std::size_t fastest = 0;
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const glm::dvec3 v(particles.velocityVolume[p]);
    const double energyJ = 0.5 * double(particles.positionMass[p].w) * glm::dot(v, v);
    kineticJ[std::size_t(particleMaterial_[noteOf(p)])] += energyJ;
    totalJ += energyJ;
    if (glm::length(v) > fastestMPerS) std::tie(fastest, fastestMPerS) = std::pair(p, glm::length(v));
  }
  if (!(totalJ > 0)) return "";
  const std::size_t most = std::size_t(std::max_element(kineticJ.begin(), kineticJ.end()) - kineticJ.begin());
  return " The particles of material \"" + materials_[most].name + "\" carry " +
         format("%.3g", 100 * kineticJ[most] / totalJ) + "% of the particles' kinetic energy (" +
         format("%.4g", kineticJ[most]) + " J); the fastest, " + describeParticle(std::int32_t(fastest), state) +
         ", moves at " + format("%.4g", fastestMPerS) + " m/s.";
}

void Diagnostics::check(const gpu::WatchdogStatus& status, const GpuState& state, std::size_t blocksNeeded,
                        std::size_t blockCapacity, const std::optional<SolverFailure>& solverFailure,
                        const std::optional<EnergyEvent>& energy) const {
  if (status.overflowCount == 0 && status.nonFiniteCount == 0 && status.cflCount == 0 && blocksNeeded == 0 &&
      !solverFailure && !energy) {
    return;
  }

  // A semi-implicit step is not bounded by the elastic wave, an explicit one is; rigid bodies, whose images push them
  // explicitly in the explicit step, may need less than that bound there (docs/algorithm.md, Rigid bodies: the
  // coupling's own step bound).
  const std::string elasticBound = "h / c = " + format("%.4g", stableDtS_) + " s for the stiffest material (scene dt " +
                                   format("%.4g", dtS_) + " s)";
  std::string stiffness = solver_.semiImplicit()
                              ? "the semi-implicit step is bounded by the particles' CFL condition dt < h / |v|"
                              : "the elastic wave bound is dt < " + elasticBound;
  stiffness += rigidBodyHint("that bound");
  auto when = [&](std::uint32_t step) {
    return "step " + std::to_string(step) + " (t ≈ " + format("%.4g", double(step) * dtS_) + " s)";
  };

  // Listed in the order they happened: the first is the cause, the others often its consequences.
  std::vector<std::pair<std::uint32_t, std::string>> events;
  if (blocksNeeded > 0) {
    // The watchdog does not time it: it is listed first.
    events.emplace_back(0, "a step needed " + std::to_string(blocksNeeded) + " blocks of the grid (" +
                               std::to_string(gpu::BLOCK_NODES) + " nodes each), more than the " +
                               std::to_string(blockCapacity) +
                               " its pool held, and left the particles of the others out. The pool grows between "
                               "frames, and `firn run` redoes such a frame; this one outgrew it within a frame: "
                               "lower the body velocities or spread them over more frames.");
  }
  if (status.overflowCount > 0 && status.overflowChannel == gpu::CHANNEL_TILE) {
    events.emplace_back(status.overflowStep,
                        when(status.overflowStep) + ": the tile of " + std::to_string(gpu::TILE_BASE_NODES) +
                            " base nodes from " + describeNode(status.overflowNode) + " held more than " +
                            std::to_string(gpu::maxTileParticles(kernelWidth_)) +
                            " particles, more than a transfer takes in one invocation on llvmpipe (which ends a "
                            "shader's loops after 65,535 iterations): the snow compressed far beyond its "
                            "particles_per_cell. Lower particles_per_cell, or stiffen the snow's compression "
                            "(a smaller critical_compression or a larger hardening).");
  } else if (status.overflowCount > 0 && status.overflowChannel == gpu::CHANNEL_SOLVER) {
    events.emplace_back(status.overflowStep,
                        when(status.overflowStep) + ": a contribution to the semi-implicit solve's Hessian product at " +
                            describeNode(status.overflowNode) + " was not finite or exceeded its 64-bit fixed-point "
                            "range (" + std::to_string(status.overflowCount) +
                            " contributions dropped): the elastic forces far exceed what the scene's stiffness and "
                            "step lead to, as when a body is crushed or torn within a step. Reduce time.dt, or raise "
                            "solver.max_iterations if a solve failed before; " + stiffness + ".");
  } else if (status.overflowCount > 0) {
    events.emplace_back(status.overflowStep,
                        when(status.overflowStep) + ": fixed-point overflow of the P2G " +
                            channelName(status.overflowChannel) + " sum at " + describeNode(status.overflowNode) + " (" +
                            std::to_string(status.overflowCount) + " overflowing additions). A node sum may reach ±" +
                            format("%.4g", maxNodeValue_) +
                            " reference masses (or that many times a node moving one cell per step); the particles "
                            "moved or compressed far beyond that. Reduce time.dt, lower the body velocities or "
                            "particles_per_cell, or set solver.atomics to \"float\"; " + stiffness + ".");
  }
  if (status.nonFiniteCount > 0) {
    events.emplace_back(status.nonFiniteStep,
                        when(status.nonFiniteStep) + ": " + describeParticle(status.nonFiniteParticle, state) +
                            " became non-finite (NaN or Inf; " + std::to_string(status.nonFiniteCount) +
                            " particle updates rejected). " + instabilityCause(state));
  }
  if (status.cflCount > 0) {
    events.emplace_back(status.cflStep,
                        when(status.cflStep) + ": " + describeParticle(status.cflParticle, state) + " moved " +
                            format("%.4g", status.cflCellsPerStep) + " cells in one step (CFL limit 1; " +
                            std::to_string(status.cflCount) + " violations). Reduce time.dt below h / |v| or lower "
                            "the body velocities" +
                            (fastestCollider_.empty()
                                 ? std::string()
                                 : ", or slow " + fastestCollider_ + ": the snow a collider meets takes its speed") +
                            "; " + stiffness + ".");
  }
  if (solverFailure) {
    const SolveReport& solve = solverFailure->report;
    const std::string ended = std::isnan(solve.residual)
                                  ? "became non-finite after " + std::to_string(solve.iterations) + " iterations"
                                  : "stopped after " + std::to_string(solve.iterations) +
                                        " iterations at relative residual " + format("%.4g", solve.residual);
    events.emplace_back(std::uint32_t(solverFailure->step),
                        when(std::uint32_t(solverFailure->step)) + ": the semi-implicit solve " + ended +
                            ", more than " + format("%.4g", kSolverFailureFactor) + " times solver.tolerance (" +
                            format("%.4g", solver_.tolerance) + "): its velocities are not the step's. Raise "
                            "solver.max_iterations (now " + std::to_string(solver_.maxIterations) +
                            "), raise solver.tolerance, reduce time.dt, or lower solver.implicit_ratio towards "
                            "0.5.");
  }
  if (energy) {
    // Known at the audit that ends the stretch, it may have begun at its first step: listed there, before what
    // followed from it.
    const EnergyCreation& made = energy->creation;
    const std::uint32_t first = std::uint32_t(energy->firstStep);
    const std::string steps = "steps " + std::to_string(energy->firstStep) + "–" +
                              std::to_string(std::max(energy->endStep, energy->firstStep + 1) - 1) + " (t ≈ " +
                              format("%.4g", double(energy->firstStep) * dtS_) + "–" +
                              format("%.4g", double(energy->endStep) * dtS_) + " s)";
    const std::string what =
        made.beyondLimit > 0
            ? std::to_string(made.beyondLimit) + " particles or collisions held more energy than the scene could give "
              "any stable step (the energy audit's bound, docs/numerics.md)"
            : "the energy grew by " + format("%.4g", made.createdJ) + " J that nothing gave it (the particles' kinetic "
              "energy went from " + format("%.4g", made.kineticBeforeJ) + " to " + format("%.4g", made.kineticJ) +
              " J; float rounding and the step's truncation allow " + format("%.3g", made.toleranceJ) + " J)" +
              (made.couplingJ > 0 ? "; besides that, the rigid bodies' explicit coupling made " +
                                        format("%.4g", made.couplingJ) + " J over the frame, counted apart"
                                  : "");
    const std::string cause =
        solver_.semiImplicit() ? "The semi-implicit step is unstable: " + stiffness + "." : instabilityCause(state);
    events.emplace_back(first, steps + ": " + what + "." + energyCarrier(state) + " " + cause);
  }
  std::stable_sort(events.begin(), events.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::string message = "the simulation became unstable:";
  for (const auto& event : events) message += "\n  - " + event.second;
  throw SimulationError(message);
}

}  // namespace firn
