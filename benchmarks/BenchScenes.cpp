#include "BenchScenes.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include "Error.h"

namespace firn::bench {

namespace {

using Json = nlohmann::json;

Json readJson(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) {
    throw InputError(path.string() + ": not found; firn bench needs the project's assets folder (give it with "
                     "--assets DIR)");
  }
  try {
    return Json::parse(in);
  } catch (const Json::exception& error) {
    throw InputError(path.string() + ": " + error.what());
  }
}

}  // namespace

BunnyScenes::BunnyScenes(const std::filesystem::path& assetsDir) : sceneFile_(assetsDir / "scenes" / "bunny_thesis.json") {
  const std::filesystem::path meshFile = assetsDir / "meshes" / "bunny.obj";
  if (!std::filesystem::is_regular_file(meshFile)) {
    throw InputError(meshFile.string() + ": the bunny mesh is missing; give the project's assets folder with --assets DIR");
  }
  thesisScene_ = readJson(sceneFile_);
  thesisScene_.erase("camera");
  const Json& bodies = thesisScene_.at("bodies");
  if (bodies.size() != 1 || bodies[0].value("shape", "") != "mesh") {
    throw InputError(sceneFile_.string() + ": firn bench expects the thesis scene's one body, a mesh");
  }
  // One sampling at the thesis's scale and one particle per cell calibrates the count (about 23,000 particles).
  Json calibration = thesisScene_;
  calibration["bodies"][0]["particles_per_cell"] = 1;
  const Scene scene = parseScene(calibration.dump(), sceneFile_);
  const Body& bunny = scene.bodies.front();
  // The placement as the file gives it (p' = translate + R · (scale · p)), so the mesh's bounds at scale 1.
  const Json& placement = bodies[0];
  thesisScale_ = placement.value("scale", 1.0);
  const std::vector<double> translate = placement.value("translate", std::vector<double>{0, 0, 0});
  const glm::dvec3 translateM(translate.at(0), translate.at(1), translate.at(2));
  cellSizeM_ = scene.grid.cellSizeM;
  unitMinM_ = (bunny.loadedMinM - translateM) / thesisScale_;
  unitMaxM_ = (bunny.loadedMaxM - translateM) / thesisScale_;
  particlesPerCellAtThesisScale_ = double(sampleBodies(scene).size());
  gridOriginM_ = scene.grid.originM;
  groundHeightM_ = scene.grid.interiorMinM().y;
  for (const Collider& collider : scene.colliders) {
    if (collider.shape == ColliderShape::Plane && collider.normal.y > 0) {
      groundHeightM_ = std::max(groundHeightM_, collider.pointM.y);
    }
  }
}

double BunnyScenes::cellSizeM() const { return cellSizeM_; }

double BunnyScenes::scaleFor(double particles, double particlesPerCell) const {
  return thesisScale_ * std::cbrt(particles / (particlesPerCell * particlesPerCellAtThesisScale_));
}

Scene BunnyScenes::scene(const BunnySetup& setup) const {
  const double h = cellSizeM();
  Json scene = thesisScene_;
  scene["grid"]["cells"] = {setup.gridCells, setup.gridCells, setup.gridCells};
  glm::dvec3 translateM;
  if (setup.centred) {
    const glm::dvec3 domainCentreM = gridOriginM_ + 0.5 * double(setup.gridCells) * h;
    translateM = domainCentreM - setup.scale * 0.5 * (unitMinM_ + unitMaxM_);
  } else {
    const double insideWallsM = (GridSpec::wallCells + 1) * h;
    const glm::dvec3 cornerM(gridOriginM_.x + insideWallsM, groundHeightM_ + h, gridOriginM_.z + insideWallsM);
    translateM = cornerM - setup.scale * unitMinM_;
  }
  Json& bunny = scene["bodies"][0];
  bunny["scale"] = setup.scale;
  bunny["translate"] = {translateM.x, translateM.y, translateM.z};
  bunny["particles_per_cell"] = setup.particlesPerCell;
  bunny["velocity"] = {setup.velocityMPerS.x, setup.velocityMPerS.y, setup.velocityMPerS.z};
  bunny["angular_velocity"] = {setup.angularVelocityRadPerS.x, setup.angularVelocityRadPerS.y,
                               setup.angularVelocityRadPerS.z};
  scene["solver"]["atomics"] = setup.atomics;
  if (!setup.kernel.empty()) scene["solver"]["kernel"] = setup.kernel;
  if (!setup.integrator.empty()) scene["solver"]["integrator"] = setup.integrator;
  if (setup.dtS > 0) scene["time"]["dt"] = setup.dtS;
  return parseScene(scene.dump(), sceneFile_);
}

