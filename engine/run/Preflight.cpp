#include "run/Preflight.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "Error.h"
#include "gpu/GpuFunctions.h"
#include "gpu/Materials.h"
#include "io/Text.h"
#include "scene/ColliderMotion.h"
#include "scene/FieldLattice.h"
#include "scene/SceneObjects.h"
#include "scene/Sampling.h"
#include "sim/FixedPoint.h"
#include "sim/SceneUpload.h"
#include "voxelizer/Voxelizer.h"

namespace firn {
namespace {

std::string seconds(double valueS) { return format("%.3g s", valueS); }

const char* colliderName(ColliderShape shape) {
  switch (shape) {
    case ColliderShape::Plane: return "plane";
    case ColliderShape::Sphere: return "sphere";
    case ColliderShape::Box: return "box";
    case ColliderShape::Mesh: return "mesh";
  }
  return "collider";
}

// Particles that start inside a collider are moved out to its surface as they are uploaded (escapeColliders):
// says how many and how deep, per body and collider; refuses a body that would be moved out whole (it would
// become a sheet on the collider's surface) or particles that cannot be moved out.
void reportBodiesInColliders(const Scene& scene, const std::vector<ParticleSeed>& particles,
                             const ColliderFields& fields, PreflightReport& report) {
  if (scene.colliders.empty() && scene.rigidBodies.empty()) return;
  // The table holds the colliders, then the rigid bodies: snow that starts inside a body is moved out of it alike.
  ColliderTableAt colliders(scene, fields);
  const std::size_t solids = scene.colliders.size() + scene.rigidBodies.size();
  const auto solidName = [&](std::size_t c) {
    return c < scene.colliders.size()
               ? "colliders[" + std::to_string(c) + "] (a " + colliderName(scene.colliders[c].shape) + ")"
               : "rigid_bodies[" + std::to_string(c - scene.colliders.size()) + "]";
  };
  struct Overlap {
    std::size_t particles = 0;
    float deepestM = 0;
  };
  std::vector<std::vector<Overlap>> overlaps(scene.bodies.size(), std::vector<Overlap>(solids));
  std::vector<std::size_t> bodyParticles(scene.bodies.size(), 0), bodyInside(scene.bodies.size(), 0);
  for (const ParticleSeed& particle : particles) {
    if (particle.bodyIndex < 0) continue;
    const auto body = std::size_t(particle.bodyIndex);
    ++bodyParticles[body];
    const ColliderEscape escape = escapeColliders(scene.grid, colliders(particle.releaseTimeS), fields.samples, particle);
    if (escape.collider < 0) continue;
    if (escape.stuck) {
      throw InputError(bodyName(scene, body) + ": a particle at " +
                       format("(%.4g, ", particle.positionM.x) + format("%.4g, ", particle.positionM.y) +
                       format("%.4g)", particle.positionM.z) + " starts inside " +
                       solidName(std::size_t(escape.collider)) + " and cannot be moved out of it: moving it out puts it in "
                       "another collider or beyond the grid's interior; move the body or the colliders");
    }
    ++bodyInside[body];
    Overlap& overlap = overlaps[body][std::size_t(escape.collider)];
    ++overlap.particles;
    overlap.deepestM = std::max(overlap.deepestM, escape.depthM);
  }
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    if (bodyParticles[b] > 0 && bodyInside[b] == bodyParticles[b]) {
      throw InputError(bodyName(scene, b) + ": every one of its " + withThousands(bodyParticles[b]) +
                       " particles starts inside a collider; moved out they would form a sheet on the collider's "
                       "surface. Move the body out of the collider");
    }
    for (std::size_t c = 0; c < solids; ++c) {
      const Overlap& overlap = overlaps[b][c];
      if (overlap.particles == 0) continue;
      report.warnings.push_back("bodies[" + std::to_string(b) + "]: " + withThousands(overlap.particles) + " of its " +
                                withThousands(bodyParticles[b]) + " particles start inside " + solidName(c) + ", up to " +
                                format("%.3g m", overlap.deepestM) +
                                " deep; they are moved out to its surface before the first step");
    }
  }
}

// An emitter's particles join over its window; what falls outside the run's frames never joins.
void noteEmitters(const Scene& scene, const std::vector<ParticleSeed>& particles, std::optional<int> lastFrame,
                  PreflightReport& report) {
  std::vector<std::size_t> bodyParticles(scene.bodies.size(), 0);
  for (const ParticleSeed& particle : particles) {
    if (particle.bodyIndex >= 0) ++bodyParticles[std::size_t(particle.bodyIndex)];
  }
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    if (!body.isEmitter()) continue;
    const std::string name = "bodies[" + std::to_string(b) + "]: ";
    const std::string particlesText = withThousands(bodyParticles[b]) + " particles";
    if (body.durationFrames == 0) {
      report.notes.push_back(name + "emitter: its " + particlesText + " join at once at frame " +
                             std::to_string(body.startFrame) + " (duration_frames 0)");
    } else {
      report.notes.push_back(name + "emitter: its " + particlesText + " join between frames " +
                             std::to_string(body.startFrame) + " and " +
                             std::to_string(body.startFrame + body.durationFrames) + ", " +
                             format("%.4g", double(bodyParticles[b]) / body.durationFrames) + " per frame");
    }
    if (!lastFrame) continue;
    if (body.startFrame > *lastFrame) {
      report.warnings.push_back(name + "the emitter starts at frame " + std::to_string(body.startFrame) +
                                ", after the run's last frame " + std::to_string(*lastFrame) + ": none of its " +
                                particlesText + " will join (they still take room in the particle buffers)");
    } else if (body.startFrame + body.durationFrames > *lastFrame) {
      // Release times are spread evenly over the window (docs/scene-format.md, Emitters): those up to the last
      // frame's time join.
      const double joining =
          std::min(double(bodyParticles[b]),
                   std::floor(double(bodyParticles[b]) * double(*lastFrame - body.startFrame) / body.durationFrames) + 1);
      report.warnings.push_back(name + "the emitter's window ends at frame " +
                                std::to_string(body.startFrame + body.durationFrames) + ", after the run's last frame " +
                                std::to_string(*lastFrame) + ": only about " + withThousands(joining) +
                                " of its " + particlesText + " will join");
    }
  }
}

