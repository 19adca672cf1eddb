#pragma once
// The check before a run: the time step against each material's elastic wave bound and the bodies' starting
// speeds, the particles per cell, emitters, mesh bodies that fill as a sheet, bodies that start inside colliders,
// the fixed-point headroom, the distance fields' lattices and the rigid bodies' mass and inertia. Nothing here needs
// a GL context.
#include <optional>
#include <string>
#include <vector>

#include "scene/Scene.h"
#include "sim/SceneUpload.h"

namespace firn {

// A fixed dt beyond the stable bound by more than this factor cannot run: the elastic wave would cross this
// many cells per step. Between 1 and this factor the run is attempted with a warning (the GPU watchdog stops
// it, exit 3, if it does go unstable).
constexpr double kPreflightFarBeyondFactor = 4.0;

struct PreflightReport {
  double stableDtS = 0;              // the smallest bound found
  std::vector<std::string> notes;    // what a user should know: bounds, particles per cell, fixed point
  std::vector<std::string> warnings; // what is likely to go wrong
};

// Throws InputError (exit 2) with the numbers when the scene's dt is far beyond its stable bound, when a body
// starts wholly inside colliders, or particles inside one cannot be moved out (sim/SceneUpload.h). With the run's
// `lastFrame`, also says which emitters would not finish within it.
PreflightReport preflight(const Scene& scene, const std::vector<ParticleSeed>& particles,
                          std::optional<int> lastFrame = std::nullopt);
// The same with the scene's distance fields baked already (sim/SceneUpload.h): a session bakes them once for the
// pre-flight and its simulations.
PreflightReport preflight(const Scene& scene, const std::vector<ParticleSeed>& particles, std::optional<int> lastFrame,
                          const ColliderFields& colliderFields);

}  // namespace firn