Scene thesisCloudScene(const std::filesystem::path& cloudPath, double dtS, const std::string& atomics,
                       const std::string& kernel, const std::string& integrator) {
  if (!std::filesystem::is_regular_file(cloudPath)) {
    throw InputError("--thesis-cloud: " + cloudPath.string() + ": no such file (a point cloud, one x,y,z per line)");
  }
  constexpr double particleMassKg = 6.25e-3;
  const Json scene = {
      {"name", "thesis bunny"},
      {"grid", {{"cells", {kThesisGridCells, kThesisGridCells, kThesisGridCells}}, {"cell_size", 0.05}}},
      {"time", {{"dt", dtS}, {"frame_rate", 30}, {"frames", 1}}},
      {"solver", {{"kernel", kernel}, {"transfer", "pic_flip"}, {"flip_ratio", 0.95}, {"atomics", atomics},
                  {"integrator", integrator}}},
      {"materials",
       {{"snow",
         {{"model", "snow"}, {"youngs_modulus", 6e6}, {"poisson_ratio", 0.2}, {"density", 400},
          {"critical_compression", 1e-2}, {"critical_stretch", 1e-3}, {"hardening", 30}}}}},
      {"bodies",
       {{{"shape", "points"}, {"path", std::filesystem::absolute(cloudPath).string()}, {"scale", 15.74},
         {"translate", {5, 0, 5}}, {"material", "snow"}, {"particle_mass", particleMassKg}}}}};
  Scene parsed = parseScene(scene.dump(), "--thesis-cloud " + cloudPath.string());
  // The thesis gives a mass per particle, not a density: the density the particles stand for is m / s³, s the
  // cloud's spacing (about 200 kg/m³), which is what the elastic wave speed and the stable step depend on.
  const double spacingM = parsed.bodies.front().pointSpacingM;
  if (spacingM > 0) parsed.materials.front().densityKgPerM3 = particleMassKg / (spacingM * spacingM * spacingM);
  return parsed;
}

Scene snowballInDomain(int cells, double particles, const std::string& kernel) {
  constexpr double kCellSizeM = 0.02, kParticlesPerCell = 8;
  // particles = ppc · (4/3) π r³ / h³
  const double radiusM = kCellSizeM * std::cbrt(particles * 3.0 / (4.0 * 3.14159265358979323846 * kParticlesPerCell));
  const double centreM = 0.1 + radiusM;  // past the walls (two cells) and a little more
  const std::string n = std::to_string(cells), c = std::to_string(centreM);
  return parseScene(R"({
    "name": "snowball in a large domain",
    "grid": { "cells": [)" + n + "," + n + "," + n + R"(], "cell_size": )" + std::to_string(kCellSizeM) + R"( },
    "time": { "dt": 2e-4, "frame_rate": 30, "frames": 1 },
    "solver": { "kernel": ")" + kernel + R"(", "transfer": "apic", "atomics": "fixed" },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "sphere", "center": [)" + c + "," + c + "," + c + R"(], "radius": )" +
                        std::to_string(radiusM) + R"(, "material": "snow", "velocity": [1, 0, 0],
                  "particles_per_cell": )" + std::to_string(kParticlesPerCell) + " } ] }",
                   "domain.csv's snowball");
}

}  // namespace firn::bench