// A mesh body whose particles are thinner than a spacing over its surface is a sheet, not a solid: an open mesh
// that encloses (next to) nothing, filled only where the winding number's rounding passes ½ near the surface.
void warnAboutSheets(const Scene& scene, const std::vector<ParticleSeed>& particles, PreflightReport& report) {
  std::vector<std::size_t> bodyParticles(scene.bodies.size(), 0);
  for (const ParticleSeed& particle : particles) {
    if (particle.bodyIndex >= 0) ++bodyParticles[std::size_t(particle.bodyIndex)];
  }
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    if (body.shape != BodyShape::Mesh) continue;
    const std::string warning = voxelizer::sheetWarning(voxelizer::measureSurface(*body.mesh), bodyParticles[b],
                                                        particleSpacingM(body, scene.grid));
    if (!warning.empty()) report.warnings.push_back("bodies[" + std::to_string(b) + "]: " + body.path + ": " + warning);
  }
}

// Each body's particles per cell, particles and mass ("bodies[i]: 4 particles per cell, 13,312 particles, 6.5 kg"),
// and for a sphere or a box whose particles hold more than 1% more or less than its shape at the material's density,
// by how much and why: each sample of the lattice (or each Poisson-disk sample's share of it, voxelizer/Samplers.h)
// carries its density times a lattice cell, and the lattice fills the shape with whole cells, so the body's density
// is exact and its volume is the lattice's.
void noteBodyMasses(const Scene& scene, const std::vector<ParticleSeed>& particles, PreflightReport& report) {
  std::vector<std::size_t> counts(scene.bodies.size(), 0);
  std::vector<double> massesKg(scene.bodies.size(), 0.0);
  for (const ParticleSeed& seed : particles) {
    if (seed.bodyIndex < 0 || std::size_t(seed.bodyIndex) >= scene.bodies.size()) continue;
    ++counts[std::size_t(seed.bodyIndex)];
    massesKg[std::size_t(seed.bodyIndex)] += double(seed.massKg);
  }
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const Body& body = scene.bodies[i];
    std::string note = "bodies[" + std::to_string(i) + "]: " + format("%.3g", body.particlesPerCell) +
                       " particles per cell, " + withThousands(double(counts[i])) + " particles, " +
                       format("%.4g kg", massesKg[i]);
    const double shapeKg =
        scene.materials[std::size_t(body.materialIndex)].densityKgPerM3 * body.massScale * shapeVolumeM3(body);
    if (shapeKg > 0 && std::abs(massesKg[i] / shapeKg - 1) > 0.01) {
      note += " (" + format("%+.1f%%", 100 * (massesKg[i] / shapeKg - 1)) + " against its " +
              (body.shape == BodyShape::Sphere ? "sphere" : "box") + "'s " + format("%.4g kg", shapeKg) +
              ": the particles fill it with whole lattice cells of " +
              format("%.3g m", particleSpacingM(body, scene.grid)) + ", each at the material's density)";
    }
    report.notes.push_back(note);
  }
}

