// Reads a scene file (docs/scene-format.md) into a Scene: the top level and its small sections (grid, time,
// solver, camera) here, materials, bodies, colliders and rigid bodies in the files SceneSections.h names. Every
// problem is an InputError naming the file, the key path and the problem (scene/JsonChecker.h).
#include <cmath>
#include <limits>
#include <string>

#include "Error.h"
#include "io/InputFile.h"
#include "io/Text.h"
#include "scene/Scene.h"
#include "scene/SceneSections.h"

namespace firn {
namespace scenefile {

using json::Interval;
using json::Object;
using json::Value;
using json::describeValue;

namespace {

GridSpec readGrid(const Object& grid) {
  grid.checkKeys({"origin", "cells", "cell_size"}, "\"grid\"");
  GridSpec spec;
  spec.originM = grid.vec3("origin", spec.originM);
  // Fewer than 8 cells leaves at most 4 interior cells between the walls; 1024³ cells is already 10⁹ nodes.
  spec.cells = grid.required("cells").ivec3(8, 1024);
  // A cell over a kilometre is a unit mistake, and bounds the domain's extent far from a double's range.
  spec.cellSizeM = grid.number("cell_size", Interval::openClosed(0, 1000));
  const double resolutionCells = spec.positionResolutionM() / spec.cellSizeM;
  if (resolutionCells > GridSpec::refusedPositionResolutionCells) {
    const glm::dvec3 farCorner = spec.originM + glm::dvec3(spec.cells) * spec.cellSizeM;
    grid.fail("origin", "positions out to the domain's far corner (" + formatApproximately(farCorner.x) + ", " +
                            formatApproximately(farCorner.y) + ", " + formatApproximately(farCorner.z) +
                            ") m are 32-bit floats on the GPU, " + format("%.3g", spec.positionResolutionM()) +
                            " m apart there: " + format("%.3g", resolutionCells) +
                            " of a cell (cell_size " + formatNumber(spec.cellSizeM) +
                            " m), coarser than the 1/100 of a cell a particle's place in its cell needs. Move the "
                            "scene nearer to (0, 0, 0), or use larger cells");
  }
  return spec;
}

TimeSpec readTime(const Object& time) {
  time.checkKeys({"dt", "frame_rate", "frames", "adaptive", "cfl"}, "\"time\"");
  TimeSpec spec;
  spec.frameRateHz = time.number("frame_rate", spec.frameRateHz, Interval::greaterThan(0));
  const double frameDurationS = 1.0 / spec.frameRateHz;
  spec.dtS = time.number("dt", Interval::greaterThan(0));
  if (spec.dtS > frameDurationS) {
    time.fail("dt", "must not exceed one frame, 1 / frame_rate = " + formatApproximately(frameDurationS) + " s (got " +
                        formatNumber(spec.dtS) + ")");
  }
  // The GPU takes dt (and each step's share of a frame) as a 32-bit float: beyond a normal float's range it would
  // be 0 or infinite there.
  if (!(spec.dtS >= double(std::numeric_limits<float>::min()) && spec.dtS <= double(std::numeric_limits<float>::max()))) {
    time.fail("dt", "must be a normal 32-bit float, between " + formatApproximately(std::numeric_limits<float>::min()) +
                        " and " + formatApproximately(std::numeric_limits<float>::max()) + " s, as the GPU takes it (got " +
                        formatNumber(spec.dtS) + ")");
  }
  // Each frame takes ⌈(1 / frame_rate) / dt⌉ steps. A frame rate below 1 Hz is the unusual value of the two (a frame
  // of more than a second), so the message names it; otherwise the step is what is small.
  const double stepsPerFrame = std::ceil(frameDurationS / spec.dtS - 1e-9);
  if (stepsPerFrame > TimeSpec::maxStepsPerFrame) {
    const std::string problem = "a frame (1 / frame_rate = " + formatApproximately(frameDurationS) + " s) would take " +
                                format("%.3g", stepsPerFrame) + " steps of dt = " + formatNumber(spec.dtS) +
                                " s, more than the " + withThousands(TimeSpec::maxStepsPerFrame) +
                                " steps a frame may take (at a millisecond per step, a quarter of an hour per frame); "
                                "raise time.dt or time.frame_rate";
    time.fail(spec.frameRateHz < 1 ? "frame_rate" : "dt", problem);
  }
  constexpr int maxFrames = 1000000;  // about nine hours at 30 Hz: more is a typo, not a shot
  spec.frames = time.integer("frames", spec.frames, 0, maxFrames);
  if (const auto adaptive = time.optional("adaptive")) {
    if (!adaptive->json().is_boolean()) adaptive->fail("expected true or false (got " + describeValue(adaptive->json()) + ")");
    spec.adaptive = adaptive->json().get<bool>();
  }
  if (time.has("cfl") && !spec.adaptive) time.fail("cfl", "applies only with \"adaptive\": true");
  // Beyond 1 the fastest particle, or the elastic wave, crosses more than a cell per step.
  spec.cfl = time.number("cfl", spec.cfl, Interval::openClosed(0, 1));
  return spec;
}

SolverSpec readSolver(const Object& solver) {
  solver.checkKeys({"kernel", "transfer", "flip_ratio", "atomics", "particle_volume", "integrator", "implicit_ratio",
                    "tolerance", "max_iterations"}, "\"solver\"");
  SolverSpec spec;
  spec.kernel = solver.choice<Kernel>("kernel", spec.kernel, {{"quadratic", Kernel::Quadratic}, {"cubic", Kernel::Cubic}});
  spec.transfer =
      solver.choice<Transfer>("transfer", spec.transfer, {{"pic_flip", Transfer::PicFlip}, {"apic", Transfer::Apic}});
  spec.flipRatio = solver.number("flip_ratio", spec.flipRatio, Interval::closed(0, 1));
  spec.atomics =
      solver.choice<Atomics>("atomics", spec.atomics,
                             {{"fixed", Atomics::FixedPoint}, {"float", Atomics::Float}});
  spec.particleVolume = solver.choice<ParticleVolume>(
      "particle_volume", spec.particleVolume,
      {{"grid_density", ParticleVolume::GridDensity}, {"material_density", ParticleVolume::MaterialDensity}});
  spec.integrator = solver.choice<Integrator>(
      "integrator", spec.integrator, {{"explicit", Integrator::Explicit}, {"semi_implicit", Integrator::SemiImplicit}});
  for (const char* key : {"implicit_ratio", "tolerance", "max_iterations"}) {
    if (solver.has(key) && !spec.semiImplicit()) solver.fail(key, "applies only with \"integrator\": \"semi_implicit\"");
  }
  spec.implicitRatio = solver.number("implicit_ratio", spec.implicitRatio, Interval::closed(0, 1));
  // Below 1e-7 the float vectors' rounding is the residual; at 1 nothing is solved.
  spec.tolerance = solver.number("tolerance", spec.tolerance, Interval::closedOpen(1e-7, 1));
  spec.maxIterations = solver.integer("max_iterations", spec.maxIterations, 1, SolverSpec::maxIterationsAllowed);
  return spec;
}

// A semi-implicit step needs the Hessian of every material the bodies use (common/material_hessians.glsl).
void requireHessians(const Object& solver, const std::vector<Material>& materials, const std::vector<Body>& bodies) {
  for (const Body& body : bodies) {
    const Material& material = materials.at(std::size_t(body.materialIndex));
    if (material.hasHessian()) continue;
    solver.fail("integrator", "\"semi_implicit\" needs the Hessian of each material's energy, and material \"" +
                                  material.name + "\" uses the model \"" + modelName(material.model) +
                                  "\", whose Hessian Firn does not implement (snow, fixed_corotated and neo_hookean "
                                  "have one); use \"explicit\" for this scene");
  }
}

CameraSpec readCamera(const Object& camera) {
  camera.checkKeys({"position", "target", "fov_deg"}, "\"camera\"");
  CameraSpec spec;
  spec.positionM = camera.vec3("position");
  spec.targetM = camera.vec3("target");
  if (spec.positionM == spec.targetM) camera.fail("target", "must differ from \"position\" (the camera looks from one to the other)");
  // Beyond 170° the perspective stretches everything to the corners; below 1° it is a telescope.
  spec.fovDeg = camera.number("fov_deg", spec.fovDeg, Interval::closed(1, 170));
  return spec;
}

Scene readScene(const Object& root, const std::filesystem::path& sceneFolder) {
  root.checkKeys(
      {"name", "description", "grid", "time", "gravity", "solver", "materials", "bodies", "colliders",
       "rigid_bodies", "camera", "surface"}, "a scene");
  Scene scene;
  scene.name = root.string("name", scene.name);
  scene.description = root.string("description", scene.description);
  scene.grid = readGrid(Object(root.required("grid")));
  scene.time = readTime(Object(root.required("time")));
  scene.gravityMPerS2 = root.vec3("gravity", scene.gravityMPerS2);
  const auto solver = root.optional("solver");
  if (solver) scene.solver = readSolver(Object(*solver));
  scene.materials = readMaterials(Object(root.required("materials")));

  const Value bodies = root.required("bodies");
  if (!bodies.json().is_array()) bodies.fail("expected an array of bodies (got " + describeValue(bodies.json()) + ")");
  if (bodies.json().empty()) bodies.fail("at least one body is required");
  for (std::size_t i = 0; i < bodies.json().size(); ++i) {
    scene.bodies.push_back(readBody(Object(bodies.element(i)), scene.grid, scene.materials, sceneFolder));
  }
  if (scene.solver.semiImplicit()) requireHessians(Object(*solver), scene.materials, scene.bodies);

  if (const auto colliders = root.optional("colliders")) {
    if (!colliders->json().is_array()) {
      colliders->fail("expected an array of colliders (got " + describeValue(colliders->json()) + ")");
    }
    for (std::size_t i = 0; i < colliders->json().size(); ++i) {
      scene.colliders.push_back(readCollider(Object(colliders->element(i)), scene.grid, sceneFolder));
    }
  }
  if (const auto rigidBodies = root.optional("rigid_bodies")) {
    scene.rigidBodies = readRigidBodies(*rigidBodies, scene.grid, sceneFolder);
  }
  if (const auto camera = root.optional("camera")) scene.camera = readCamera(Object(*camera));
  if (const auto surface = root.optional("surface")) scene.surface = readSurface(Object(*surface));
  return scene;
}

}  // namespace
}  // namespace scenefile

Scene parseScene(const std::string& jsonText, const std::filesystem::path& source) {
  const std::string file = source.string();
  const json::Json root = json::parse(jsonText, file);
  Scene scene = scenefile::readScene(json::Object(json::Value(root, "", file)), source.parent_path());
  scene.sourcePath = source;
  return scene;
}

Scene loadScene(const std::filesystem::path& path) {
  return parseScene(readRegularFile(path, "scene file", kMaxSceneFileBytes), path);
}

}  // namespace firn
