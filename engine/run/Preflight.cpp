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
  }
  return "collider";
}

// Particles that start inside a collider are moved out to its surface as they are uploaded (escapeColliders):
// says how many and how deep, per body and collider; refuses a body that would be moved out whole (it would
// become a sheet on the collider's surface) or particles that cannot be moved out.
void reportBodiesInColliders(const Scene& scene, const std::vector<ParticleSeed>& particles, PreflightReport& report) {
  if (scene.colliders.empty()) return;
  const std::vector<gpu::ColliderParams> colliders = buildColliderTable(scene);
  struct Overlap {
    std::size_t particles = 0;
    float deepestM = 0;
  };
  std::vector<std::vector<Overlap>> overlaps(scene.bodies.size(), std::vector<Overlap>(scene.colliders.size()));
  std::vector<std::size_t> bodyParticles(scene.bodies.size(), 0), bodyInside(scene.bodies.size(), 0);
  for (const ParticleSeed& particle : particles) {
    if (particle.bodyIndex < 0) continue;
    const auto body = std::size_t(particle.bodyIndex);
    ++bodyParticles[body];
    const ColliderEscape escape = escapeColliders(scene.grid, colliders, particle);
    if (escape.collider < 0) continue;
    if (escape.stuck) {
      throw InputError(bodyName(scene, body) + ": a particle at " +
                       format("(%.4g, ", particle.positionM.x) + format("%.4g, ", particle.positionM.y) +
                       format("%.4g)", particle.positionM.z) + " starts inside colliders[" +
                       std::to_string(escape.collider) + "] and cannot be moved out of it: moving it out puts it in "
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
    for (std::size_t c = 0; c < scene.colliders.size(); ++c) {
      const Overlap& overlap = overlaps[b][c];
      if (overlap.particles == 0) continue;
      report.warnings.push_back("bodies[" + std::to_string(b) + "]: " + withThousands(overlap.particles) + " of its " +
                                withThousands(bodyParticles[b]) + " particles start inside colliders[" + std::to_string(c) +
                                "] (a " + colliderName(scene.colliders[c].shape) + "), up to " +
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

}  // namespace

PreflightReport preflight(const Scene& scene, const std::vector<ParticleSeed>& particles, std::optional<int> lastFrame) {
  PreflightReport report;
  const double h = scene.grid.cellSizeM;
  const double dt = scene.time.dtS;

  // The elastic bound dt < h / c of the stiffest material as its body uses it, and the CFL bound dt < h / |v| of
  // the fastest particle at the start.
  const StiffestBody stiffest = stiffestBody(scene);
  const double elasticDt = h / stiffest.waveSpeedMPerS;
  const std::string stiffestName = "material \"" +
                                   scene.materials.at(std::size_t(scene.bodies.at(std::size_t(stiffest.bodyIndex)).materialIndex)).name +
                                   "\" (wave speed c = " + format("%.4g m/s", stiffest.waveSpeedMPerS) + ")";
  double fastestMPerS = 0;
  for (const ParticleSeed& particle : particles) fastestMPerS = std::max(fastestMPerS, double(glm::length(particle.velocityMPerS)));
  const double cflDt = fastestMPerS > 0 ? h / fastestMPerS : std::numeric_limits<double>::infinity();
  // A semi-implicit step takes the elastic forces implicitly: only the particles' CFL bound limits it, and the
  // elastic bound is what an explicit step of the scene would need.
  const bool semiImplicit = scene.solver.semiImplicit();
  report.stableDtS = semiImplicit ? cflDt : std::min(elasticDt, cflDt);
  const std::string cflNote = std::isfinite(cflDt) ? "CFL bound h / |v| = " + seconds(cflDt) + " for the fastest particle (" +
                                                         format("%.3g m/s", fastestMPerS) + ")"
                                                   : std::string();
  if (semiImplicit) {
    report.notes.push_back("stable time step: semi-implicit, bounded by the particles' CFL condition" +
                           (cflNote.empty() ? std::string(" (the particles start at rest)") : ": " + cflNote) +
                           "; time.dt = " + seconds(dt) + " is " + format("%.3g", dt / elasticDt) +
                           " times the elastic bound h / c = " + seconds(elasticDt) + " of " + stiffestName +
                           " that an explicit step would need");
  } else {
    report.notes.push_back("stable time step: elastic bound h / c = " + seconds(elasticDt) + " for " + stiffestName +
                           (cflNote.empty() ? std::string() : ", " + cflNote) + "; time.dt = " + seconds(dt));
  }
  if (scene.time.adaptive) {
    report.notes.push_back("adaptive time step: each step at most " + seconds(dt) + " and " +
                           format("%.2g", scene.time.cfl) + " of the bounds");
  } else {
    const std::string limit = !semiImplicit && elasticDt <= cflDt
                                  ? "the elastic bound h / c = " + seconds(elasticDt) + " of " + stiffestName
                                  : "the CFL bound h / |v| = " + seconds(cflDt) + " of the fastest particle";
    if (dt > kPreflightFarBeyondFactor * report.stableDtS) {
      const std::string advice = semiImplicit || elasticDt > cflDt
                                     ? ""
                                     : ", or set solver.integrator to \"semi_implicit\", which the elastic bound does "
                                       "not limit";
      throw InputError(sceneFileName(scene) + ": time.dt: " + seconds(dt) + " is " + format("%.3g", dt / report.stableDtS) +
                       " times " + limit + "; the " + (semiImplicit ? "semi-implicit" : "explicit") +
                       " step cannot be stable beyond it. Set time.dt to at most " + seconds(report.stableDtS) +
                       " (a fifth of it is a safe choice)" + advice);
    }
    if (dt > report.stableDtS) {
      report.warnings.push_back("time.dt = " + seconds(dt) + " exceeds " + limit +
                                ": the run is likely to go unstable; set time.dt to at most " +
                                seconds(report.stableDtS) + ", or let \"adaptive\": true choose it");
    }
  }

  // Particles per cell, and the fixed-point resolution that leaves (sim/FixedPoint.h; fixed-point atomics only).
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    report.notes.push_back("bodies[" + std::to_string(i) + "]: " + format("%.3g", scene.bodies[i].particlesPerCell) +
                           " particles per cell");
  }
  if (scene.solver.atomics == Atomics::FixedPoint) {
    const FixedPointScale fixedPoint = fixedPointScaleFor(scene, particles);
    report.notes.push_back("fixed point: " + std::to_string(fixedPoint.fractionBits) + " fraction bits (resolution " +
                           format("%.2g", fixedPoint.resolution()) + " of the heaviest particle's mass); a node sum may reach " +
                           format("%.0f", fixedPoint.maxNodeValue()) + " of them, " +
                           format("%.0f", fixedPoint.maxNodeValue() / std::max(maxParticlesPerCell(scene), 1.0)) +
                           "× a cell's particles at rest");
  }

  noteEmitters(scene, particles, lastFrame, report);
  warnAboutSheets(scene, particles, report);
  reportBodiesInColliders(scene, particles, report);
  return report;
}

}  // namespace firn