// Each distance field's lattice and memory (scene/FieldLattice.h), and each rigid body's mass, volume and inertia.
void noteObjects(const Scene& scene, PreflightReport& report) {
  for (const FieldLattice& field : fieldLattices(scene)) {
    report.notes.push_back(field.object + ": distance field of " + field.path + ", " + format("%.0f", field.samples.x) +
                           " × " + format("%.0f", field.samples.y) + " × " + format("%.0f", field.samples.z) +
                           " samples " + format("%.3g", field.spacingM) + " m apart (" +
                           format("%.3g", field.bytes() / 1e6) + " MB as 32-bit floats)");
  }
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i) {
    const RigidBody& body = scene.rigidBodies[i];
    const glm::dmat3& inertia = body.inertiaKgM2;
    // A mesh's products of inertia carry the integrals' rounding, a few ε of the moments: below 1e-12 of the
    // largest moment they are shown as the 0 they are.
    const double roundingKgM2 = 1e-12 * std::max({inertia[0][0], inertia[1][1], inertia[2][2]});
    const bool diagonal = std::abs(inertia[0][1]) <= roundingKgM2 && std::abs(inertia[0][2]) <= roundingKgM2 &&
                          std::abs(inertia[1][2]) <= roundingKgM2;
    const auto row = [&](int r) {
      return format("%.3g", inertia[0][r]) + ", " + format("%.3g", inertia[1][r]) + ", " + format("%.3g", inertia[2][r]);
    };
    report.notes.push_back("rigid_bodies[" + std::to_string(i) + "]: " + format("%.4g kg", body.massKg) + ", " +
                           format("%.4g m³", body.volumeM3) + ", centre of mass (" + format("%.4g", body.centerOfMassM.x) +
                           ", " + format("%.4g", body.centerOfMassM.y) + ", " + format("%.4g", body.centerOfMassM.z) +
                           ") m, inertia about it " +
                           (diagonal ? "diag(" + format("%.3g", inertia[0][0]) + ", " + format("%.3g", inertia[1][1]) +
                                           ", " + format("%.3g", inertia[2][2]) + ")"
                                     : "[" + row(0) + "; " + row(1) + "; " + row(2) + "]") +
                           " kg m² along its own axes");
  }
}

// A bound on the step from a speed: h / |v|, the CFL condition, for what moves that fast (a particle, a collider
// that the snow it meets follows, a fall under gravity), with what to change to raise it.
struct SpeedBound {
  double dtS = std::numeric_limits<double>::infinity();
  std::string what;  // "the CFL bound h / |v| = … s of …"
  std::string key;   // the scene's key that sets the speed
  std::string fix;   // what to lower, besides time.dt
};

