#pragma once
// The scene description: what design.md's JSON scene file says, parsed and validated, in SI units.
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace firn {

enum class Kernel { Quadratic, Cubic };          // B-spline order: 27 or 64 nodes per particle
enum class Transfer { PicFlip, Apic };            // seed 002's PIC/FLIP blend, or seed 001's APIC
enum class Atomics { FixedPoint, Float };         // integer atomics on nondimensional sums, or NV float atomics
enum class Boundary { Sticky, Slip, Separate };   // seed 001 ch. 5
enum class BodyShape { Sphere, Box };
enum class ColliderShape { Plane, Sphere, Box };

struct GridSpec {
  glm::dvec3 originM{0.0};
  glm::ivec3 cells{64};  // nodes per axis = cells + 1
  double cellSizeM = 0.02;

  // The outer cells on every side are walls (design.md); particles start in the interior between them.
  static constexpr int wallCells = 2;
  glm::dvec3 interiorMinM() const { return originM + double(wallCells) * cellSizeM; }
  glm::dvec3 interiorMaxM() const { return originM + glm::dvec3(cells - wallCells) * cellSizeM; }
};

struct TimeSpec {
  double dtS = 1e-4;        // largest step; each frame takes ceil(frame duration / dt) equal steps
  double frameRateHz = 30;  // frame N is the state at N / frameRateHz
  int frames = 60;
};

struct SolverSpec {
  Kernel kernel = Kernel::Cubic;
  Transfer transfer = Transfer::PicFlip;
  double flipRatio = 0.95;  // α in v = α v_FLIP + (1 − α) v_PIC
  Atomics atomics = Atomics::FixedPoint;
};

// Stomakhin et al. 2013 snow: fixed corotated elasticity with plastic hardening.
struct SnowMaterial {
  std::string name;
  double youngsModulusPa = 1.4e5;
  double poissonRatio = 0.2;
  double densityKgPerM3 = 400;
  double criticalCompression = 2.5e-2;  // θc
  double criticalStretch = 7.5e-3;      // θs
  double hardening = 10;                // ξ
};

struct Body {
  BodyShape shape = BodyShape::Sphere;
  glm::dvec3 centerM{0.0};  // sphere
  double radiusM = 0;       // sphere
  glm::dvec3 minM{0.0};     // box
  glm::dvec3 maxM{0.0};     // box
  int materialIndex = 0;    // into Scene::materials
  glm::dvec3 velocityMPerS{0.0};
  double particlesPerCell = 8;

  glm::dvec3 boundsMinM() const { return shape == BodyShape::Sphere ? centerM - radiusM : minM; }
  glm::dvec3 boundsMaxM() const { return shape == BodyShape::Sphere ? centerM + radiusM : maxM; }
};

struct Collider {
  ColliderShape shape = ColliderShape::Plane;
  glm::dvec3 pointM{0.0};   // plane: a point on it
  glm::dvec3 normal{0, 1, 0};  // plane: unit normal pointing out of the solid
  glm::dvec3 centerM{0.0};  // sphere
  double radiusM = 0;       // sphere
  glm::dvec3 minM{0.0};     // box
  glm::dvec3 maxM{0.0};     // box
  glm::dvec3 velocityMPerS{0.0};  // the collider translates at this velocity
  double friction = 0;            // Coulomb μ
  Boundary boundary = Boundary::Slip;
};

struct Scene {
  std::string name;
  std::string description;
  std::filesystem::path sourcePath;  // empty for the built-in scene
  GridSpec grid;
  TimeSpec time;
  glm::dvec3 gravityMPerS2{0, -9.81, 0};
  SolverSpec solver;
  std::vector<SnowMaterial> materials;
  std::vector<Body> bodies;
  std::vector<Collider> colliders;

  glm::dvec3 domainMinM() const { return grid.originM; }
  glm::dvec3 domainMaxM() const { return grid.originM + glm::dvec3(grid.cells) * grid.cellSizeM; }
};

// One particle as sampled from a body, before the GPU takes it over.
struct ParticleSeed {
  glm::vec3 positionM;
  glm::vec3 velocityMPerS;
  float massKg;
  int materialIndex;
  int bodyIndex;
};

// Reads and validates a scene file; throws InputError naming the file, the key and the problem.
Scene loadScene(const std::filesystem::path& path);
// Same, from text; `source` names the file in messages.
Scene parseScene(const std::string& jsonText, const std::filesystem::path& source);
// The built-in scene `firn run` uses with no SCENE: a snowball thrown at a wall.
Scene defaultScene();
// The material presets a scene may name: dry, wet, icy, slushy, stomakhin.
const std::vector<SnowMaterial>& snowPresets();

// Jittered lattice sampling of every body (fixed seed, so a scene always gives the same particles).
std::vector<ParticleSeed> sampleBodies(const Scene& scene);

}  // namespace firn
