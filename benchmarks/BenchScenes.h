#pragma once
// The scenes `firn bench` times: the source thesis's bunny drop (assets/scenes/bunny_thesis.json: 0.05 m cells,
// cubic B-splines, PIC/FLIP 0.95, the thesis's snow) resized and rescaled per configuration, and the thesis
// implementation's own 91,897-particle bunny, from a point cloud the user supplies.
#include <filesystem>
#include <string>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "scene/Scene.h"

namespace firn::bench {

struct BunnySetup {
  int gridCells = 200;                 // per axis, of the thesis scene's cell size
  double scale = 0;                    // of the mesh; the thesis scene's is 0.245 (a 2.4 m bunny)
  double particlesPerCell = 8;
  bool centred = true;                 // in the domain; otherwise in its low corner, one cell inside the walls
                                       // and above the ground plane, so the same particles fit every domain
  std::string atomics = "fixed";
  std::string kernel;      // "cubic", "quadratic"; empty: the thesis scene's (cubic)
  std::string integrator;  // "explicit", "semi_implicit"; empty: the thesis scene's (explicit)
  double dtS = 0;          // 0: the thesis scene's 1e-4 s
  glm::dvec3 velocityMPerS{0.0};
  glm::dvec3 angularVelocityRadPerS{0.0};
};

class BunnyScenes {
 public:
  // Reads `assetsDir`/scenes/bunny_thesis.json and its mesh (meshes/bunny.obj), and samples the bunny once to
  // calibrate particle counts. Throws InputError naming the missing file and --assets.
  explicit BunnyScenes(const std::filesystem::path& assetsDir);

  // Throws InputError (from the scene loader) when the bunny does not fit the domain.
  Scene scene(const BunnySetup& setup) const;
  // The scale at which the bunny holds about `particles` at `particlesPerCell`: the lattice gives each particle
  // h³ / ppc of the volume, so the count goes as ppc × scale³.
  double scaleFor(double particles, double particlesPerCell) const;
  double cellSizeM() const;

 private:
  std::filesystem::path sceneFile_;
  nlohmann::json thesisScene_;
  double thesisScale_ = 0;
  double cellSizeM_ = 0;
  glm::dvec3 gridOriginM_{0.0};
  glm::dvec3 unitMinM_{0.0}, unitMaxM_{0.0};  // the placed mesh's bounds at scale 1, without translation
  double particlesPerCellAtThesisScale_ = 0;   // particles per unit of particles_per_cell at the thesis's scale
  double groundHeightM_ = 0;                   // the highest upward-facing plane collider, else the walls
};

// A snowball of about `particles` particles (8 per cell, APIC, fixed point, `kernel`: "quadratic", "cubic") moving
// at 1 m/s near the low corner of a domain of cells³ cells of 0.02 m, always at the same place: domain.csv's scene,
// and the calibration of `firn bench`'s estimate.
Scene snowballInDomain(int cells, double particles, const std::string& kernel);

// The thesis implementation's grid: 201³ cells of 0.05 m.
constexpr int kThesisGridCells = 201;

// What the implementation of Snow thesis 2015 runs on its bunny: its 91,897-particle bunny cloud scaled by 15.74
// and offset by (5, 0, 5) into 201³ cells of 0.05 m, 6.25e-3 kg per particle, cubic B-splines, PIC/FLIP 0.95,
// E = 6e6 Pa, ν = 0.2, ξ = 30, θc = 1e-2, θs = 1e-3, at `dtS`, with P2G summing by `atomics` (solver.atomics),
// stepped by `integrator` (solver.integrator; semi-implicit with the solver's defaults).
// Throws InputError naming --thesis-cloud if the file is missing or is not a point cloud.
Scene thesisCloudScene(const std::filesystem::path& cloudPath, double dtS, const std::string& atomics,
                       const std::string& kernel = "cubic", const std::string& integrator = "explicit");

}  // namespace firn::bench