// The speeds a step must keep within a cell: the fastest particle at the start, the fastest collider (snow it
// touches takes its velocity, and a collider crossing more than a cell per step passes through snow), and the
// speed a fall under gravity reaches across the domain's interior, √(2 |g| L) with L the interior's extent along g
// (walls stop anything longer).
std::vector<SpeedBound> speedBounds(const Scene& scene, const std::vector<ParticleSeed>& particles) {
  const double h = scene.grid.cellSizeM;
  std::vector<SpeedBound> bounds;
  double fastestMPerS = 0;
  int fastestBody = -1;
  for (const ParticleSeed& particle : particles) {
    const double speed = glm::length(particle.velocityMPerS);
    if (speed <= fastestMPerS) continue;
    fastestMPerS = speed;
    fastestBody = particle.bodyIndex;
  }
  if (fastestMPerS > 0) {
    const std::string key = "bodies[" + std::to_string(fastestBody) + "].velocity";
    bounds.push_back({h / fastestMPerS,
                      "the CFL bound h / |v| = " + seconds(h / fastestMPerS) + " of the fastest particle (" +
                          format("%.3g m/s", fastestMPerS) + ")",
                      key, "lower the body velocities"});
  }
  int fastestCollider = -1;
  double colliderMPerS = 0;
  for (std::size_t c = 0; c < scene.colliders.size(); ++c) {
    // A turning collider's surface moves fastest at its reach from the pivot: |v| + |ω| r.
    const double speed = fastestColliderSpeedMPerS(scene, scene.colliders[c]);
    if (speed > colliderMPerS) {
      colliderMPerS = speed;
      fastestCollider = int(c);
    }
  }
  if (fastestCollider >= 0) {
    const std::string name = "colliders[" + std::to_string(fastestCollider) + "]";
    const std::string motion =
        scene.colliders[std::size_t(fastestCollider)].keyframes.empty() ? ".velocity" : ".keyframes";
    bounds.push_back({h / colliderMPerS,
                      "the CFL bound h / |v| = " + seconds(h / colliderMPerS) + " of " + name + " (a " +
                          colliderName(scene.colliders[std::size_t(fastestCollider)].shape) + " moving at " +
                          format("%.3g m/s", colliderMPerS) + ": the snow it meets takes its speed)",
                      name + motion, "slow " + name + motion});
  }
  int fastestRigidBody = -1;
  double rigidBodyMPerS = 0;
  for (std::size_t b = 0; b < scene.rigidBodies.size(); ++b) {
    // The explicit coupling meets a body at the nodes and particles it reaches each step: one that crosses more than
    // a cell per step passes through snow, and its contact probes through thin colliders.
    const double speed = rigidBodySurfaceSpeedMPerS(scene.rigidBodies[b]);
    if (speed > rigidBodyMPerS) {
      rigidBodyMPerS = speed;
      fastestRigidBody = int(b);
    }
  }
  if (fastestRigidBody >= 0) {
    const std::string name = "rigid_bodies[" + std::to_string(fastestRigidBody) + "]";
    const RigidBody& body = scene.rigidBodies[std::size_t(fastestRigidBody)];
    const bool spinning = glm::length(body.angularVelocityRadPerS) * rigidBodyReachM(body) > glm::length(body.velocityMPerS);
    const std::string key = name + (spinning ? ".angular_velocity" : ".velocity");
    bounds.push_back({h / rigidBodyMPerS,
                      "the CFL bound h / |v| = " + seconds(h / rigidBodyMPerS) + " of " + name + " (its surface moves at " +
                          format("%.3g m/s", rigidBodyMPerS) + " at the start)",
                      key, "slow " + key});
  }
  const double gravity = glm::length(scene.gravityMPerS2);
  if (gravity > 0) {
    const glm::dvec3 extentM = scene.grid.interiorMaxM() - scene.grid.interiorMinM();
    const double fallM = glm::dot(glm::abs(scene.gravityMPerS2) / gravity, extentM);
    const double fallSpeedMPerS = std::sqrt(2 * gravity * fallM);
    bounds.push_back({h / fallSpeedMPerS,
                      "the CFL bound h / √(2 |g| L) = " + seconds(h / fallSpeedMPerS) + " of gravity (|g| = " +
                          format("%.3g m/s²", gravity) + ": a fall across the domain's interior, L = " +
                          format("%.3g m", fallM) + ", reaches " + format("%.3g m/s", fallSpeedMPerS) + ")",
                      "gravity", "reduce gravity"});
  }
  return bounds;
}

}  // namespace

PreflightReport preflight(const Scene& scene, const std::vector<ParticleSeed>& particles, std::optional<int> lastFrame) {
  return preflight(scene, particles, lastFrame, bakeColliderFields(scene));
}

