#include "run/Preflight.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "Error.h"
#include "sim/FixedPoint.h"
#include "sim/GpuFunctions.h"
#include "sim/Materials.h"
#include "sim/SceneUpload.h"

namespace firn {
namespace {

std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

std::string seconds(double valueS) { return format("%.3g s", valueS); }

std::string sceneFile(const Scene& scene) {
  return scene.sourcePath.empty() ? kBuiltInSceneName : scene.sourcePath.string();
}

const char* colliderName(ColliderShape shape) {
  switch (shape) {
    case ColliderShape::Plane: return "plane";
    case ColliderShape::Sphere: return "sphere";
    case ColliderShape::Box: return "box";
  }
  return "collider";
}

// Warns about bodies that start inside a collider: they are pushed out violently on the first step.
void warnAboutBodiesInColliders(const Scene& scene, const std::vector<ParticleSeed>& particles, PreflightReport& report) {
  const std::vector<gpu::ColliderParams> colliders = buildColliderTable(scene);
  for (std::size_t c = 0; c < scene.colliders.size(); ++c) {
    std::vector<std::size_t> inside(scene.bodies.size(), 0);
    for (const ParticleSeed& particle : particles) {
      glm::vec3 normal;
      if (particle.bodyIndex >= 0 && gpu::colliderDistance(colliders[c], particle.positionM, 0.0f, normal) < 0) {
        ++inside[std::size_t(particle.bodyIndex)];
      }
    }
    for (std::size_t b = 0; b < inside.size(); ++b) {
      if (inside[b] == 0) continue;
      report.warnings.push_back("bodies[" + std::to_string(b) + "]: " + std::to_string(inside[b]) +
                                " particles start inside colliders[" + std::to_string(c) + "] (a " +
                                colliderName(scene.colliders[c].shape) + "); they will be pushed out on the first step");
    }
  }
}

}  // namespace

PreflightReport preflight(const Scene& scene, const std::vector<ParticleSeed>& particles) {
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
      throw InputError(sceneFile(scene) + ": time.dt: " + seconds(dt) + " is " + format("%.3g", dt / report.stableDtS) +
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

  warnAboutBodiesInColliders(scene, particles, report);
  return report;
}

}  // namespace firn