PreflightReport preflight(const Scene& scene, const std::vector<ParticleSeed>& particles, std::optional<int> lastFrame,
                          const ColliderFields& colliderFields) {
  PreflightReport report;
  const double h = scene.grid.cellSizeM;
  const double dt = scene.time.dtS;

  // The elastic bound dt < h / c of the stiffest material as its body uses it, and the CFL bounds dt < h / |v| of
  // what moves.
  const StiffestBody stiffest = stiffestBody(scene);
  const double elasticDt = h / stiffest.waveSpeedMPerS;
  const std::string stiffestName = "material \"" +
                                   scene.materials.at(std::size_t(scene.bodies.at(std::size_t(stiffest.bodyIndex)).materialIndex)).name +
                                   "\" (wave speed c = " + format("%.4g m/s", stiffest.waveSpeedMPerS) + ")";
  const std::vector<SpeedBound> speeds = speedBounds(scene, particles);
  SpeedBound cfl;
  std::string speedNotes;
  for (const SpeedBound& bound : speeds) {
    if (bound.dtS < cfl.dtS) cfl = bound;
    speedNotes += ", " + bound.what;
  }
  // A semi-implicit step takes the elastic forces implicitly: only the CFL bounds limit it, and the elastic bound
  // is what an explicit step of the scene would need.
  const bool semiImplicit = scene.solver.semiImplicit();
  const SpeedBound elastic{elasticDt, "the elastic bound h / c = " + seconds(elasticDt) + " of " + stiffestName, "", ""};
  const SpeedBound& binding = !semiImplicit && elasticDt <= cfl.dtS ? elastic : cfl;
  report.stableDtS = binding.dtS;
  if (semiImplicit) {
    report.notes.push_back("stable time step: semi-implicit, bounded by the CFL conditions" +
                           (speeds.empty() ? std::string(" (nothing moves at the start)") : ": " + speedNotes.substr(2)) +
                           "; time.dt = " + seconds(dt) + " is " + format("%.3g", dt / elasticDt) +
                           " times the elastic bound h / c = " + seconds(elasticDt) + " of " + stiffestName +
                           " that an explicit step would need");
  } else {
    report.notes.push_back("stable time step: elastic bound h / c = " + seconds(elasticDt) + " for " + stiffestName +
                           speedNotes + "; time.dt = " + seconds(dt));
  }
  const double frameS = 1 / scene.time.frameRateHz;
  if (scene.time.adaptive) {
    report.notes.push_back("adaptive time step: each step at most " + seconds(dt) + " and " +
                           format("%.2g", scene.time.cfl) + " of the bounds");
    // Adaptive steps shrink with the speeds: a speed that would need more steps per frame than a frame may take
    // (TimeSpec::maxStepsPerFrame) cannot be run.
    const double stepsPerFrame = frameS / (scene.time.cfl * cfl.dtS);
    if (stepsPerFrame > TimeSpec::maxStepsPerFrame) {
      throw InputError(sceneFileName(scene) + ": " + cfl.key + ": " + cfl.what +
                       " would make the adaptive steps " + seconds(scene.time.cfl * cfl.dtS) + " long, " +
                       format("%.3g", stepsPerFrame) + " per frame, more than the " +
                       withThousands(TimeSpec::maxStepsPerFrame) + " steps a frame may take; " + cfl.fix);
    }
  } else {
    if (dt > kPreflightFarBeyondFactor * report.stableDtS) {
      const std::string advice = &binding == &elastic && !semiImplicit
                                     ? ", or set solver.integrator to \"semi_implicit\", which the elastic bound does "
                                       "not limit"
                                     : ", or " + binding.fix;
      throw InputError(sceneFileName(scene) + ": time.dt: " + seconds(dt) + " is " + format("%.3g", dt / report.stableDtS) +
                       " times " + binding.what + "; the " + (semiImplicit ? "semi-implicit" : "explicit") +
                       " step cannot be stable beyond it. Set time.dt to at most " + seconds(report.stableDtS) +
                       " (a fifth of it is a safe choice)" + advice);
    }
    if (dt > report.stableDtS) {
      report.warnings.push_back("time.dt = " + seconds(dt) + " exceeds " + binding.what +
                                ": the run is likely to go unstable; set time.dt to at most " +
                                seconds(report.stableDtS) + ", or let \"adaptive\": true choose it");
    }
  }

  // Positions are floats on the GPU (GridSpec::positionResolutionM); the scene loader refuses what is far too coarse.
  const double resolutionM = scene.grid.positionResolutionM();
  if (resolutionM > GridSpec::warnedPositionResolutionCells * h) {
    report.warnings.push_back("grid.origin: positions out at the domain's far corner are 32-bit floats " +
                              format("%.3g m", resolutionM) + " apart, " + format("%.3g", resolutionM / h) +
                              " of a cell (more than 1/1000): a particle slower than " +
                              format("%.3g m/s", resolutionM / (2 * dt)) + " (half of that per step of time.dt) "
                              "stands still. Move the scene nearer to (0, 0, 0) for finer positions");
  }

  // Particles per cell, each body's particles and mass, and the fixed-point resolution that leaves
  // (sim/FixedPoint.h; fixed-point atomics only).
  noteBodyMasses(scene, particles, report);
  if (scene.solver.atomics == Atomics::FixedPoint) {
    const FixedPointScale fixedPoint = fixedPointScaleFor(scene, particles);
    report.notes.push_back("fixed point: " + std::to_string(fixedPoint.fractionBits) + " fraction bits (resolution " +
                           format("%.2g", fixedPoint.resolution()) + " of the heaviest particle's mass); a node sum may reach " +
                           format("%.0f", fixedPoint.maxNodeValue()) + " of them, " +
                           format("%.0f", fixedPoint.maxNodeValue() / std::max(maxParticlesPerCell(scene), 1.0)) +
                           "× a cell's particles at rest");
  }

  noteObjects(scene, report);
  noteEmitters(scene, particles, lastFrame, report);
  warnAboutSheets(scene, particles, report);
  reportBodiesInColliders(scene, particles, colliderFields, report);
  return report;
}

}  // namespace firn
